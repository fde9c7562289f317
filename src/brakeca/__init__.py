"""brakeca: cellular-automaton simulation of brake pad friction, wear and wear emissions.

Implements the simplified cellular-automaton model of

    J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad
    Properties on Friction and Wear Emissions", Advances in Tribology, 2016,
    Article ID 8181260. doi:10.1155/2016/8181260

The names most scripts need are available here, imported on first use (so that
``import brakeca`` stays cheap)::

    import brakeca

    config = brakeca.load_preset("paper").with_updates({"WP": 1e-13, "A": 10})
    run = brakeca.simulate(config, seed=3)              # a RunResult: run.MU, run.V, run.dataset
    study = brakeca.run_campaign("paper", "study", quick=True, workers=2)
    brakeca.write_study(study)                          # tables, figures, study/report.html

Everything else lives in the submodules (``brakeca.config``, ``brakeca.design``,
``brakeca.campaign``, ``brakeca.analysis``, ``brakeca.plotting``, ...).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

#: Public name -> the submodule that defines it (imported when the name is first used).
_EXPORTS = {
    "ConfigError": "brakeca.config",
    "SimulationConfig": "brakeca.config",
    "load_config": "brakeca.config",
    "load_preset": "brakeca.presets",
    "load_cycle": "brakeca.presets",
    "simulate": "brakeca.simulation",
    "RunResult": "brakeca.results",
    "load_design": "brakeca.design",
    "quick_config": "brakeca.design",
    "UnitWarning": "brakeca.config",
    "run_campaign": "brakeca.campaign",
    "load_campaign": "brakeca.campaign",
    "finish_campaign": "brakeca.campaign",
    "make_executor": "brakeca.campaign",
    "analyze": "brakeca.analysis",
    "write_study": "brakeca.study",
    "plot_run": "brakeca.study",
}

__all__ = [  # __version__ and _EXPORTS's names, spelled out for linters
    "ConfigError",
    "RunResult",
    "SimulationConfig",
    "UnitWarning",
    "__version__",
    "analyze",
    "finish_campaign",
    "load_campaign",
    "load_config",
    "load_cycle",
    "load_design",
    "load_preset",
    "make_executor",
    "plot_run",
    "quick_config",
    "run_campaign",
    "simulate",
    "write_study",
]

if TYPE_CHECKING:  # for type checkers and editors; at run time __getattr__ imports
    from brakeca.analysis import analyze
    from brakeca.campaign import finish_campaign, load_campaign, make_executor, run_campaign
    from brakeca.config import ConfigError, SimulationConfig, UnitWarning, load_config
    from brakeca.design import load_design, quick_config
    from brakeca.presets import load_cycle, load_preset
    from brakeca.results import RunResult
    from brakeca.simulation import simulate
    from brakeca.study import plot_run, write_study


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'brakeca' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
