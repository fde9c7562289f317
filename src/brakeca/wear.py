"""Wear laws: Archard wear of plateaus and the fixed-depth wear of resin (Section 2.2).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260.
"""

from __future__ import annotations

from numba import njit

from brakeca import _cachedir

_cachedir.install()  # before anything below is compiled: brakeca's own cache folder

__all__ = ["archard_wear_depth", "resin_cut_depth"]


@njit(cache=True)
def archard_wear_depth(
    specific_wear_rate: float, pressure: float, sliding_distance: float, interference: float
) -> float:
    """Archard wear depth of a plateau cell in one step, clipped at its interference.

    Parameters
    ----------
    specific_wear_rate : float
        WP [m^3/(N m)] (= m^2/N).
    pressure : float
        Local contact pressure p [Pa].
    sliding_distance : float
        Distance slid in the step [m].
    interference : float
        How far the cell stands above the disc surface, h - z [m].

    Returns
    -------
    float
        Wear depth of the step [m], at most ``interference``.

    Notes
    -----
    ``dh = min(WP p s_j f, h - z)``: Archard's law, as the paper applies it to every plateau
    cell in contact, clipped. ``s_j f`` is the step's sliding distance: row ``j``'s full-step
    distance ``r_j N_m dtheta`` times the fraction ``f`` of a full step (the caller passes the
    product). The clip, a decision (docs/model.md section 6, "Clip"), keeps a cell from
    wearing below the disc surface in one step; with ``p = K (h - z)`` it acts only when
    ``WP K s_j f >= 1``, never at the paper's parameters (``WP K s`` ~ 1e-4). A secondary
    plateau's wear is also clipped at its deposit, by the kernel, not here (docs/model.md
    section 6).

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260; J. F. Archard, "Contact and
    rubbing of flat surfaces", J. Appl. Phys. 24, 981-988, 1953 (doi:10.1063/1.1721448).

    Examples
    --------
    >>> from brakeca.wear import archard_wear_depth
    >>> archard_wear_depth(1e-14, 2e6, 0.01, 1e-5)  # WP p s: 1e-14 m²/N, 2 MPa, 10 mm slid
    2e-10
    >>> archard_wear_depth(1e-13, 2e6, 0.01, 1e-9)  # clipped: the cell stood 1 nm into the disc
    1e-09
    """
    dh = specific_wear_rate * pressure * sliding_distance
    return dh if dh < interference else interference


@njit(cache=True)
def resin_cut_depth(height: float, disc_position: float, resin_wear_depth: float) -> float:
    """Depth removed from a resin cell that stands above the disc: it drops to ``z - WR``.

    Parameters
    ----------
    height : float
        Resin cell height h [m].
    disc_position : float
        Disc surface position z [m].
    resin_wear_depth : float
        WR [m].

    Returns
    -------
    float
        Depth removed from the cell [m]; 0 when it does not stand above the disc.

    Notes
    -----
    ``dh = h - (z - WR)`` if ``h > z``, else 0: a cut cell ends at ``z - WR``, and the
    removed volume ``(h - z + WR) A`` joins the particle stream of its row and subdomain. The
    paper says only that resin in contact wears down a fixed depth WR at once, leaving a gap;
    cutting to ``z - WR`` (WR below the disc, not WR below the cell's own height) is the
    decision that makes WR what the factor means (docs/model.md section 6, "Resin cut", and
    the table of decisions fixed in code). With the fibre field the exact kernel stops the
    cut at the top of a buried fibre above ``z - WR`` (docs/model.md section 7); this
    function does not.

    References
    ----------
    Wahlström (2016), Section 2.2, doi:10.1155/2016/8181260.

    Examples
    --------
    >>> from brakeca.wear import resin_cut_depth
    >>> round(resin_cut_depth(12e-6, 10e-6, 1e-7) * 1e6, 9)  # 2 µm above z: cut to z - WR [µm]
    2.1
    >>> resin_cut_depth(9e-6, 10e-6, 1e-7)  # below the disc surface: not cut
    0.0
    """
    if height > disc_position:
        return height - (disc_position - resin_wear_depth)
    return 0.0
