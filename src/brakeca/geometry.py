"""Polar pad mesh: cell positions, areas, sliding distances and subdomains (Section 2.2, Table 5).

Rows ``j`` run outwards in radius (north), columns ``i`` run along the sliding direction (east):
a point of the disc enters the pad at column 0 (leading edge) and leaves after column
``n_angular - 1`` (trailing edge). Arrays are indexed ``[j, i]``.

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260, Section 2.2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from brakeca.config import SimulationConfig

__all__ = ["Grid", "make_grid", "status_area_fractions"]


@dataclass(frozen=True)
class Grid:
    """The polar grid of the simulated band.

    Attributes
    ----------
    radius : ndarray, shape (n_radial,)
        Row radii r_j [m].
    angle : ndarray, shape (n_angular,)
        Column angles theta_i [rad], 0 at the leading edge.
    cell_area : ndarray, shape (n_radial,)
        Cell area of each row, A_j = r_j * dtheta * dr [m^2].
    step_sliding_distance : ndarray, shape (n_radial,)
        Sliding distance of row j in one full time step, r_j * N_m * dtheta [m].
    columns_per_subdomain : int
        N_m [-].
    n_subdomains : int
        N [-].
    """

    radius: np.ndarray
    angle: np.ndarray
    cell_area: np.ndarray
    step_sliding_distance: np.ndarray
    columns_per_subdomain: int
    n_subdomains: int

    @property
    def shape(self) -> tuple[int, int]:
        """(n_radial, n_angular) [-]."""
        return (self.radius.size, self.angle.size)

    @property
    def area(self) -> float:
        """Simulated area A_sim = sum of all cell areas [m^2]."""
        return float(self.cell_area.sum() * self.angle.size)

    def cell_area_map(self) -> np.ndarray:
        """Cell areas broadcast to the grid shape [m^2]."""
        return np.broadcast_to(self.cell_area[:, None], self.shape)


def make_grid(config: SimulationConfig) -> Grid:
    """Build the grid of ``config``: radii ``r_i + j dr``, angles ``i dtheta`` (Table 5).

    Parameters
    ----------
    config
        The configuration: its mesh (``mesh.radial_step`` dr [m], ``mesh.angular_step_deg``
        [deg], the rows, columns and subdomains [-]) and its inner radius r_i [m].

    Returns
    -------
    Grid
        Radii [m], angles [rad], cell areas [m^2] and sliding distances [m] per row, all
        read-only.

    Notes
    -----
    ``r_j = r_i + j dr`` (``j = 0 ... N_r - 1``), ``theta_i = i dtheta``
    (``i = 0 ... N_theta - 1``, column 0 at the leading edge), the cell area
    ``A_j = r_j dtheta dr`` and a full step's sliding distance ``s_j = r_j N_m dtheta``, with
    ``N_m = N_theta / N`` columns per subdomain and ``dtheta`` in radians. Unless
    ``mesh.inner_radius`` is set, ``r_i = r_eff - (N_r - 1) dr / 2``, which centres the band
    on the effective radius (103 mm at Table 5's mesh; a decision, docs/model.md section 2).

    References
    ----------
    Wahlström (2016), Section 2.2 and Table 5, doi:10.1155/2016/8181260.

    Examples
    --------
    The paper's mesh (Table 5): 201 rows of 0.1 mm, 1000 columns of 0.044°, the band from
    r_i = 103 mm (centred on the effective radius: a decision, docs/model.md):

    >>> from brakeca.geometry import make_grid
    >>> from brakeca.presets import load_preset
    >>> grid = make_grid(load_preset())
    >>> grid.shape
    (201, 1000)
    >>> round(float(grid.radius[0]), 6), round(float(grid.radius[-1]), 6)  # [m]
    (0.103, 0.123)
    >>> round(float(grid.cell_area[0]) * 1e6, 6)  # r_0 dtheta dr [mm²]
    0.00791
    >>> round(grid.area * 1e6, 1)  # the band [mm²]
    1744.2
    """
    mesh = config.mesh
    dtheta = mesh.angular_step
    radius = config.inner_radius + mesh.radial_step * np.arange(mesh.n_radial)
    angle = dtheta * np.arange(mesh.n_angular)
    cell_area = radius * dtheta * mesh.radial_step
    step_sliding_distance = radius * mesh.columns_per_subdomain * dtheta
    for arr in (radius, angle, cell_area, step_sliding_distance):
        arr.setflags(write=False)
    return Grid(
        radius=radius,
        angle=angle,
        cell_area=cell_area,
        step_sliding_distance=step_sliding_distance,
        columns_per_subdomain=mesh.columns_per_subdomain,
        n_subdomains=mesh.n_subdomains,
    )


def status_area_fractions(status: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """The share of the band's area [-] each cell status covers: resin (0), primary (1) and
    secondary plateaus (2), a cell's area proportional to its row's radius.

    Parameters
    ----------
    status : ndarray, shape (n_radial, n_angular)
        Cell statuses [-].
    radius : ndarray, shape (n_radial,)
        Row radii [m] (any unit: only their ratios count).

    Returns
    -------
    ndarray, shape (3,)
        The fractions of status 0, 1 and 2 [-]; zeros for an empty band.
    """
    weights = np.broadcast_to(np.asarray(radius, dtype=float)[:, None], status.shape)
    total = weights.sum()
    if total <= 0:
        return np.zeros(3)
    return np.array([weights[status == k].sum() / total for k in range(3)])
