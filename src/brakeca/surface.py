"""Initial pad surface: metal fibres lying in a rough resin matrix (Section 2.3, Figure 5).

Fibres are cylinders lying in the surface plane with their axis at the top of the resin
roughness band; at lateral distance ``s`` from the axis a fibre's top stands
``sqrt((d/2)^2 - s^2)`` above that level. Where fibres overlap the higher top wins. Fibres are
added until their covered area reaches the target fraction A (the last one may overshoot).
Fibre cells start as primary plateaus; all others are resin (status none) with heights uniform
in ``[0, resin_roughness]``, drawn independently per cell.

With ``pad.fibre_model = "field"`` the pad below the resin band holds more fibres, lying at
random depths through the friction material (the foundation's bar length L), so that wear
exposes new fibre where old fibre wears through (:class:`FibreField`, docs/model.md section 7).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from brakeca.config import PadConfig
from brakeca.geometry import Grid

__all__ = [
    "NONE",
    "PRIMARY",
    "SECONDARY",
    "FibreField",
    "Surface",
    "generate_surface",
    "lay_fibre_field",
]

NONE = 0  #: resin, not a plateau
PRIMARY = 1  #: primary plateau (metal fibre)
SECONDARY = 2  #: secondary plateau (compacted wear particles)


@dataclass(frozen=True)
class FibreField:
    """The fibre a cell meets as the pad wears down: per cell, the height intervals that are
    fibre, highest first, where the fibres crossing the cell's vertical line overlap merged
    into one interval (``pad.fibre_model = "field"``).

    Attributes
    ----------
    offsets : ndarray of int64, shape (n_cells + 1,)
        Cell ``c``'s intervals are ``top[offsets[c]:offsets[c + 1]]`` (flat index
        ``j * n_angular + i``).
    top, bottom : ndarray of float64
        Upper and lower ends of each interval [m], ``bottom < top``; within a cell the
        intervals are disjoint and in descending order.
    next : ndarray of int64, shape (n_cells,)
        Index of the first interval below the cell's fibre at the surface (of its first
        interval on a resin cell): the next fibre wear can expose.
    depth : float
        Thickness of the fibre field below the resin band [m].
    n_fibres : int
        Number of fibres laid below the resin band [-].
    """

    offsets: np.ndarray
    top: np.ndarray
    bottom: np.ndarray
    next: np.ndarray
    depth: float
    n_fibres: int

    def volume_fraction(self, cell_area: np.ndarray) -> float:
        """Fraction of the field's volume (the band's area times ``depth``, below the resin
        band) that is fibre, from the merged intervals [-].

        Parameters
        ----------
        cell_area : ndarray, shape (n_cells,)
            Area of each cell [m^2], flat index.
        """
        top = np.minimum(self.top, 0.0)
        bottom = np.maximum(self.bottom, -self.depth)
        length = np.maximum(top - bottom, 0.0)
        per_cell = np.add.reduceat(np.append(length, 0.0), self.offsets[:-1])
        per_cell[self.offsets[:-1] == self.offsets[1:]] = 0.0
        return float(np.sum(per_cell * cell_area) / (np.sum(cell_area) * self.depth))


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
        Number of fibres laid on the surface [-].
    field : FibreField or None
        The fibres below the resin band (``pad.fibre_model = "field"`` only).
    """

    height: np.ndarray
    status: np.ndarray
    fibre_floor: np.ndarray
    n_fibres: int
    field: FibreField | None = None

    @property
    def fibre_area_fraction(self) -> float:
        """Fraction of cells that are fibre (unweighted by area) [-]."""
        return float(np.mean(self.status == PRIMARY))


@dataclass(frozen=True)
class _Band:
    """The band's bounds for laying fibres: row radii and column angles [m, rad], their steps,
    and the band's outer edges."""

    r: np.ndarray
    th: np.ndarray
    dr: float
    dth: float
    r_lo: float
    r_hi: float
    th_lo: float
    th_hi: float

    @classmethod
    def of(cls, grid: Grid) -> _Band:
        r, th = grid.radius, grid.angle
        dr = r[1] - r[0] if r.size > 1 else 1.0
        dth = th[1] - th[0] if th.size > 1 else 1.0
        return cls(r, th, dr, dth, r[0] - dr / 2, r[-1] + dr / 2, th[0] - dth / 2, th[-1] + dth / 2)

    def draw(self, pad: PadConfig, rng: np.random.Generator) -> tuple[float, ...]:
        """One fibre's length [m], diameter [m], orientation [rad] and centre (radius [m],
        angle [rad]), uniform in area over the band, drawn in that order."""
        length = rng.uniform(pad.fibre_length_min, pad.fibre_length_max)
        diameter = rng.uniform(pad.fibre_diameter_min, pad.fibre_diameter_max)
        phi = rng.uniform(0.0, np.pi)
        rc = np.sqrt(rng.uniform(self.r_lo * self.r_lo, self.r_hi * self.r_hi))
        tc = rng.uniform(self.th_lo, self.th_hi)
        return length, diameter, phi, rc, tc

    def footprint(
        self, length: float, diameter: float, phi: float, rc: float, tc: float
    ) -> tuple[slice, slice, np.ndarray, np.ndarray] | None:
        """The cells a lying fibre covers: the window's rows and columns, the mask of the
        window's cells within the fibre, and the half-chord ``sqrt((d/2)^2 - s^2)`` [m] at each
        cell's lateral distance ``s`` from the axis; None if it covers no cell."""
        r, th, dr, dth = self.r, self.th, self.dr, self.dth
        reach = length / 2 + diameter / 2
        j0 = max(0, int(np.floor((rc - reach - r[0]) / dr)))
        j1 = min(r.size, int(np.ceil((rc + reach - r[0]) / dr)) + 1)
        half_angle = reach / max(self.r_lo, 1e-9)
        i0 = max(0, int(np.floor((tc - half_angle - th[0]) / dth)))
        i1 = min(th.size, int(np.ceil((tc + half_angle - th[0]) / dth)) + 1)
        if j0 >= j1 or i0 >= i1:
            return None
        rr = r[j0:j1, None]
        tt = th[None, i0:i1]
        dx = rr * np.cos(tt) - rc * np.cos(tc)
        dy = rr * np.sin(tt) - rc * np.sin(tc)
        along = dx * np.cos(phi) + dy * np.sin(phi)
        across = np.abs(-dx * np.sin(phi) + dy * np.cos(phi))
        radius_f = diameter / 2
        inside = (np.abs(along) <= length / 2) & (across < radius_f)
        if not inside.any():
            return None
        chord = np.sqrt(np.maximum(radius_f * radius_f - across * across, 0.0))
        return slice(j0, j1), slice(i0, i1), inside, chord


def generate_surface(
    pad: PadConfig, grid: Grid, rng: np.random.Generator, *, field_depth: float | None = None
) -> Surface:
    """Lay fibres on a rough resin band until they cover the fraction ``pad.fibre_area_fraction``.

    Parameters
    ----------
    pad
        Pad material parameters (lengths and diameters [m], area fraction [-]).
    grid
        The polar grid.
    rng
        The run's random generator; every draw of the surface comes from it.
    field_depth
        Thickness of the fibre field below the resin band [m] (``pad.fibre_model = "field"``
        only; default ``pad.fibre_field_depth``; ``PadConfig.field_depth`` resolves a
        configuration's).

    Returns
    -------
    Surface
        Heights [m], statuses and fibre floors [m]; with ``pad.fibre_model = "field"`` also the
        fibre field below the resin band (:func:`lay_fibre_field`).

    Notes
    -----
    Draws, in this order: the resin heights of every cell, then per fibre its length, diameter,
    orientation in [0, pi), and centre (uniform in area over the band); for the field, then the
    field's fibres (:func:`lay_fibre_field`). So the surface of the three fibre models is the
    same for the same generator.
    """
    n_r, n_t = grid.shape
    resin = rng.uniform(0.0, pad.resin_roughness, size=(n_r, n_t))
    top = np.full((n_r, n_t), -np.inf)
    floor = np.full((n_r, n_t), np.inf)
    is_fibre = np.zeros((n_r, n_t), dtype=bool)

    band = _Band.of(grid)
    target = pad.fibre_area_fraction * grid.area
    covered = 0.0
    n_fibres = 0
    area_row = grid.cell_area
    axis_level = pad.resin_roughness
    while covered < target:
        fibre = band.draw(pad, rng)
        n_fibres += 1
        cells = band.footprint(*fibre)
        if cells is None:
            continue
        rows, cols, inside, chord = cells
        sub_new = inside & ~is_fibre[rows, cols]
        covered += float((sub_new * area_row[rows, None]).sum())
        is_fibre[rows, cols] |= inside
        top[rows, cols] = np.where(
            inside, np.maximum(top[rows, cols], axis_level + chord), top[rows, cols]
        )
        floor[rows, cols] = np.where(
            inside, np.minimum(floor[rows, cols], axis_level - chord), floor[rows, cols]
        )
    height = np.where(is_fibre, top, resin)
    status = np.where(is_fibre, PRIMARY, NONE).astype(np.int8)
    field = None
    if pad.fibre_model == "columns":
        fibre_floor = np.full((n_r, n_t), -np.inf)
    else:
        fibre_floor = np.where(is_fibre, floor, -np.inf)
    if pad.fibre_model == "field":
        field_depth = pad.fibre_field_depth if field_depth is None else field_depth
        if field_depth is None:
            raise ValueError(
                "generate_surface: fibre_model = 'field' needs field_depth (or "
                "pad.fibre_field_depth)"
            )
        field = lay_fibre_field(pad, grid, rng, field_depth, band, is_fibre, top, floor)
        first = field.offsets[:-1]
        has = is_fibre.ravel()
        # a surface fibre's floor is the bottom of the merged interval that holds its top
        flat_floor = fibre_floor.ravel().copy()
        flat_floor[has] = field.bottom[first[has]]
        fibre_floor = flat_floor.reshape(n_r, n_t)
    return Surface(
        height=height, status=status, fibre_floor=fibre_floor, n_fibres=n_fibres, field=field
    )


def lay_fibre_field(
    pad: PadConfig,
    grid: Grid,
    rng: np.random.Generator,
    depth: float,
    band: _Band | None = None,
    is_fibre: np.ndarray | None = None,
    top: np.ndarray | None = None,
    floor: np.ndarray | None = None,
) -> FibreField:
    """Lay fibres through the pad below the resin band, and merge them per cell with the
    surface's fibres into the intervals wear will meet.

    The field is the slab from ``-depth`` to 0 (the resin band's bottom); a
    fibre lies in it like the surface's fibres (the same laws for length, diameter,
    orientation and centre) with its axis at a depth uniform over the levels that keep it
    whole inside the slab. Fibres are added until their summed volume (as the grid sees them)
    reaches ``-ln(1 - A) V``, ``V`` the slab's volume: for fibres placed independently (a
    Boolean model) that makes the expected fibre fraction of the slab ``A``, overlaps counted
    once (:meth:`FibreField.volume_fraction` gives the realised one).

    Parameters
    ----------
    pad
        Pad parameters; ``fibre_area_fraction`` A [-] is the field's volume fraction.
    grid
        The polar grid.
    rng
        The run's generator; draws per fibre its length, diameter, orientation, centre and
        then its axis depth.
    depth
        The field's thickness [m].
    band, is_fibre, top, floor
        The band and the surface's fibres (mask, tops and undersides [m], grid-shaped), as
        :func:`generate_surface` laid them; none for a field without surface fibres.
    """
    n_r, n_t = grid.shape
    band = band or _Band.of(grid)
    fraction = pad.fibre_area_fraction
    if fraction >= 1.0:
        raise ValueError("pad.fibre_area_fraction must be below 1 for fibre_model = 'field'")
    target = -np.log1p(-fraction) * grid.area * depth
    cells: list[np.ndarray] = []
    tops: list[np.ndarray] = []
    bottoms: list[np.ndarray] = []
    if is_fibre is not None and top is not None and floor is not None and is_fibre.any():
        flat = np.flatnonzero(is_fibre.ravel())
        cells.append(flat)
        tops.append(top.ravel()[flat])
        bottoms.append(floor.ravel()[flat])
    area_row = grid.cell_area
    laid = 0.0
    n_fibres = 0
    while laid < target:
        length, diameter, phi, rc, tc = band.draw(pad, rng)
        axis = rng.uniform(-depth + diameter / 2, -diameter / 2)
        n_fibres += 1
        hit = band.footprint(length, diameter, phi, rc, tc)
        if hit is None:
            continue
        rows, cols, inside, chord = hit
        jj, ii = np.nonzero(inside)
        half = chord[jj, ii]
        keep = half > 0.0
        jj, ii, half = jj[keep], ii[keep], half[keep]
        jj = jj + rows.start
        ii = ii + cols.start
        laid += float(np.sum(2.0 * half * area_row[jj]))
        cells.append(jj * n_t + ii)
        tops.append(axis + half)
        bottoms.append(axis - half)
    offsets, merged_top, merged_bottom = _merge_intervals(
        n_r * n_t,
        np.concatenate(cells) if cells else np.zeros(0, dtype=np.int64),
        np.concatenate(tops) if tops else np.zeros(0),
        np.concatenate(bottoms) if bottoms else np.zeros(0),
    )
    nxt = offsets[:-1].copy()
    if is_fibre is not None:
        nxt[is_fibre.ravel()] += 1  # the surface fibre's interval is the cell's first
    return FibreField(offsets, merged_top, merged_bottom, nxt, float(depth), n_fibres)


def _merge_intervals(
    n_cells: int, cell: np.ndarray, top: np.ndarray, bottom: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per cell, the union of the intervals ``[bottom, top]`` [m] as disjoint intervals in
    descending order: (offsets, tops, bottoms) in the layout of :class:`FibreField`.
    Intervals that touch or overlap merge."""
    order = np.lexsort((-top, cell))
    cell, top, bottom = cell[order], top[order], bottom[order]
    # an interval starts a new merged one where it begins a cell's list or lies wholly below
    # every interval before it in the cell (its top under their lowest bottom); the running
    # lowest bottom is taken rank by rank (a cell holds a few tens of intervals at most)
    counts = np.bincount(cell, minlength=n_cells)
    starts = np.zeros(n_cells + 1, dtype=np.int64)
    np.cumsum(counts, out=starts[1:])
    rank = np.arange(cell.size) - starts[cell]
    new = rank == 0
    low = bottom.copy()
    for r in range(1, int(counts.max(initial=0))):
        at = np.flatnonzero(rank == r)
        new[at] = top[at] < low[at - 1]
        low[at] = np.minimum(low[at - 1], bottom[at])
    group = np.cumsum(new) - 1
    n = int(new.sum())
    merged_top = top[new]
    merged_bottom = np.full(n, np.inf)
    np.minimum.at(merged_bottom, group, bottom)
    counts = np.bincount(cell[new], minlength=n_cells)
    offsets = np.zeros(n_cells + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    return offsets, merged_top, merged_bottom
