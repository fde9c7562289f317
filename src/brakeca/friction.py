"""Local coefficient of friction on plateaus (Figure 4 of the paper).

``mu(p) = max(mu_min, mu_0 - c p)``: the COF falls linearly with the local contact pressure and
never drops below the floor ``mu_min`` (0.15 in the paper). Primary and secondary plateaus share
the law; resin carries no load and no friction.

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Figure 4.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike

from brakeca import _cachedir

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

__all__ = ["coefficient_of_friction", "friction_stress_peak", "local_cof"]


@njit(cache=True)
def local_cof(pressure: float, mu_0: float, slope: float, mu_min: float) -> float:
    """Local COF at one contact pressure.

    Parameters
    ----------
    pressure : float
        Local contact pressure p [Pa].
    mu_0 : float
        COF at zero pressure [-].
    slope : float
        Decrease of the COF per pascal, c [1/Pa].
    mu_min : float
        COF floor [-].

    Returns
    -------
    float
        The local COF mu(p) [-].

    Notes
    -----
    ``mu(p) = max(mu_min, mu_0 - c p)``, the paper's law on primary and secondary plateaus
    alike (a tribofilm covers both): linear in the local pressure down to the floor, reached
    at ``p = (mu_0 - mu_min) / c`` (15 MPa with the defaults ``mu_0`` = 0.6, ``c`` = 3e-8 /Pa,
    ``mu_min`` = 0.15). Resin carries no load and so no friction. The paper gives the floor;
    ``mu_0`` and ``c`` are ours (docs/model.md section 5, ``friction.*``).

    This is the scalar, compiled form of :func:`coefficient_of_friction`, the same law: the
    exact kernel calls it for each plateau cell in contact. Computed as
    ``mu_0 - c p if that > mu_min else mu_min``, so a NaN pressure gives ``mu_min`` here and
    NaN from :func:`coefficient_of_friction`.

    References
    ----------
    Wahlström (2016), Figure 4, doi:10.1155/2016/8181260.

    Examples
    --------
    >>> from brakeca.friction import local_cof
    >>> round(local_cof(5e6, 0.6, 3e-8, 0.15), 12)  # 5 MPa on the paper's law: 0.6 - 0.15
    0.45
    >>> local_cof(40e6, 0.6, 3e-8, 0.15)  # past (0.6 - 0.15) / 3e-8 = 15 MPa: the floor
    0.15
    """
    mu = mu_0 - slope * pressure
    return mu if mu > mu_min else mu_min


def coefficient_of_friction(
    pressure: ArrayLike, mu_0: float = 0.6, slope: float = 3e-8, mu_min: float = 0.15
) -> np.ndarray:
    """Vectorised ``mu(p) = max(mu_min, mu_0 - c p)`` for an array of pressures.

    Parameters
    ----------
    pressure : array_like
        Contact pressures p [Pa].
    mu_0, slope, mu_min : float
        The friction law: COF at zero pressure mu_0 [-], its fall c [1/Pa], its floor
        mu_min [-] (the defaults are the configuration's, ``friction.*``).

    Returns
    -------
    numpy.ndarray
        The local COF mu(p) [-], shaped as ``pressure``.

    Notes
    -----
    ``mu(p) = max(mu_min, mu_0 - c p)`` elementwise (``numpy.maximum``): the same law as
    :func:`local_cof`, vectorised over an array of pressures for use outside the compiled
    kernels (a NaN pressure gives NaN here, ``mu_min`` there). Primary and secondary plateaus
    share it; resin carries no friction (docs/model.md section 5).

    References
    ----------
    Wahlström (2016), Figure 4, doi:10.1155/2016/8181260.

    Examples
    --------
    >>> round(float(coefficient_of_friction(5e6)), 12)  # 0.6 - 3e-8 * 5e6, to round-off
    0.45
    >>> float(coefficient_of_friction(20e6))
    0.15
    """
    return np.maximum(mu_min, mu_0 - slope * np.asarray(pressure, dtype=float))


def friction_stress_peak(mu_0: float, slope: float, mu_min: float) -> tuple[float, float]:
    """Pressure [Pa] and friction stress [Pa] where ``mu(p) p`` peaks on the linear branch.

    Parameters
    ----------
    mu_0, slope, mu_min : float
        The friction law: mu_0 [-], c [1/Pa], mu_min [-].

    Returns
    -------
    tuple of float
        ``(p*, mu(p*) p*)`` [Pa, Pa]; ``(inf, inf)`` when ``mu p`` has no peak there.

    Notes
    -----
    ``d(mu p)/dp = mu_0 - 2 c p = 0`` gives ``p* = mu_0 / (2c)`` and ``mu(p*) p* = mu_0^2/(4c)``,
    valid when ``mu(p*) >= mu_min``; otherwise ``mu p`` is monotone and there is no peak (inf).

    Examples
    --------
    >>> from brakeca.friction import friction_stress_peak
    >>> p, stress = friction_stress_peak(0.6, 3e-8, 0.0)  # p* = 0.6 / (2 * 3e-8)
    >>> round(p / 1e6, 6), round(stress / 1e6, 6)  # [MPa]
    (10.0, 3.0)
    >>> friction_stress_peak(0.6, 3e-8, 0.15)  # mu(p*) = 0.3 >= 0.15: the same peak
    (10000000.0, 3000000.0)
    >>> friction_stress_peak(0.6, 3e-8, 0.35)  # mu(p*) = 0.3 below the floor: mu p keeps rising
    (inf, inf)
    """
    if slope <= 0.0:
        return float("inf"), float("inf")
    p_star = mu_0 / (2.0 * slope)
    if mu_0 - slope * p_star < mu_min:
        return float("inf"), float("inf")
    return p_star, mu_0 * mu_0 / (4.0 * slope)
