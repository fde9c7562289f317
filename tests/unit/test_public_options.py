"""Public options that no other test passed (a review of the API's options): the Box-Cox
results of the "In short" lines (``box_cox``), ``block_trace``'s shape of the trace,
``brake_work``'s integration step, ``level_comparisons``' ANOVA type, ``model_matrix``'s
interactions and ``load_cycle_events``' speed unit and trace configuration; each against a
closed form, an independent computation or the documented behaviour."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pandas as pd
import pytest

from brakeca.analysis import Factor, level_comparisons, model_matrix
from brakeca.boxcox import BoxCox
from brakeca.config import ConfigError
from brakeca.cycle import KMH, Stop
from brakeca.presets import load_preset
from brakeca.report import all_findings, in_short
from brakeca.traces import (
    MPH,
    BrakingEvent,
    TraceCycleConfig,
    block_trace,
    brake_work,
    detect_events,
    load_cycle_events,
)

NO_CORR = TraceCycleConfig.no_corrections()

S = Factor("S", (0.0, 1.0), "-", labels=("-", "+"))
WP = Factor("WP", (1e-15, 1e-14, 1e-13), "m^3/(N m)", labels=("-", "0", "+"))
A = Factor("A", (10.0, 20.0), "%", labels=("-", "+"))
FACTORS = (S, WP, A)


def _unbalanced_runs() -> pd.DataFrame:
    """S x WP x A (2 x 3 x 2), two replicates, four runs of different cells dropped: every
    cell has a run, the design is not balanced."""
    rng = np.random.default_rng(11)
    rows = []
    for _ in range(2):
        for s, wp, a in itertools.product(S.levels, WP.levels, A.levels):
            i = WP.levels.index(wp)
            mu = (
                0.3
                + 0.02 * s
                + 0.03 * i
                + 0.01 * (a == 20.0)
                + 0.02 * (i == 2) * (a == 20.0)
                + 0.015 * (s == 1.0) * (a == 20.0) * (i == 1)
                + 0.01 * rng.standard_normal()
            )
            rows.append({"S": s, "WP": wp, "A": a, "MU": mu, "status": "ok"})
    return pd.DataFrame(rows).drop(index=[0, 5, 14, 21]).reset_index(drop=True)


def _coded(runs: pd.DataFrame) -> pd.DataFrame:
    """The runs with each factor's level as its index (for statsmodels' formulas)."""
    return runs.assign(**{f.name: runs[f.name].map(f.levels.index) for f in FACTORS})


# --- box_cox (brakeca.report.in_short, all_findings) ------------------------------------------


def _box_cox(response: str, lam: float, low: float, high: float, **more) -> BoxCox:
    """A Box-Cox result with the given λ̂ and interval (Montgomery's as given in ``more``)."""
    profile = pd.DataFrame(
        {"lam": pd.Series(dtype=float), "log_likelihood": pd.Series(dtype=float)}
    )
    return BoxCox(response, 30, 27.0, "", lam, low, high, round(2 * lam) / 2, 0.95, profile, **more)


def test_in_short_box_cox_clauses_follow_the_documented_reading() -> None:
    """``box_cox=`` adds V's scale clause only where the interval leaves out λ = 1 and holds
    λ = 0 (pointing to the log10_V_mm3 line, or saying Montgomery's interval holds λ = 1),
    MU's also where it holds neither, and passes through all_findings unchanged."""
    frame = pd.DataFrame(
        {
            "term": ["A", "Residual"],
            "p_value": [1e-4, math.nan],
            "percent_contribution": [90.0, 10.0],
        }
    )
    tables = {"V": frame, "log10_V_mm3": frame, "MU": frame}
    plain = in_short(tables)
    log_v = _box_cox("V", 0.05, -0.1, 0.2, ci_low_df=-0.15, ci_high_df=0.25)
    neither = _box_cox("MU", -1.43, -1.9, -0.6, ci_low_df=-2.0, ci_high_df=-0.4)
    said = in_short(tables, box_cox={"V": log_v, "MU": neither})
    assert said[0] == plain[0] + (
        "; Box-Cox puts V's λ at 0.05 (95 % interval -0.10 to 0.20), which holds the log and "
        "not V as it is: read the log10_V_mm3 line"
    )
    assert said[1] == plain[1]  # log10_V_mm3 has no scale clause
    assert said[2] == plain[2] + (
        "; Box-Cox puts MU's λ at -1.43 (95 % interval -1.90 to -0.60), which holds neither MU "
        "as it is nor its log (the report analyses MU as it is)"
    )
    # Montgomery's wider interval holds λ = 1: the data do not settle the scale
    (unsettled,) = in_short(
        {"V": frame},
        box_cox={"V": _box_cox("V", 0.05, -0.1, 0.2, ci_low_df=-0.3, ci_high_df=1.2)},
    )
    assert unsettled.endswith(
        "which holds the log and not V as it is, but with 27 residual degrees of freedom "
        "Montgomery's wider interval (-0.30 to 1.20) holds λ = 1 too: the data do not settle "
        "V's scale"
    )
    # nothing where λ = 1 is held, nor for V's interval that holds neither 1 nor 0
    holds_one = _box_cox("V", 0.6, 0.1, 1.1, ci_low_df=0.0, ci_high_df=1.2)
    v_neither = _box_cox("V", -1.43, -1.9, -0.6, ci_low_df=-2.0, ci_high_df=-0.4)
    for silent in (holds_one, v_neither):
        assert in_short(tables, box_cox={"V": silent}) == plain
    assert all_findings(tables, box_cox={"V": log_v, "MU": neither}) == said


# --- block_trace ------------------------------------------------------------------------------


def test_block_trace_options_shape_the_trace_in_closed_form() -> None:
    """acceleration, coast, cruise, dwell, sample_interval and name: the trace passes through
    the closed-form knots, with ceil(duration / sample_interval) equal intervals per segment,
    each sample labelled with its stop's block, and its events where the knots put them."""
    stops = [
        Stop(1, "A", 20.0, 10.0, 2.0),
        Stop(2, "B", 6.0, 0.0, 2.0),
        Stop(3, "C", 16.0, 0.0, 4.0),
    ]
    acc, coast, cruise, dwell, dt = 2.0, 0.25, 3.0, 1.5, 0.7
    trace = block_trace(
        stops,
        acceleration=acc,
        coast=coast,
        cruise=cruise,
        dwell=dwell,
        sample_interval=dt,
        name="mine",
    )
    # (duration [s], speed at its end [m/s], block) of each segment, by hand
    segments = [
        (cruise, 20.0, "A"),
        ((20.0 - 10.0) / 2.0, 10.0, "A"),
        (dwell, 10.0, "A"),
        ((10.0 - 6.0) / coast, 6.0, "B"),  # coasting down to B's slower brake-on speed
        (cruise, 6.0, "B"),
        (6.0 / 2.0, 0.0, "B"),
        (dwell, 0.0, "B"),
        (16.0 / acc, 16.0, "C"),  # accelerating up to C's brake-on speed
        (cruise, 16.0, "C"),
        (16.0 / 4.0, 0.0, "C"),
        (dwell, 0.0, "C"),
    ]
    knot_t = np.concatenate(([0.0], np.cumsum([d for d, _, _ in segments])))
    knot_v = np.array([20.0] + [v for _, v, _ in segments])
    assert (trace.name, trace.source) == ("mine", "mine (built from block stops)")
    assert trace.time.size == 1 + sum(math.ceil(d / dt - 1e-9) for d, _, _ in segments)
    assert trace.time[-1] == pytest.approx(knot_t[-1], rel=1e-12)
    assert np.diff(trace.time).max() <= dt * (1 + 1e-12)
    for t in knot_t:  # a sample at every knot
        assert np.min(np.abs(trace.time - t)) <= 1e-12 * knot_t[-1]
    np.testing.assert_allclose(trace.speed, np.interp(trace.time, knot_t, knot_v), atol=1e-12)
    # a sample belongs to the stop its segment leads to (t = 0 to the first)
    seg = np.clip(np.searchsorted(knot_t, trace.time, side="left") - 1, 0, len(segments) - 1)
    assert list(trace.trip) == [segments[k][2] for k in seg]
    events = detect_events(trace, config=NO_CORR)  # coasting at 0.25 m/s² is not braking
    assert [e.block for e in events] == ["A", "B", "C"]
    ons = [knot_t[1], knot_t[5], knot_t[9]]
    offs = [knot_t[2], knot_t[6], knot_t[10]]
    for e, on, off in zip(events, ons, offs, strict=True):
        assert (e.start_time, e.end_time) == (pytest.approx(on), pytest.approx(off))


# --- brake_work(step=) ------------------------------------------------------------------------


def test_brake_work_step_against_closed_forms_with_drag() -> None:
    """With a drag road load (speed-dependent) the work depends on ``step``: one step over the
    whole event takes the drag at its mean speed, two steps at theirs, a fine step tends to
    the integral m (a d - k ∫ v² dx); a block stop is exact whatever the step."""
    m, v0, a = 500.0, 20.0, 5.0  # 20 -> 0 m/s in 4 s over d = 40 m
    corrections = TraceCycleConfig.no_corrections(drag_area=1.0, vehicle_mass=100.0)
    k = corrections.air_density * 1.0 / (2 * 100.0)  # drag per v² [1/m]
    event = BrakingEvent(1, "x", time=[0.0, 4.0], speed=[v0, 0.0], corrections=corrections)
    d = v0**2 / (2 * a)
    assert event.distance == pytest.approx(d, rel=1e-12)
    one = m * (a - k * (v0 / 2) ** 2) * d  # the step's mean speed v0 / 2
    v1 = math.sqrt(v0**2 - 2 * a * d / 2)  # the speed halfway
    two = m * (d / 2) * ((a - k * ((v0 + v1) / 2) ** 2) + (a - k * (v1 / 2) ** 2))
    exact = m * (a * d - k * (v0**2 * d - a * d**2))  # ∫ v² dx, v² = v0² - 2 a x
    assert brake_work([event], m, step=2 * d) == pytest.approx(one, rel=1e-12)
    assert brake_work([event], m, step=d / 2) == pytest.approx(two, rel=1e-12)
    assert brake_work([event], m, step=d / 4000) == pytest.approx(exact, rel=1e-6)
    assert brake_work([event], m) == brake_work([event], m, step=0.05)  # the default
    assert abs(one - exact) > 0.1 * exact  # the cases tell the steps apart
    stop = Stop(1, "b", v0, 0.0, a)
    assert brake_work([stop], m, step=2 * d) == pytest.approx(m * a * d, rel=1e-12)
    assert brake_work([stop], m, step=d / 7) == brake_work([stop], m, step=2 * d)


# --- level_comparisons(typ=) -----------------------------------------------------------------


def test_level_comparisons_typ_follows_statsmodels_anova_types() -> None:
    """In an unbalanced design with the three-factor interaction, WP:A's p differs between
    Type II and III (statsmodels' anova_lm, treatment and sum coding); at a confidence
    between them only the type whose p lies below 1 - confidence names WP:A in the note.
    The least-squares means and differences do not depend on the type; "III" is 3."""
    import statsmodels.formula.api as smf
    from statsmodels.stats.anova import anova_lm

    runs = _unbalanced_runs()
    data = _coded(runs)
    p2 = anova_lm(smf.ols("MU ~ C(S) * C(WP) * C(A)", data).fit(), typ=2)
    p3 = anova_lm(smf.ols("MU ~ C(S, Sum) * C(WP, Sum) * C(A, Sum)", data).fit(), typ=3)
    p_ii = float(p2.loc["C(WP):C(A)", "PR(>F)"])
    p_iii = float(p3.loc["C(WP, Sum):C(A, Sum)", "PR(>F)"])
    assert abs(math.log(p_ii / p_iii)) > 0.1  # the types differ here
    confidence = 1.0 - math.sqrt(p_ii * p_iii)  # alpha between them
    tables = {
        typ: level_comparisons(runs, FACTORS, "MU", interactions=3, typ=typ, confidence=confidence)
        for typ in (2, 3, "III")
    }
    for typ, p in ((2, p_ii), (3, p_iii)):
        named = "WP is in a significant interaction (WP:A)" in tables[typ].attrs["note"]
        assert named == (p < 1.0 - confidence), (typ, tables[typ].attrs["note"])
    columns = ["level_a", "level_b", "mean_a", "mean_b", "difference", "se", "p_adjusted"]
    pd.testing.assert_frame_equal(tables[2][columns], tables[3][columns])
    pd.testing.assert_frame_equal(tables["III"], tables[3])
    assert tables[3].attrs == tables["III"].attrs


# --- model_matrix(interactions=) --------------------------------------------------------------


def _hat(x: np.ndarray) -> np.ndarray:
    """The projection onto the columns of x."""
    return x @ np.linalg.pinv(x)


@pytest.mark.parametrize(
    ("interactions", "formula", "columns"),
    [
        (False, "C(S) + C(WP) + C(A)", 1 + 1 + 2 + 1),
        (1, "C(S) + C(WP) + C(A)", 1 + 1 + 2 + 1),
        (True, "(C(S) + C(WP) + C(A)) ** 2", 1 + 1 + 2 + 1 + 2 + 1 + 2),
        (3, "C(S) * C(WP) * C(A)", 12),
        (["S", "WP", "A", "WP*A"], "C(S) + C(WP) * C(A)", 1 + 1 + 2 + 1 + 2),
    ],
)
def test_model_matrix_interactions_span_the_formulas_columns(
    interactions, formula, columns
) -> None:
    """The model matrix has the intercept and one treatment-coded column per estimable
    effect of the terms ``interactions`` asks for, spanning the same space as the model
    matrix of the formula that states them (statsmodels/patsy), so the fits agree; a failed
    run is left out."""
    import statsmodels.formula.api as smf

    runs = _unbalanced_runs()
    runs.loc[3, "status"] = "failed"
    exog = model_matrix(runs, FACTORS, "MU", interactions=interactions)
    usable = _coded(runs[runs["status"] == "ok"])
    reference = smf.ols(f"MU ~ {formula}", usable).fit().model.exog
    assert exog.shape == (len(usable), columns) == reference.shape
    np.testing.assert_array_equal(exog[:, 0], 1.0)
    assert np.linalg.matrix_rank(exog) == columns
    np.testing.assert_allclose(_hat(exog), _hat(reference), atol=1e-9)


# --- load_cycle_events(trace_config, speed_unit) -------------------------------------------------


def test_load_cycle_events_speed_unit_and_trace_config(tmp_path) -> None:
    """A trace whose header states no unit is read in ``speed_unit`` (60 -> 0 in 10 s is
    16.7 m/s at 1.67 m/s² in km/h, 26.8 m/s at 2.68 m/s² in mph); ``trace_config``'s
    threshold decides which unit's braking is an event, and its brake share scales the brake
    work; a speed unit for a block cycle is refused."""
    path = tmp_path / "trace.csv"
    path.write_text("time_s,speed\n0,0\n10,60\n20,60\n30,0\n35,0\n", encoding="utf-8")
    config = load_preset("paper")
    for unit, factor in (("km/h", KMH), ("mph", MPH)):
        (event,) = load_cycle_events(path, config, NO_CORR, speed_unit=unit)
        assert (event.start_time, event.end_time) == (20.0, 30.0)
        assert event.initial_speed == pytest.approx(60 * factor, rel=1e-12)
        assert event.final_speed == 0.0
        assert event.deceleration == pytest.approx(6 * factor, rel=1e-12)
        assert event.distance == pytest.approx(0.5 * 60 * factor * 10, rel=1e-12)
    # a threshold of 2 m/s² lies between the two units' decelerations
    strict = TraceCycleConfig.no_corrections(threshold=2.0)
    assert load_cycle_events(path, config, strict, speed_unit="km/h") == []
    assert len(load_cycle_events(path, config, strict, speed_unit="mph")) == 1
    # the brake takes c phi_f / psi_f of the vehicle's deceleration (no road load)
    half = TraceCycleConfig.no_corrections(friction_share=0.5)
    events = load_cycle_events(path, config, half, speed_unit="mph")
    assert events[0].corrections == half
    assert brake_work(events, 400.0) == pytest.approx(0.5 * 0.5 * 400.0 * (60 * MPH) ** 2)
    with pytest.raises(ConfigError, match="is a block cycle"):
        load_cycle_events("paper", config, speed_unit="mph")
    with pytest.raises(ConfigError, match="states no unit"):
        load_cycle_events(path, config, NO_CORR)
