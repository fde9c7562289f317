"""Elastic-foundation contact under torque control (Section 2.2 of the paper; decisions in
docs/model.md).

Each cell is an independent elastic bar (Winkler foundation): a plateau cell whose undeformed
height ``h`` stands above the rigid, flat disc surface at ``z`` carries ``p = K (h - z)`` with
``K = E / L``. Resin carries no load. Under torque control the disc position ``z`` is the one at
which the friction force ``F(z) = sum mu(p_i) p_i A_i`` equals the demanded friction force.
``mu(p) p`` is not monotone, so several ``z`` can do it: the solver returns the first one met as
the approach grows from zero (the smallest normal load), which depends on the surface alone.

Algorithm
---------
Sort the plateau heights (descending). Between consecutive breakpoints (a cell entering
contact at ``z = h_k``, a cell reaching the COF floor at ``z = h_k - u_f``, with
``u_f = (mu_0 - mu_min) / (c K)``)
``F`` is a quadratic in the approach ``w``: ``F = F_0 + D w - Q w^2``. Walk the breakpoints
from the top, updating ``F``, ``D`` and ``Q``, and solve the quadratic in each interval; the
first root is exact to round-off. Cost: O(number of cells in contact) once heights are sorted.

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.2.
E. Winkler, Die Lehre von der Elasticität und Festigkeit, Prag, 1867 (the elastic foundation).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import ArrayLike

from brakeca import _cachedir
from brakeca._jit import njit_noalloc

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

__all__ = [
    "ContactError",
    "contact_pressure",
    "first_root",
    "first_root_binned",
    "friction_force",
    "solve_disc_position",
]

SOLVE_OK = 0
SOLVE_NO_PLATEAU = 1
SOLVE_NO_ROOT = 2


class ContactError(RuntimeError):
    """The demanded torque cannot be reached (no plateau can touch the disc, or the foundation
    would have to be compressed beyond its length)."""


@njit(cache=True)
def first_root(height, area, n_plateau, stiffness, mu_0, slope, mu_min, target):
    """First disc position z at which the friction force reaches ``target``.

    Parameters
    ----------
    height : float64 array
        Plateau cell heights sorted highest first [m] (the first ``n_plateau`` are used).
    area : float64 array
        Their areas, in the same order [m^2].
    n_plateau : int
        Number of plateau cells.
    stiffness : float
        Foundation stiffness K [Pa/m].
    mu_0, slope, mu_min : float
        Friction law: mu_0 [-], c [1/Pa], mu_min [-].
    target : float
        Demanded friction force [N], > 0.

    Returns
    -------
    z : float
        Disc surface position [m].
    n_in : int
        Number of leading cells with ``h > z`` (the cells in contact).
    code : int
        0 ok, 1 no plateau cell, 2 no root: with ``mu_min = 0`` the friction force has a
        maximum (``mu(p) p`` peaks at ``mu_0^2 / 4c``), which ``target`` may exceed.

    Notes
    -----
    The friction force of the disc at ``z`` is
    ``F(z) = sum_{k: h_k > z} A_k mu(p_k) p_k``, with ``p_k = K (h_k - z)`` and
    ``mu(p) = max(mu_min, mu_0 - c p)``. ``F`` is 0 at ``z = h_0`` and continuous; the result
    is its first root, ``F(z) = target`` with ``z`` largest: the first met as the approach
    ``h_0 - z`` grows from zero. That ``mu(p) p`` is not monotone lets ``F`` have several
    roots; taking the first is a decision (docs/model.md section 4, "Torque control, first
    root", and the table of decisions fixed in code), so the root depends on the surface
    alone, not on the last step's.

    The breakpoints of ``F`` are ``z = h_k`` (cell ``k`` enters contact) and
    ``z = h_k - u_f``, ``u_f = (mu_0 - mu_min) / (c K)`` (it reaches the COF floor). Between
    two of them, with ``w = z_hi - z``, ``F = F_0 + D w - Q w^2``: a cell entering adds
    ``A K mu_0`` to ``D`` and ``A c K^2`` to ``Q``; one reaching the floor adds
    ``A K (mu_0 - mu_min)`` to ``D`` and takes ``A c K^2`` from ``Q``; moving down an interval
    of length ``w`` takes ``2 Q w`` from ``D``. In the interval that reaches the target,
    ``w = 2 R / (D + sqrt(D^2 - 4 Q R))`` with ``R = target - F_0`` (the smaller root, free of
    cancellation). Exact to round-off, with no iteration (docs/model.md section 4, "Solver").
    This is :func:`first_root_binned` with ``A_k = area[k]``. The bar-length check (no bar
    compressed beyond ``L``) is the kernels' (``_kernels.phase_contact``, ``_lazy``).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260; E. Winkler, Die Lehre von der
    Elasticität und Festigkeit, Prag, 1867 (the elastic foundation).
    """
    return first_root_binned(
        height,
        np.arange(n_plateau),
        area,
        n_plateau,
        stiffness,
        mu_0,
        slope,
        mu_min,
        target,
    )


@njit_noalloc
def first_root_binned(
    height, cell_bin, bin_area, n_plateau, stiffness, mu_0, slope, mu_min, target
):
    """:func:`first_root` with the area of cell ``k`` read as ``bin_area[cell_bin[k]]`` [m^2].

    The kernel's packed plateau records carry a stream bin, not an area (every cell of a row
    has the same area); :func:`first_root` is this function with ``cell_bin = arange(n)``.

    Parameters
    ----------
    height : float64 array
        Plateau cell heights sorted highest first [m] (the first ``n_plateau`` are used).
    cell_bin : int array
        Stream bin (row and subdomain) of each cell, in the same order [-].
    bin_area : float64 array
        Cell area of each stream bin [m^2].
    n_plateau : int
        Number of plateau cells.
    stiffness : float
        Foundation stiffness K [Pa/m].
    mu_0, slope, mu_min : float
        Friction law: mu_0 [-], c [1/Pa], mu_min [-].
    target : float
        Demanded friction force [N], > 0.

    Returns
    -------
    z : float
        Disc surface position [m].
    n_in : int
        Number of leading cells with ``h > z`` (the cells in contact).
    code : int
        0 ok, 1 no plateau cell, 2 no root (as :func:`first_root`).

    Notes
    -----
    The first root (largest ``z``) of ``F(z) = target``, with
    ``F(z) = sum_{k: h_k > z} A_k mu(K (h_k - z)) K (h_k - z)``,
    ``A_k = bin_area[cell_bin[k]]`` and ``mu(p) = max(mu_min, mu_0 - c p)``: the equation and
    the walk over its breakpoints of :func:`first_root`, which calls this function. The first
    root is a decision (docs/model.md section 4, "Torque control, first root").

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260; E. Winkler, Die Lehre von der
    Elasticität und Festigkeit, Prag, 1867 (the elastic foundation).
    """
    if n_plateau == 0:
        return 0.0, 0, SOLVE_NO_PLATEAU
    k2 = slope * stiffness * stiffness
    if slope > 0.0:
        u_floor = (mu_0 - mu_min) / (slope * stiffness)
    else:
        u_floor = math.inf
    z_hi = height[0]
    f = 0.0  # friction force at z_hi [N]
    d = 0.0  # dF/dw at z_hi [N/m]
    q = 0.0  # -0.5 d2F/dw2 [N/m^2]
    a = 0  # cells entered (in contact)
    b = 0  # cells entered on the floor branch
    h_a = height[0]  # height of the next cell to enter (-inf when none is left)
    zf = -math.inf  # z at which the next cell reaches the floor (-inf when none can)
    while True:
        # apply every event at z_hi: cells entering contact, then cells reaching the floor
        while h_a >= z_hi:
            cell = bin_area[cell_bin[a]]
            d += cell * mu_0 * stiffness
            q += cell * k2
            a += 1
            if a < n_plateau:
                h_a = height[a]
            else:
                h_a = -math.inf
                break
        if b < a:
            zf = height[b] - u_floor
            while zf >= z_hi:
                cell = bin_area[cell_bin[b]]
                # the slope jumps from A K (2 mu_min - mu_0) to A K mu_min
                d += cell * stiffness * (mu_0 - mu_min)
                q -= cell * k2
                b += 1
                if b < a:
                    zf = height[b] - u_floor
                else:
                    zf = -math.inf
                    break
        else:
            zf = -math.inf
        if q < 0.0:
            q = 0.0
        z_next = h_a if h_a > zf else zf
        w_max = z_hi - z_next
        rest = target - f
        if mu_min == 0.0 and slope > 0.0 and not (w_max < math.inf):
            # every cell is past its floor, where mu(p) p = 0: F stays at f (0 but for
            # round-off, which could leave d a little above 0 and put a root far away), below
            # the target; with mu_min = 0 the friction force has a maximum the demand exceeds.
            # (With slope = 0 no cell has a floor, mu = mu_0: F rises without bound.)
            return z_hi, a, SOLVE_NO_ROOT
        # F(w) = f + d w - q w^2 <= f + d w_max on the interval: when that bound stays below the
        # target (the usual case: intervals are short) no root lies here and the quadratic is
        # not solved. The root found is the same, bit for bit.
        if d > 0.0 and d * w_max >= rest:
            w = math.inf
            if q > 0.0:
                disc = d * d - 4.0 * q * rest
                if disc >= 0.0:
                    w = 2.0 * rest / (d + math.sqrt(disc))
            else:
                w = rest / d
            if w <= w_max:
                return z_hi - w, a, SOLVE_OK
        if not (w_max < math.inf):
            return z_hi, a, SOLVE_NO_ROOT  # unreachable with mu_min > 0; kept for safety
        f += d * w_max - q * w_max * w_max
        d -= 2.0 * q * w_max
        z_hi = z_next


def contact_pressure(height: ArrayLike, disc_position: float, stiffness: float) -> np.ndarray:
    """Winkler contact pressure ``p = K max(h - z, 0)`` [Pa] of cells of undeformed heights
    ``height`` [m] against the disc surface at ``disc_position`` z [m], on a foundation of
    stiffness ``stiffness`` K = E / L [Pa/m].

    Parameters
    ----------
    height : array_like
        Undeformed cell heights h [m].
    disc_position : float
        Disc surface position z [m].
    stiffness : float
        Foundation stiffness K [Pa/m].

    Returns
    -------
    float64 array
        Contact pressure of each cell [Pa], of the shape of ``height``; 0 where ``h <= z``.

    Notes
    -----
    ``p = K max(h - z, 0)``, ``K = E / L``: each cell is an independent elastic bar of a
    Winkler foundation (the paper's elastic bars), compressed by its interference ``h - z``.
    ``E`` and ``L`` are ours, not the paper's (``contact.elastic_modulus`` 1 GPa,
    ``contact.bar_length`` 10 mm, so ``K`` = 1e11 Pa/m; docs/model.md section 4). This
    function takes any heights; in the model only plateau cells carry load, resin above the
    disc being cut instead (docs/model.md section 4 and section 6).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260; E. Winkler, Die Lehre von der
    Elasticität und Festigkeit, Prag, 1867 (the elastic foundation).

    Examples
    --------
    >>> from brakeca.contact import contact_pressure
    >>> contact_pressure([12e-6, 10e-6, 9e-6], 10e-6, 1e11)  # K = E / L = 1 GPa / 10 mm [Pa]
    array([200000.,      0.,      0.])
    """
    return stiffness * np.maximum(np.asarray(height, dtype=float) - disc_position, 0.0)


def friction_force(
    height: ArrayLike,
    area: ArrayLike,
    disc_position: float,
    stiffness: float,
    mu_0: float,
    slope: float,
    mu_min: float,
) -> float:
    """Friction force ``sum mu(p) p A`` [N] of plateau cells of heights ``height`` [m] and
    areas ``area`` [m^2], the disc at ``disc_position`` [m], the foundation's ``stiffness``
    [Pa/m], and the friction law ``mu_0`` [-], ``slope`` c [1/Pa], ``mu_min`` [-].

    Parameters
    ----------
    height : array_like
        Plateau cell heights [m] (any order).
    area : array_like
        Their areas [m^2] (broadcast against ``height``).
    disc_position : float
        Disc surface position z [m].
    stiffness : float
        Foundation stiffness K [Pa/m].
    mu_0, slope, mu_min : float
        Friction law mu(p) = max(mu_min, mu_0 - c p): [-], [1/Pa], [-].

    Returns
    -------
    float
        Friction force [N].

    Notes
    -----
    ``F(z) = sum_i mu(p_i) p_i A_i``, with ``p_i = K max(h_i - z, 0)``
    (:func:`contact_pressure`) and ``mu(p) = max(mu_min, mu_0 - c p)``
    (:func:`brakeca.friction.coefficient_of_friction`), evaluated directly on every cell. Under
    torque control ``z`` is set so that ``F(z)`` equals the band's demanded friction force
    (:func:`solve_disc_position`; docs/model.md section 4); :func:`first_root` reaches the
    same ``F`` by its walk over the breakpoints.

    References
    ----------
    Wahlström (2016), Section 2.2 and Figure 4, doi:10.1155/2016/8181260.

    Examples
    --------
    >>> import numpy as np
    >>> from brakeca.contact import friction_force
    >>> height = np.array([12e-6, 11e-6, 9e-6])  # the third cell is off the disc
    >>> # (0.6 - 3e-8 * 0.2 MPa) * 0.2 MPa * 1 mm² + (0.6 - 3e-8 * 0.1 MPa) * 0.1 MPa * 1 mm²
    >>> round(friction_force(height, 1e-6, 10e-6, 1e11, 0.6, 3e-8, 0.15), 9)  # [N]
    0.1785
    """
    p = contact_pressure(height, disc_position, stiffness)
    mu = np.maximum(mu_min, mu_0 - slope * p)
    return float(np.sum(mu * p * np.asarray(area, dtype=float)))


def solve_disc_position(
    height: ArrayLike,
    area: ArrayLike,
    *,
    stiffness: float,
    mu_0: float,
    slope: float,
    mu_min: float,
    target: float,
) -> float:
    """Torque-controlled contact of a set of plateau cells: the first z with F(z) = target.

    Parameters
    ----------
    height : array_like
        Plateau cell heights [m].
    area : array_like
        Their areas [m^2] (same shape).
    stiffness : float
        K [Pa/m].
    mu_0, slope, mu_min : float
        Friction law [-], [1/Pa], [-].
    target : float
        Demanded friction force [N].

    Returns
    -------
    float
        Disc position z [m].

    Raises
    ------
    ContactError
        If there is no plateau cell, the target is not positive, or no position reaches it
        (with ``mu_min = 0`` the friction force has a maximum).

    Notes
    -----
    Solves ``F(z) = target`` for the first root, the largest ``z``, with
    ``F(z) = sum_{k: h_k > z} A_k mu(K (h_k - z)) K (h_k - z)`` and
    ``mu(p) = max(mu_min, mu_0 - c p)`` (:func:`friction_force`): the heights are sorted
    highest first (a stable sort) and handed to :func:`first_root`. The first root, the
    smallest normal load, is a decision (docs/model.md section 4, "Torque control, first
    root"). No bar-length check is made here (the kernels make it).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260; E. Winkler, Die Lehre von der
    Elasticität und Festigkeit, Prag, 1867 (the elastic foundation).

    Examples
    --------
    The flat punch: four cells of 25 mm² at one height carry 100 N of friction at the
    pressure of :func:`brakeca.reference.flat_punch_pressure`:

    >>> import numpy as np
    >>> from brakeca.contact import solve_disc_position
    >>> from brakeca.reference import flat_punch_pressure
    >>> height, area = np.full(4, 20e-6), np.full(4, 25e-6)
    >>> z = solve_disc_position(
    ...     height, area, stiffness=1e11, mu_0=0.6, slope=3e-8, mu_min=0.15, target=100.0
    ... )
    >>> pressure = 1e11 * (20e-6 - z)  # K (h - z) [Pa]
    >>> bool(np.isclose(pressure, flat_punch_pressure(100.0, 1e-4, 0.6, 3e-8, 0.15), rtol=1e-12))
    True
    """
    h = np.ascontiguousarray(np.ravel(height), dtype=np.float64)
    ar = np.ascontiguousarray(np.broadcast_to(area, np.shape(height)).ravel(), dtype=np.float64)
    if target <= 0.0:
        raise ContactError(f"demanded friction force must be positive, got {target} N")
    order = np.argsort(-h, kind="stable")
    z, _, code = first_root(
        np.ascontiguousarray(h[order]),
        np.ascontiguousarray(ar[order]),
        h.size,
        stiffness,
        mu_0,
        slope,
        mu_min,
        target,
    )
    if code == SOLVE_NO_ROOT:
        raise ContactError(
            f"no disc position gives the demanded friction force {target:.4g} N: with mu_min = 0 "
            f"the friction force has a maximum (mu(p) p peaks at mu_0^2 / 4c), below the demand"
        )
    if code != SOLVE_OK:
        raise ContactError("no plateau cell can reach the disc")
    return z
