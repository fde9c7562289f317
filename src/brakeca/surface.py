"""Initial pad surface: metal fibres lying in a rough resin matrix (Section 2.3, Figure 5).

Fibres are cylinders lying in the surface plane with their axis at the top of the resin
roughness band; at lateral distance ``s`` from the axis a fibre's top stands
``sqrt((d/2)^2 - s^2)`` above that level. Where fibres overlap the higher top wins. Fibres are
added until their covered area reaches the target fraction A (the last one may overshoot).
Fibre cells start as primary plateaus; all others are resin (status none) with heights uniform
in ``[0, resin_roughness]``, drawn independently per cell.

With ``pad.fibre_model = "field"`` the pad below the resin band holds more fibres, lying at
random depths, laid slab by slab ahead of the wear, so that wear exposes new fibre where old
fibre wears through (:class:`FibreField`, docs/model.md section 7).

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
    "FIELD_SLAB",
    "NONE",
    "PRIMARY",
    "SECONDARY",
    "FibreField",
    "FibreFieldError",
    "Surface",
    "deepen_fibre_field",
    "generate_surface",
    "start_fibre_field",
]

NONE = 0  #: resin, not a plateau
PRIMARY = 1  #: primary plateau (metal fibre)
SECONDARY = 2  #: secondary plateau (compacted wear particles)


FIELD_SLAB = 2e-3  #: thickness of the slabs the fibre field is laid in, as wear needs [m]


class FibreFieldError(RuntimeError):
    """The pad surface came down past the fibre field laid ahead of it in one stop (more than
    a slab, :data:`FIELD_SLAB`): fibres there would have been passed unseen."""


@dataclass(frozen=True)
class FibreField:
    """The fibre a cell meets as the pad wears down: per cell, the height intervals that are
    fibre, highest first, where the fibres crossing the cell's vertical line overlap merged
    into one interval (``pad.fibre_model = "field"``).

    The field is laid in slabs of :data:`FIELD_SLAB` as the wear front comes down
    (:func:`deepen_fibre_field`): slab ``k`` holds the fibres whose axes lie between
    ``-(k + 1) FIELD_SLAB`` and ``-k FIELD_SLAB``, drawn from their own generator seeded with
    ``(seed, k)``.

    Attributes
    ----------
    offsets : ndarray of int64, shape (n_cells + 1,)
        Cell ``c``'s intervals are ``top[offsets[c]:offsets[c + 1]]`` (flat index
        ``j * n_angular + i``).
    top, bottom : ndarray of float64
        Upper and lower ends of each interval [m], ``bottom < top``; within a cell the
        intervals are disjoint and in descending order.
    next : ndarray of int64, shape (n_cells,)
        Index of the first interval below the cell's pad surface: the next fibre wear can
        expose.
    seed : int
        Seed of the field's slabs, drawn from the run's generator [-].
    slabs : int
        Slabs laid so far [-].
    n_fibres : int
        Fibres laid in them [-].
    """

    offsets: np.ndarray
    top: np.ndarray
    bottom: np.ndarray
    next: np.ndarray
    seed: int
    slabs: int
    n_fibres: int

    def volume_fraction(self, cell_area: np.ndarray, upper: float, lower: float) -> float:
        """Fraction of the volume between the levels ``upper`` and ``lower`` [m] under the band
        that is fibre, from the merged intervals [-].

        Parameters
        ----------
        cell_area : ndarray, shape (n_cells,)
            Area of each cell [m^2], flat index.
        upper, lower : float
            The levels [m], ``lower < upper``.

        Returns
        -------
        float
            Fibre volume between the levels over the band's volume between them [-].
        """
        length = np.maximum(np.minimum(self.top, upper) - np.maximum(self.bottom, lower), 0.0)
        cell = np.repeat(np.arange(cell_area.size), np.diff(self.offsets))
        volume = float(np.sum(length * cell_area[cell]))
        return volume / (float(np.sum(cell_area)) * (upper - lower))


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

    reach: float = 0.0

    @classmethod
    def of(cls, grid: Grid, reach: float = 0.0) -> _Band:
        """The band of ``grid``; fibre centres are drawn up to ``reach`` [m] beyond its
        edges (:attr:`brakeca.config.PadConfig.fibre_reach`)."""
        r, th = grid.radius, grid.angle
        dth = th[1] - th[0]  # a mesh has at least two columns
        # one row: the radial step from the row's cell area, A_j = r_j dtheta dr
        dr = r[1] - r[0] if r.size > 1 else grid.cell_area[0] / (r[0] * dth)
        return cls(
            r, th, dr, dth, r[0] - dr / 2, r[-1] + dr / 2, th[0] - dth / 2, th[-1] + dth / 2, reach
        )

    def centre_bounds(self) -> tuple[float, float, float, float]:
        """Where fibre centres are drawn: radii [m] and angles [rad], the band widened by
        :attr:`reach` on every side (the angle by ``reach`` over the smallest radius)."""
        r_lo = max(self.r_lo - self.reach, 1e-3 * self.r_lo)
        wide = self.reach / r_lo
        return r_lo, self.r_hi + self.reach, self.th_lo - wide, self.th_hi + wide

    def draw(self, pad: PadConfig, rng: np.random.Generator) -> tuple[float, ...]:
        """One fibre's length [m], diameter [m], orientation [rad] and centre (radius [m],
        angle [rad]), uniform in area over the band (widened by :attr:`reach`), drawn in
        that order."""
        length = rng.uniform(pad.fibre_length_min, pad.fibre_length_max)
        diameter = rng.uniform(pad.fibre_diameter_min, pad.fibre_diameter_max)
        phi = rng.uniform(0.0, np.pi)
        r_lo, r_hi, th_lo, th_hi = self.centre_bounds()  # at reach 0: the band's, to the bit
        rc = np.sqrt(rng.uniform(r_lo * r_lo, r_hi * r_hi))
        tc = rng.uniform(th_lo, th_hi)
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


def centre_area(grid: Grid, reach: float) -> float:
    """The area fibre centres are drawn over [m^2]: the band of ``grid`` widened by ``reach``
    [m] (:meth:`_Band.centre_bounds`; the band's own area, to the cells' edges, at 0)."""
    r_lo, r_hi, th_lo, th_hi = _Band.of(grid, reach).centre_bounds()
    return 0.5 * (th_hi - th_lo) * (r_hi * r_hi - r_lo * r_lo)


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
        Heights [m], statuses [-] and fibre floors [m], each of shape (n_radial, n_angular),
        and the number of fibres laid; with ``pad.fibre_model = "field"`` also the fibre
        field's first slab below the resin band (:func:`start_fibre_field`).

    Notes
    -----
    Draws, in this order: the resin heights of every cell, then per fibre its length, diameter,
    orientation in [0, pi), and centre (uniform in area over the band); for the field, then one
    integer, the seed of the field's slabs (:func:`start_fibre_field`). So the surface of the
    three fibre models is the same for the same generator.

    Fibres are laid until their share of the band reaches A, so the share drawn exceeds A by
    up to the last fibre's share: nothing on the paper's band, much on a band of a few rows,
    where one fibre (up to 10 mm by 0.7 mm) covers several per cent of it. Over 8 seeds:
    20.6 ± 0.3 % for A = 20 % on 21 × 1000 cells (the quick band), 25.4 ± 3.6 % on 21 × 100,
    30.4 ± 11.6 % on 5 × 100 and 34.9 ± 13.2 % on 3 × 100 (for A = 5 %: 5.4, 8.2, 10.2 and
    16.7 %). A run's ``primary_area_fraction`` is the share drawn; a study of A needs a band
    of many rows (docs/model.md §3).

    References
    ----------
    Wahlström (2016), Section 2.3 and Figure 5, doi:10.1155/2016/8181260.

    Examples
    --------
    A pad of the paper's material (A = 20 %) on a band of 21 rows and 200 columns; the same
    seed lays the same pad:

    >>> import numpy as np
    >>> from brakeca.geometry import make_grid
    >>> from brakeca.presets import load_preset
    >>> from brakeca.surface import PRIMARY, generate_surface
    >>> config = load_preset().with_updates({"mesh.n_radial": 21, "mesh.n_angular": 200})
    >>> grid = make_grid(config)
    >>> pad = generate_surface(config.pad, grid, np.random.default_rng(2016))
    >>> pad.height.shape
    (21, 200)
    >>> covered = float(np.sum((pad.status == PRIMARY) * grid.cell_area[:, None]) / grid.area)
    >>> 0.20 <= covered < 0.25  # fibres are laid until they cover A (the last overshoots)
    True
    >>> again = generate_surface(config.pad, grid, np.random.default_rng(2016))
    >>> bool(np.array_equal(pad.height, again.height))
    True
    """
    n_r, n_t = grid.shape
    resin = rng.uniform(0.0, pad.resin_roughness, size=(n_r, n_t))
    top = np.full((n_r, n_t), -np.inf)
    floor = np.full((n_r, n_t), np.inf)
    is_fibre = np.zeros((n_r, n_t), dtype=bool)

    band = _Band.of(grid, pad.fibre_reach)
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
        field = start_fibre_field(pad, grid, rng, band, is_fibre, top, floor)
        first = field.offsets[:-1]
        has = is_fibre.ravel()
        # a surface fibre's floor is the bottom of the merged interval that holds its top
        flat_floor = fibre_floor.ravel().copy()
        flat_floor[has] = field.bottom[first[has]]
        fibre_floor = flat_floor.reshape(n_r, n_t)
    return Surface(
        height=height, status=status, fibre_floor=fibre_floor, n_fibres=n_fibres, field=field
    )


def _lay_slab(
    pad: PadConfig, grid: Grid, band: _Band, seed: int, k: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The fibres of slab ``k`` of the field: (cells, interval tops [m], interval bottoms [m],
    fibres laid).

    A fibre follows the surface fibres' laws (length, diameter, orientation, centre), lies
    flat, and has its axis at a level uniform between ``-(k + 1) FIELD_SLAB`` and
    ``-k FIELD_SLAB``; the first slab's fibres are cut at 0, the bottom of the resin band.
    Fibres are added until their summed volume (as the grid sees them, uncut) reaches
    ``-ln(1 - A)`` times the slab's volume: for fibres placed independently (a Boolean model)
    the expected fibre fraction of the field is then ``A``, overlaps counted once. Draws come
    from a generator seeded with ``(seed, k)``: per fibre length, diameter, orientation,
    centre, then axis level."""
    rng = np.random.default_rng([seed, k])
    n_t = grid.shape[1]
    upper, lower = -k * FIELD_SLAB, -(k + 1) * FIELD_SLAB
    target = -np.log1p(-pad.fibre_area_fraction) * grid.area * FIELD_SLAB
    area_row = grid.cell_area
    cells, tops, bottoms = [], [], []
    laid = 0.0
    n_fibres = 0
    while laid < target:
        length, diameter, phi, rc, tc = band.draw(pad, rng)
        axis = rng.uniform(lower, upper)
        n_fibres += 1
        hit = band.footprint(length, diameter, phi, rc, tc)
        if hit is None:
            continue
        rows, cols, inside, chord = hit
        jj, ii = np.nonzero(inside)
        half = chord[jj, ii]
        jj = jj + rows.start
        ii = ii + cols.start
        laid += float(np.sum(2.0 * half * area_row[jj]))
        t, b = axis + half, axis - half
        if k == 0:
            t = np.minimum(t, 0.0)
        keep = t > b
        cells.append((jj * n_t + ii)[keep])
        tops.append(t[keep])
        bottoms.append(b[keep])
    if not cells:
        return np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0), n_fibres
    return np.concatenate(cells), np.concatenate(tops), np.concatenate(bottoms), n_fibres


def start_fibre_field(
    pad: PadConfig,
    grid: Grid,
    rng: np.random.Generator,
    band: _Band | None = None,
    is_fibre: np.ndarray | None = None,
    top: np.ndarray | None = None,
    floor: np.ndarray | None = None,
) -> FibreField:
    """The fibre field's first slab under the resin band, merged per cell with the surface's
    fibres into the intervals wear will meet.

    Parameters
    ----------
    pad
        Pad parameters; ``fibre_area_fraction`` A [-] is the field's volume fraction.
    grid
        The polar grid.
    rng
        The run's generator: one integer is drawn from it, the seed of the field's slabs.
    band, is_fibre, top, floor
        The band and the surface's fibres (mask, tops and undersides [m], grid-shaped), as
        :func:`generate_surface` laid them; none for a field without surface fibres.

    Returns
    -------
    FibreField
        One slab laid, its intervals [m] merged with the surface fibres'; each cell's
        ``next`` is its first interval, or its second where a surface fibre holds the first.

    Raises
    ------
    ValueError
        If ``pad.fibre_area_fraction`` is 1 or more (the slab's volume target,
        ``-ln(1 - A)``, would be infinite).
    """
    if pad.fibre_area_fraction >= 1.0:
        raise ValueError("pad.fibre_area_fraction must be below 1 for fibre_model = 'field'")
    band = band or _Band.of(grid, pad.fibre_reach)
    seed = int(rng.integers(0, 2**63 - 1))
    cells, tops, bottoms, n_fibres = _lay_slab(pad, grid, band, seed, 0)
    n_cells = grid.shape[0] * grid.shape[1]
    fibre = np.zeros(n_cells, dtype=bool)
    if is_fibre is not None and top is not None and floor is not None:
        fibre = is_fibre.ravel()
        flat = np.flatnonzero(fibre)
        cells = np.concatenate([flat, cells])
        tops = np.concatenate([top.ravel()[flat], tops])
        bottoms = np.concatenate([floor.ravel()[flat], bottoms])
    offsets, merged_top, merged_bottom = _merge_intervals(n_cells, cells, tops, bottoms)
    nxt = offsets[:-1] + fibre  # the surface fibre's interval is the cell's first
    return FibreField(offsets, merged_top, merged_bottom, nxt, seed, 1, n_fibres)


def deepen_fibre_field(
    field: FibreField,
    pad: PadConfig,
    grid: Grid,
    lowest: float,
    status: np.ndarray,
    height: np.ndarray,
    fibre_floor: np.ndarray,
) -> FibreField:
    """Lay the field's next slabs until it reaches a slab below ``lowest``, the lowest pad
    surface [m], and keep of the old intervals only those still ahead of the wear.

    The field must be laid ahead of the wear: a new slab's fibres reach a fibre radius above
    its top level, and that must still be below every cell's surface. So slabs are added
    while ``lowest`` is within one slab of the field's last level, and a surface that has come
    down further than that since the last call (more than ``FIELD_SLAB`` minus the largest
    fibre radius in one stop) is an error.

    Parameters
    ----------
    field
        The field so far.
    pad, grid
        Pad parameters and the grid the field was laid for.
    lowest
        The lowest pad surface of any cell [m].
    status, height, fibre_floor : arrays (n_cells,)
        Statuses, heights [m] and fibre floors [m] of the cells; ``fibre_floor`` changes in
        place where a new fibre touches the fibre a primary plateau stands in.

    Returns
    -------
    FibreField
        The field with its new slabs, the intervals above the wear dropped, and each cell's
        ``next`` at its first interval below the surface; ``field`` itself, unchanged, when
        ``lowest`` is not yet within a slab of the field's last level.

    Raises
    ------
    FibreFieldError
        (A ``RuntimeError``.) If ``lowest`` lies less than the largest fibre radius
        (``pad.fibre_diameter_max / 2``) above the field's last level: the surface came
        down into the unlaid slab in one stop.
    """
    if lowest - FIELD_SLAB >= -field.slabs * FIELD_SLAB:
        return field
    if lowest < -field.slabs * FIELD_SLAB + pad.fibre_diameter_max / 2:
        raise FibreFieldError(
            f"the pad surface came down to {lowest * 1e3:.3f} mm, into the fibre field's "
            f"unlaid slab (below {-field.slabs * FIELD_SLAB * 1e3:.3f} mm): it came down more "
            f"than a slab of the field ({FIELD_SLAB * 1e3:g} mm, less a fibre radius) in one stop"
        )
    band = _Band.of(grid, pad.fibre_reach)
    n_cells = status.size
    # the intervals still ahead of the wear: from each cell's next one on
    ahead = field.offsets[1:] - field.next
    cell = np.repeat(np.arange(n_cells), ahead)
    first = np.cumsum(ahead) - ahead
    k = field.next[cell] + (np.arange(cell.size) - first[cell])
    pieces = [(cell, field.top[k], field.bottom[k])]
    # a primary plateau's fibre, from its surface to its floor, so a new fibre touching it
    # lowers its floor
    primary = np.flatnonzero(status == PRIMARY)
    pieces.append((primary, height[primary], fibre_floor[primary]))
    slabs, n_fibres = field.slabs, field.n_fibres
    while lowest - FIELD_SLAB < -slabs * FIELD_SLAB:
        c, t, b, n = _lay_slab(pad, grid, band, field.seed, slabs)
        pieces.append((c, t, b))
        slabs += 1
        n_fibres += n
    offsets, top, bottom = _merge_intervals(
        n_cells,
        np.concatenate([p[0] for p in pieces]),
        np.concatenate([p[1] for p in pieces]),
        np.concatenate([p[2] for p in pieces]),
    )
    nxt = offsets[:-1].copy()
    fibre_floor[primary] = bottom[nxt[primary]]
    nxt[primary] += 1
    return FibreField(offsets, top, bottom, nxt, field.seed, slabs, n_fibres)


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
