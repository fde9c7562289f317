"""Shared fixtures: small configurations that run in a second."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))  # for tests/naive.py

from brakeca.config import BrakeBlock, CycleConfig
from brakeca.presets import load_preset


def short_cycle(stops: int = 3, v0: float = 11.0, v1: float = 10.0, g: float = 0.3) -> dict:
    """A cycle of a few short stops, as a dict for with_updates."""
    block = BrakeBlock(
        name="test", initial_speed_kmh=v0, final_speed_kmh=v1, deceleration_g=g, stops=stops
    )
    return CycleConfig(name="test", blocks=(block,)).model_dump()


@pytest.fixture
def tiny_config():
    """8 x 60 cells, 6 subdomains, three short stops."""
    return load_preset("paper").with_updates(
        {"mesh.n_radial": 8, "mesh.n_angular": 60, "mesh.n_subdomains": 6, "cycle": short_cycle()}
    )
