"""The examples run (on a tiny band, as their --tiny option) and give what they print."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

EXAMPLES = Path(__file__).parents[2] / "examples"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def test_the_response_surface_example_runs(tmp_path, capsys, monkeypatch) -> None:
    # its own default folder, apart from the quick variant's (whose runs are of another
    # band: one folder for both refused the second as another study)
    monkeypatch.chdir(tmp_path)
    out = _load("response_surface").main(["--tiny"])
    assert out["figures"] == Path("examples_out/response_surface_tiny/example_figures")
    assert set(out["fits"]) == {"MU", "log10_V_mm3"}
    assert 0.0 <= out["optimum"].composite <= 1.0
    for name in ("surface_MU.png", "surface_log10_V_mm3.png", "overlaid_contours.png"):
        assert (out["figures"] / name).is_file()
    printed = capsys.readouterr().out
    assert printed.startswith("central composite design (face-centred, α = 1), 3 factors")
    assert "composite desirability:" in printed
