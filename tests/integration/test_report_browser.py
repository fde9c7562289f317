"""Open the HTML report in headless Chromium: every image is present and decodes offline.

The report's inline script sets ``data-images-loaded`` on ``<body>`` to the number of images
with ``naturalWidth > 0`` once all of them have settled; ``--dump-dom`` shows it.

References
----------
Wahlström (2016), doi:10.1155/2016/8181260.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import Factor, anova, ranked_effects
from brakeca.plotting import plot_main_effects, plot_pareto, plot_surface_map
from brakeca.report import write_report

pytestmark = pytest.mark.browser

PNG = b"\x89PNG\r\n\x1a\n"
FACTORS = (
    Factor("S", (0.0, 1.0), "-", labels=("-", "+")),
    Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", labels=("-", "0", "+")),
)


def _chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        found = shutil.which(name)
        if found:
            return found
    pytest.skip("no Chromium found (looked for chromium, chromium-browser, google-chrome)")


def _run(browser: str, profile: Path, *args: str) -> subprocess.CompletedProcess[str]:
    command = [
        browser,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={profile}",
        "--virtual-time-budget=5000",
        *args,
    ]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> tuple[Path, int]:
    tmp = tmp_path_factory.mktemp("report")
    rng = np.random.default_rng(5)
    rows = [
        {
            "test": k + 1,
            "run_id": f"t{k + 1:02d}-s{seed}",
            "S": s,
            "WP": wp,
            "seed": seed,
            "MU": 0.4 + 0.02 * s + 0.003 * rng.standard_normal(),
            "V": 1e-10 * (1 + 2 * FACTORS[1].levels.index(wp)),
            "status": "ok",
        }
        for seed in (1, 2)
        for k, (wp, s) in enumerate((wp, s) for wp in FACTORS[1].levels for s in (0.0, 1.0))
    ]
    summary = pd.DataFrame(rows)
    status = (rng.random((41, 120)) < 0.2).astype(int)
    figures = [
        ("Main effects", "Main effects on MU", tmp / "me.png"),
        ("Main effects", "Pareto chart of MU", tmp / "pareto.png"),
        ("Surface", "Final plateau map", tmp / "map.png"),
    ]
    plot_main_effects(summary, FACTORS, "MU", path=figures[0][2])
    plot_pareto(ranked_effects(summary, FACTORS, "MU"), "MU", path=figures[1][2])
    plot_surface_map(
        status,
        np.linspace(0.103, 0.123, 41),
        np.radians(np.linspace(0, 44, 120)),
        "",
        figures[2][2],
    )
    path = write_report(
        tmp / "report.html",
        title="Browser check",
        design_table=summary[summary["seed"] == 1][["test", "S", "WP"]],
        summary=summary,
        anova_tables={r: anova(summary, FACTORS, r) for r in ("MU", "V")},
        figures=figures,
        config_text='name = "browser"',
        version="test",
    )
    return path, len(figures)


def test_all_images_present_and_loaded(report, tmp_path) -> None:
    browser = _chromium()
    path, n_images = report
    result = _run(browser, tmp_path / "profile", "--dump-dom", path.as_uri())
    assert result.returncode == 0, result.stderr[-2000:]
    dom = result.stdout
    assert "<h1>Browser check</h1>" in dom
    images = re.findall(r"<img\b[^>]*>", dom)
    assert len(images) == n_images
    assert all('src="data:image/png;base64,' in img for img in images)
    body = re.search(r"<body\b[^>]*>", dom)
    assert body is not None
    assert f'data-images-total="{n_images}"' in body.group(0)
    assert f'data-images-loaded="{n_images}"' in body.group(0), body.group(0)


def test_screenshot_renders(report, tmp_path) -> None:
    browser = _chromium()
    path, _ = report
    shot = tmp_path / "shot.png"
    result = _run(
        browser,
        tmp_path / "profile",
        f"--screenshot={shot}",
        "--window-size=1280,2000",
        path.as_uri(),
    )
    assert result.returncode == 0, result.stderr[-2000:]
    data = shot.read_bytes()
    assert data.startswith(PNG) and len(data) > 10_000
