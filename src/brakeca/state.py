"""A run's state between stops: the cells' arrays with the kernels' bookkeeping
(:class:`SimulationState`), and what the run keeps of its finished stops (:class:`StopLog`).

References
----------
J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad Properties on
Friction and Wear Emissions", Advances in Tribology, 2016, Article ID 8181260.
doi:10.1155/2016/8181260
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from brakeca import _kernels as K
from brakeca import _lazy
from brakeca.automaton import Exposure
from brakeca.geometry import Grid
from brakeca.surface import NONE, SECONDARY, FibreField, Surface

__all__ = [
    "SimulationState",
    "StopLog",
]


_PACKED_FIELDS = {
    "pk_h": K.P_H,
    "pk_base": K.P_BASE,
    "pk_idx": K.P_IDX,
    "pk_bin": K.P_BIN,
    "pk_st": K.P_ST,
}


@dataclass
class SimulationState:
    """The mutable state of a run between stops (flat arrays, index ``j * n_angular + i``).

    Attributes
    ----------
    height : float64 array
        Cell heights [m].
    base : float64 array
        Height under the deposit of secondary cells [m].
    status : int8 array
        NONE / PRIMARY / SECONDARY.
    fibre_floor : float64 array
        Fibre underside [m] (-inf for columns).
    inflow, outflow : float64 arrays (n_radial * n_subdomains)
        Particle streams per bin ``j * n_sub + k`` [m^3].
    acc : float64 array
        Accumulators: removed, emitted, held [m^3]; primary and secondary area [m^2].
    cell_area : float64 array
        Each cell's area, its row's ``A_j = r_j dtheta dr`` [m^2].
    cell_slide : float64 array
        Each cell's sliding distance in a full step, its row's ``r_j N_m dtheta`` [m].
    cell_bin : int64 array
        Each cell's stream bin ``j * n_sub + k`` [-].
    n_radial, n_angular : int
        Rows and columns of the grid [-].
    n_subdomains : int
        Subdomains N along the sliding direction [-].
    fibres : FibreField or None
        The fibre field (``pad.fibre_model = "field"`` only); its ``next`` changes in place,
        and it is replaced when it is laid deeper.

    The other arrays are derived bookkeeping of the kernel (sorted plateaus, resin heap,
    creation candidates, rule-4 list), rebuilt by :meth:`resync`.
    """

    height: np.ndarray
    base: np.ndarray
    status: np.ndarray
    fibre_floor: np.ndarray
    inflow: np.ndarray
    outflow: np.ndarray
    acc: np.ndarray
    cell_area: np.ndarray
    cell_slide: np.ndarray
    cell_bin: np.ndarray
    n_radial: int
    n_angular: int
    n_subdomains: int
    fibres: FibreField | None = None
    exposed: np.ndarray = field(init=False)
    pk: tuple = field(init=False)
    gone: tuple = field(init=False)
    bin_area: np.ndarray = field(init=False)
    bin_slide: np.ndarray = field(init=False)
    rule7_on: bool = field(init=False)
    heap_keys: np.ndarray = field(init=False)
    heap_vals: np.ndarray = field(init=False)
    cand: np.ndarray = field(init=False)
    ncand: np.ndarray = field(init=False)
    cmax: np.ndarray = field(init=False)
    rule4_list: np.ndarray = field(init=False)
    cnt: np.ndarray = field(init=False)
    mark: np.ndarray = field(init=False)
    prof: np.ndarray = field(init=False)
    lazy: _lazy.Lazy | None = field(init=False, default=None)
    lazy_walk: np.ndarray = field(init=False)
    packed_stale: bool = field(init=False, default=False)

    def __post_init__(self) -> None:
        n = self.height.size
        self.pk = K.packed_records(n)
        self.gone = K.packed_records(n)
        # every cell of a stream bin (one row, one subdomain) has the same area and slide
        self.bin_area = np.zeros(self.n_radial * self.n_subdomains)
        self.bin_slide = np.zeros(self.n_radial * self.n_subdomains)
        self.bin_area[self.cell_bin] = self.cell_area
        self.bin_slide[self.cell_bin] = self.cell_slide
        # the fibre field exposes fibres later, so rule 7 is checked even with none yet
        self.rule7_on = bool(np.isfinite(self.fibre_floor).any()) or self.fibres is not None
        self.exposed = np.zeros(0, dtype=np.int64)  # the fibre field's scratch, made on use
        self.mark = np.zeros(n, dtype=np.int8)
        self.prof = np.zeros(K.N_TIMED, dtype=np.int64)  # cycles per kernel phase (profiling)
        # lazy kernel counters: solves that walked, walk steps, envelope iterations, jumps,
        # cycles in the envelope iteration, cycles in the walk, exact-scan fallbacks
        self.lazy_walk = np.zeros(8)
        self.heap_keys = np.zeros(4 * n + 8)
        self.heap_vals = np.zeros(4 * n + 8, dtype=np.int64)
        self.cand = np.zeros(n, dtype=np.int8)
        self.ncand = np.zeros(self.n_radial * self.n_subdomains, dtype=np.int64)
        self.cmax = np.zeros(self.n_radial * self.n_subdomains)
        self.rule4_list = np.zeros(n, dtype=np.int64)
        self.cnt = np.zeros(K.N_CNT, dtype=np.int64)
        self.resync()

    def array(self, name: str) -> np.ndarray:
        """A state array by name; ``pk_h``, ``pk_base``, ``pk_idx``, ``pk_bin`` and ``pk_st``
        are the fields of the packed plateau records."""
        if name in _PACKED_FIELDS:
            return self.pk[_PACKED_FIELDS[name]]
        return getattr(self, name)

    @classmethod
    def from_surface(cls, surface: Surface, grid: Grid) -> SimulationState:
        """Initial state of a fresh pad surface on ``grid``."""
        n_r, n_t = surface.height.shape
        n_sub = grid.n_subdomains
        rows = np.repeat(np.arange(n_r), n_t)
        cols = np.tile(np.arange(n_t), n_r)
        height = np.ascontiguousarray(surface.height, dtype=np.float64).ravel().copy()
        fibres = surface.field
        if fibres is not None:
            fibres = dataclasses.replace(fibres, next=fibres.next.copy())
        return cls(
            height=height,
            base=height.copy(),
            status=np.ascontiguousarray(surface.status, dtype=np.int8).ravel().copy(),
            fibre_floor=np.ascontiguousarray(surface.fibre_floor, dtype=np.float64).ravel().copy(),
            inflow=np.zeros(n_r * n_sub),
            outflow=np.zeros(n_r * n_sub),
            acc=np.zeros(K.N_ACC),
            cell_area=np.asarray(grid.cell_area, dtype=np.float64)[rows],
            cell_slide=np.asarray(grid.step_sliding_distance, dtype=np.float64)[rows],
            cell_bin=(rows * n_sub + cols // grid.columns_per_subdomain).astype(np.int64),
            n_radial=n_r,
            n_angular=n_t,
            n_subdomains=n_sub,
            fibres=fibres,
        )

    def resync(self) -> None:
        """Rebuild every derived structure from heights and statuses: the plateau order
        (stable sort, highest first), the resin heap, the creation candidates, the areas and
        held volume, and a rule-4 check of every secondary plateau at the next step."""
        plateau = np.flatnonzero(self.status != NONE)
        ranked = plateau[np.argsort(-self.height[plateau], kind="stable")]
        K.pack_plateaus(
            ranked,
            ranked.size,
            self.pk,
            self.height,
            self.base,
            self.cell_bin,
            self.status,
            self.cnt,
        )
        self.packed_stale = False
        K.heap_rebuild(self.heap_keys, self.heap_vals, self.cnt, self.status, self.height)
        K.rebuild_candidates(
            self.status,
            self.height,
            self.cand,
            self.ncand,
            self.cmax,
            self.cell_bin,
            self.n_angular,
        )
        secondary = np.flatnonzero(self.status == SECONDARY)
        self.rule4_list[: secondary.size] = secondary
        self.cnt[K.CNT_RULE4] = secondary.size
        self.acc[K.ACC_HELD] = self.held_volume()
        self.acc[K.ACC_PRIMARY_AREA] = float(self.cell_area[self.status == 1].sum())
        self.acc[K.ACC_SECONDARY_AREA] = float(self.cell_area[secondary].sum())

    def held_volume(self) -> float:
        """Volume held in secondary plateaus, summed from the state [m^3]."""
        sec = self.status == SECONDARY
        return float(np.sum((self.height[sec] - self.base[sec]) * self.cell_area[sec]))


@dataclass
class StopLog:
    """What a run keeps of its finished stops: per stop, the reductions of the per-step
    records and the records of the steps the per-step series keeps
    (:func:`brakeca.results.summarise_stop`), the step durations [s], the volume flushed at
    the end of the stop [m^3], the secondary plateaus rule S removed, the rule counts, and
    with the fibre field what the exposure after the stop did; the maps kept after stops."""

    summaries: list[np.ndarray]
    kept: list[np.ndarray]
    dts: list[np.ndarray]
    flush: list[float]
    s_removed: list[int]
    rule_counts: list[np.ndarray]
    exposures: list[Exposure] = field(default_factory=list)
    #: stop -> (statuses [-], heights [m]) after it, for the stops that
    #: :func:`brakeca.simulation.simulate`'s ``maps_at`` asks for
    maps: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
