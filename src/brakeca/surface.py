"""Initial pad surface: metal fibres lying in a rough resin matrix (Section 2.3, Figure 5).

Fibres are cylinders lying in the surface plane with their axis at the top of the resin
roughness band; at lateral distance ``s`` from the axis a fibre's top stands
``sqrt((d/2)^2 - s^2)`` above that level. Where fibres overlap the higher top wins. Fibres are
added until their covered area reaches the target fraction A (the last one may overshoot).
Fibre cells start as primary plateaus; all others are resin (status none) with heights uniform
in ``[0, resin_roughness]``, drawn independently per cell.

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from brakeca.config import PadConfig
from brakeca.geometry import Grid

__all__ = ["NONE", "PRIMARY", "SECONDARY", "Surface", "generate_surface"]

NONE = 0  #: resin, not a plateau
PRIMARY = 1  #: primary plateau (metal fibre)
SECONDARY = 2  #: secondary plateau (compacted wear particles)


@dataclass(frozen=True)
class Surface:
    """A pad surface.

    Attributes
    ----------
    height : ndarray of float64, shape (n_radial, n_angular)
        Undeformed surface height above the pad datum [m].
    status : ndarray of int8
        NONE, PRIMARY or SECONDARY [-].
    fibre_floor : ndarray of float64
        Height below which a fibre cell is no longer fibre [m]; ``-inf`` where fibres are
        columns through the pad (and on resin cells).
    n_fibres : int
        Number of fibres laid [-].
    """

    height: np.ndarray
    status: np.ndarray
    fibre_floor: np.ndarray
    n_fibres: int

    @property
    def fibre_area_fraction(self) -> float:
        """Fraction of cells that are fibre (unweighted by area) [-]."""
        return float(np.mean(self.status == PRIMARY))


def generate_surface(pad: PadConfig, grid: Grid, rng: np.random.Generator) -> Surface:
    """Lay fibres on a rough resin band until they cover the fraction ``pad.fibre_area_fraction``.

    Parameters
    ----------
    pad
        Pad material parameters (lengths and diameters [m], area fraction [-]).
    grid
        The polar grid.
    rng
        The run's random generator; every draw of the surface comes from it.

    Returns
    -------
    Surface
        Heights [m], statuses and fibre floors [m].

    Notes
    -----
    Draws, in this order: the resin heights of every cell, then per fibre its length, diameter,
    orientation in [0, pi), and centre (uniform in area over the band).
    """
    n_r, n_t = grid.shape
    resin = rng.uniform(0.0, pad.resin_roughness, size=(n_r, n_t))
    top = np.full((n_r, n_t), -np.inf)
    floor = np.full((n_r, n_t), np.inf)
    is_fibre = np.zeros((n_r, n_t), dtype=bool)

    r, th = grid.radius, grid.angle
    dr = r[1] - r[0] if n_r > 1 else 1.0
    dth = th[1] - th[0] if n_t > 1 else 1.0
    r_lo, r_hi = r[0] - dr / 2, r[-1] + dr / 2
    th_lo, th_hi = th[0] - dth / 2, th[-1] + dth / 2
    target = pad.fibre_area_fraction * grid.area
    covered = 0.0
    n_fibres = 0
    area_row = grid.cell_area
    axis_level = pad.resin_roughness
    while covered < target:
        length = rng.uniform(pad.fibre_length_min, pad.fibre_length_max)
        diameter = rng.uniform(pad.fibre_diameter_min, pad.fibre_diameter_max)
        phi = rng.uniform(0.0, np.pi)
        rc = np.sqrt(rng.uniform(r_lo * r_lo, r_hi * r_hi))
        tc = rng.uniform(th_lo, th_hi)
        n_fibres += 1
        reach = length / 2 + diameter / 2
        j0 = max(0, int(np.floor((rc - reach - r[0]) / dr)))
        j1 = min(n_r, int(np.ceil((rc + reach - r[0]) / dr)) + 1)
        half_angle = reach / max(r_lo, 1e-9)
        i0 = max(0, int(np.floor((tc - half_angle - th[0]) / dth)))
        i1 = min(n_t, int(np.ceil((tc + half_angle - th[0]) / dth)) + 1)
        if j0 >= j1 or i0 >= i1:
            continue
        rr = r[j0:j1, None]
        tt = th[None, i0:i1]
        dx = rr * np.cos(tt) - rc * np.cos(tc)
        dy = rr * np.sin(tt) - rc * np.sin(tc)
        along = dx * np.cos(phi) + dy * np.sin(phi)
        across = np.abs(-dx * np.sin(phi) + dy * np.cos(phi))
        radius_f = diameter / 2
        inside = (np.abs(along) <= length / 2) & (across < radius_f)
        if not inside.any():
            continue
        chord = np.sqrt(np.maximum(radius_f * radius_f - across * across, 0.0))
        sub_new = inside & ~is_fibre[j0:j1, i0:i1]
        covered += float((sub_new * area_row[j0:j1, None]).sum())
        is_fibre[j0:j1, i0:i1] |= inside
        top[j0:j1, i0:i1] = np.where(
            inside, np.maximum(top[j0:j1, i0:i1], axis_level + chord), top[j0:j1, i0:i1]
        )
        floor[j0:j1, i0:i1] = np.where(
            inside, np.minimum(floor[j0:j1, i0:i1], axis_level - chord), floor[j0:j1, i0:i1]
        )
    height = np.where(is_fibre, top, resin)
    status = np.where(is_fibre, PRIMARY, NONE).astype(np.int8)
    if pad.fibre_model == "columns":
        fibre_floor = np.full((n_r, n_t), -np.inf)
    else:
        fibre_floor = np.where(is_fibre, floor, -np.inf)
    return Surface(height=height, status=status, fibre_floor=fibre_floor, n_fibres=n_fibres)
