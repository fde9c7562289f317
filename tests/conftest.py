"""Shared fixtures: small configurations that run in a second."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import settings

sys.path.insert(0, str(Path(__file__).parent))  # for tests/naive.py

from brakeca.config import BrakeBlock, CycleConfig
from brakeca.presets import load_preset

_pytest_approx = pytest.approx


def _approx(expected, rel=None, abs=None, nan_ok=False):
    """``pytest.approx`` without its default absolute tolerance of 1e-12, which accepts
    anything for the volumes of this model (1e-10 m³ per stop and less: a V 3 % off had
    passed a comparison "to 1e-9"; a helper's audit of the tests). The relative tolerance
    is pytest's (1e-6) unless given; a test that wants an absolute one gives ``abs``, alone
    (then only it counts, as in pytest) or with ``rel`` (either)."""
    if abs is not None:
        return _pytest_approx(expected, rel=rel, abs=abs, nan_ok=nan_ok)
    return _pytest_approx(expected, rel=1e-6 if rel is None else rel, abs=0.0, nan_ok=nan_ok)


pytest.approx = _approx

# Hypothesis: the same examples on every run, and no example database in the repository (a
# tests review: .hypothesis/ grew in the checkout, and a run's examples were its own). Set
# HYPOTHESIS_PROFILE=explore for fresh random examples each run. Its other files (caches)
# go to the temporary folder, not the checkout.
os.environ.setdefault(
    "HYPOTHESIS_STORAGE_DIRECTORY", os.path.join(tempfile.gettempdir(), "brakeca-hypothesis")
)
settings.register_profile("brakeca", derandomize=True, database=None)
settings.register_profile("explore", database=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "brakeca"))


def short_cycle(stops: int = 3, v0: float = 11.0, v1: float = 10.0, g: float = 0.3) -> dict:
    """A cycle of a few short stops, as a dict for with_updates."""
    block = BrakeBlock(
        name="test", initial_speed_kmh=v0, final_speed_kmh=v1, deceleration_g=g, stops=stops
    )
    return CycleConfig(name="test", blocks=(block,)).model_dump()


def resumable_config(stops: int, removal: float = 0.5):
    """A 4 x 200 band at WP = 1e-13 and A = 10 % with ``stops`` short stops (30 to 4 km/h
    at 0.3 g) and S = ``removal``: a run that wears and builds secondary plateaus (some 150
    at each stop's end) in a second, to kill and resume; rule S then draws from the run's
    generator (at A = 20 % no secondary plateau formed, so a resume that lost the generator's
    state went unnoticed: a test-suite audit)."""
    return load_preset().with_updates(
        {
            "mesh.n_radial": 4,
            "mesh.n_angular": 200,
            "WP": 1e-13,
            "A": 10,
            "S": removal,
            "cycle": short_cycle(stops=stops, v0=30, v1=4, g=0.3),
        }
    )


@pytest.fixture
def tiny_config():
    """8 x 60 cells, 6 subdomains, three short stops."""
    return load_preset("paper").with_updates(
        {"mesh.n_radial": 8, "mesh.n_angular": 60, "mesh.n_subdomains": 6, "cycle": short_cycle()}
    )


#: The test files that take longest on two cores, longest first (a review of the suite's
#: time). The whole suite (scripts/test) hands whole files to its processes in collection
#: order (--dist loadfile --no-loadscope-reorder), so these go first and the processes end
#: together; by default pytest-xdist would hand out the files with the most tests first,
#: leaving a long file of three tests to run alone at the end. A file not listed keeps its
#: place after them.
LONGEST_FIRST = (
    "integration/test_study_cli.py",
    "integration/test_campaign.py",
    "integration/test_fractional_campaign.py",
    "integration/test_dask.py",
    "verification/test_kernel_vs_naive.py",
    "integration/test_campaign_maps.py",
    "integration/test_composite_campaign.py",
    "unit/test_power.py",
    "integration/test_warmup.py",
    "verification/test_lazy.py",
    "integration/test_examples.py",
    "unit/test_plotting.py",
)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The files of :data:`LONGEST_FIRST` first, in its order; the rest, and the tests within
    each file, in their order (a stable sort)."""
    here = Path(__file__).parent
    rank = {name: k for k, name in enumerate(LONGEST_FIRST)}

    def place(item: pytest.Item) -> int:
        try:
            name = item.path.relative_to(here).as_posix()
        except ValueError:  # (a test outside tests/)
            return len(rank)
        return rank.get(name, len(rank))

    items.sort(key=place)
