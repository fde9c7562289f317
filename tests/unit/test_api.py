"""The top-level names of ``import brakeca``: imported on first use, the same objects as the
submodules'."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

import brakeca


def test_import_brakeca_stays_cheap():
    code = "import sys, brakeca; print(sorted({'numba', 'xarray', 'pandas'} & set(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


@pytest.mark.parametrize("name", sorted(brakeca._EXPORTS))
def test_each_top_level_name_is_the_submodules_object(name):
    module = importlib.import_module(brakeca._EXPORTS[name])
    assert getattr(brakeca, name) is getattr(module, name)
    assert name in brakeca.__all__ and name in dir(brakeca)


def test_all_names_the_exports():
    assert sorted(brakeca.__all__) == sorted(["__version__", *brakeca._EXPORTS])


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'simulation_config'"):
        brakeca.simulation_config  # noqa: B018


@pytest.mark.parametrize("config", [{"WP": 1e-13}, "paper", None])
def test_simulate_says_what_a_config_is(config):
    """simulate({'WP': 1e-13}) or simulate('paper') raised AttributeError: 'dict' object has
    no attribute 'mesh' (a second review)."""
    from brakeca.simulation import simulate

    with pytest.raises(TypeError, match=r"config must be a SimulationConfig \(e.g. brakeca"):
        simulate(config, seed=1)
