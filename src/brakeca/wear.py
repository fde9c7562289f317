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
        ``min(WP p s, h - z)`` [m]: a cell cannot wear below the disc surface in one step (a
        bound that is never active at the paper's parameters, where WP K s ~ 1e-4).

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
        ``h - (z - WR)`` if ``h > z`` else 0 [m].

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
