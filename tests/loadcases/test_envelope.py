"""Envelope extraction against hand-made result tables; curves on grids; margins."""

from __future__ import annotations

import math

import numpy as np
import pytest

from loadcases.report.curves import envelope_curves, envelope_on_grid
from loadcases.report.envelope import extract_envelope
from loadcases.report.margins import apply_margins, margin
from loadcases.results.saved import SavedRun

NAN = math.nan


def run(name: str, time: list[float], **channels: list[float]) -> SavedRun:
    return SavedRun(
        name,
        np.array(time),
        {k.replace("__", "."): np.array(v, dtype=float) for k, v in channels.items()},
        units={"h.fx": "N", "h.fy": "N", "abscissa.value": "rad"},
    )


def test_max_min_with_run_time_abscissa_and_concurrent_values() -> None:
    a = run("a", [0, 1, 2], h__fx=[1, 5, 2], h__fy=[0, -3, 7], abscissa__value=[0, 0.5, 1])
    b = run("b", [0, 1, 2], h__fx=[-4, 0, 3], h__fy=[1, 1, 1], abscissa__value=[0, 0.2, 0.4])
    rows = {r.column: r for r in extract_envelope([a, b])}
    fx = rows["h.fx"]
    assert (fx.max, fx.max_run, fx.max_time, fx.max_abscissa) == (5.0, "a", 1.0, 0.5)
    assert (fx.min, fx.min_run, fx.min_time, fx.min_abscissa) == (-4.0, "b", 0.0, 0.0)
    assert fx.max_concurrent == "fy=-3.0" and fx.min_concurrent == "fy=1.0"
    assert fx.abs_max == 5.0 and fx.unit == "N"


def test_ties_keep_the_first_run_and_the_earliest_time() -> None:
    a = run("a", [0, 1, 2], h__fx=[2, 2, 1])
    b = run("b", [0, 1, 2], h__fx=[2, 0, 2])
    fx = extract_envelope([a, b])[0]
    assert (fx.max_run, fx.max_time) == ("a", 0.0)
    fx = extract_envelope([b, a])[0]
    assert (fx.max_run, fx.max_time, fx.min_run, fx.min_time) == ("b", 0.0, "b", 1.0)


def test_nan_rows_of_a_failed_run_are_skipped() -> None:
    ok = run("ok", [0, 1, 2], h__fx=[1, 2, 3])
    failed = run("failed", [0, 1, 2], h__fx=[NAN, 9, NAN])
    empty = run("empty", [0, 1], h__fx=[NAN, NAN])
    fx = extract_envelope([empty, failed, ok])[0]
    assert (fx.max, fx.max_run, fx.min, fx.min_run) == (9.0, "failed", 1.0, "ok")
    assert extract_envelope([empty])[0].max is None


def test_single_run_set() -> None:
    fx = extract_envelope([run("only", [0.0], h__fx=[-2.0])])[0]
    assert (fx.max, fx.min, fx.max_run, fx.min_run, fx.abs_max) == (-2.0, -2.0, "only", "only", 2.0)


def test_curves_on_a_union_grid_that_does_not_line_up() -> None:
    a = run("f[p=1]", [0, 1, 2], h__fx=[0, 2, 0], abscissa__value=[0, 1, 2])
    b = run("f[p=2]", [0, 1, 2], h__fx=[1, 1, 4], abscissa__value=[0.5, 1.5, 3])
    (curve,) = envelope_curves([a, b])
    assert curve.family == "f" and curve.abscissa == "abscissa.value"
    np.testing.assert_array_equal(curve.x, [0, 0.5, 1, 1.5, 2, 3])
    np.testing.assert_allclose(curve.upper["h.fx"], [0, 1, 2, 1, 2, 4])
    np.testing.assert_allclose(curve.lower["h.fx"], [0, 1, 1, 1, 0, 4])


def test_curve_of_a_back_and_forth_abscissa_covers_every_branch() -> None:
    grid = np.array([0.0, 1.0, 2.0])
    upper, lower = envelope_on_grid([(np.array([0, 2, 0.0]), np.array([1, 1, -1.0]))], grid)
    np.testing.assert_allclose(upper, [1, 1, 1])
    np.testing.assert_allclose(lower, [-1, 0, 1])
    upper, _ = envelope_on_grid([(np.array([5.0, 6.0]), np.array([1.0, 1.0]))], grid)
    assert np.isnan(upper).all()  # outside a run's range it contributes nothing


def test_family_without_abscissa_uses_time() -> None:
    (curve,) = envelope_curves([run("g", [0, 1], h__fx=[1, 2]), run("g", [0, 0.5], h__fx=[3, 3])])
    assert curve.abscissa == "time"
    np.testing.assert_allclose(curve.upper["h.fx"], [3, 3, 2])


def test_margins_both_sides_and_negative_loads() -> None:
    rows = extract_envelope([run("a", [0, 1], h__fx=[1000, -500], h__fy=[-10, -20])])
    factors = {"ultimate": 1.5, "h.fx": 1.2}
    allowables = {"h.fx": {"max": 3600.0, "min": -1800.0}, "h.fy": {"max": 100.0}}
    fx, fy = apply_margins(rows, factors, allowables)
    assert fx.factor == pytest.approx(1.8)
    assert (fx.ultimate_max, fx.ultimate_min) == pytest.approx((1800.0, -900.0))
    assert fx.ms_max == pytest.approx(3600 / 1800 - 1) and fx.ms_min == pytest.approx(1.0)
    assert fy.ms_max is None  # never loaded towards +y: no margin on that side
    assert margin(-8000.0, 1.5, -6000.0) == pytest.approx(8000 / 9000 - 1)
    assert margin(100.0, 1.5, 0.0) is None


def test_only_load_columns_get_the_ultimate_factor() -> None:
    rows = extract_envelope([run("a", [0], h__fx=[1.0], abscissa__value=[2.0])])
    fx, x = apply_margins(rows, {"ultimate": 1.5}, {})
    assert fx.factor == 1.5 and x.factor is None and x.ultimate_max is None


def test_extreme_rows_of_all_columns_equal_extreme_row_of_each() -> None:
    """extreme_rows (every column of a run at once) gives the rows extreme_row gives column
    by column: the first largest and smallest finite value, ties to the earliest row,
    None for a column of NaN and infinities only; columns of unequal or no length too."""
    from loadcases.report.envelope import extreme_row, extreme_rows

    rng = np.random.default_rng(11)
    values = rng.normal(size=(200, 6)).round(1)  # rounding makes ties
    values[rng.random(values.shape) < 0.1] = np.nan
    values[5, 1], values[9, 2] = np.inf, -np.inf  # not finite: never an extreme
    values[:, 3] = np.nan  # no finite value
    values[:, 4] = 2.5  # all tied: row 0 both ways
    channels = {f"c{k}": values[:, k] for k in range(6)}
    found = extreme_rows(channels)
    expected = {n: (extreme_row(v, 1.0), extreme_row(v, -1.0)) for n, v in channels.items()}
    assert found == expected
    assert found["c3"] == (None, None) and found["c4"] == (0, 0)
    assert extreme_rows({"a": np.array([1.0, 3.0]), "b": np.array([2.0])}) == {
        "a": (1, 0),
        "b": (0, 0),
    }
    assert extreme_rows({"a": np.empty(0)}) == {"a": (None, None)}
    assert extreme_rows({}) == {}


def _brute_envelope(runs: list[tuple[np.ndarray, np.ndarray]], grid: np.ndarray):
    """Reference: every segment between two finite rows, every grid point in it, in plain
    Python; a run with a single finite row adds its point where the grid has it."""
    upper = [-math.inf] * grid.size
    lower = [math.inf] * grid.size
    for x, y in runs:
        ok = [i for i in range(len(x)) if math.isfinite(x[i]) and math.isfinite(y[i])]
        spans = [(i, i) for i in ok] if len(ok) == 1 else []
        spans += [(i, i + 1) for i in range(len(x) - 1) if i in ok and i + 1 in ok]
        for i, j in spans:
            lo, hi = min(x[i], x[j]), max(x[i], x[j])
            for g, at in enumerate(grid):
                if lo <= at <= hi:
                    if x[j] == x[i]:
                        top, bottom = max(y[i], y[j]), min(y[i], y[j])
                    else:
                        top = bottom = y[i] + (at - x[i]) / (x[j] - x[i]) * (y[j] - y[i])
                    upper[g], lower[g] = max(upper[g], top), min(lower[g], bottom)
    clean = [np.array([v if math.isfinite(v) else NAN for v in side]) for side in (upper, lower)]
    return clean[0], clean[1]


def test_family_curves_match_a_segment_by_segment_reference() -> None:
    """All columns of a run folded together give, column by column, the envelope of a
    plain segment-by-segment reference (1e-12): NaN and infinite values skipped, a column
    with one finite row a point, a run without a column, an abscissa going back, repeated
    abscissa values (a jump)."""
    rng = np.random.default_rng(3)
    runs = []
    for n in range(6):
        x = np.sort(rng.uniform(0, 2, 9)) if n % 2 else np.array([0, 1, 2, 1.5, 1.5, 0.2, 1, 1, 3])
        fx, fy = rng.normal(size=9), rng.normal(size=9)
        fx[rng.integers(0, 9, 2)] = [NAN, np.inf]
        if n == 2:
            fy[:] = NAN
            fy[4] = 7.0  # one finite row: a point
        channels = {"h__fx": list(fx), "abscissa__value": list(x)}
        if n != 3:  # run 3 has no h.fy
            channels["h__fy"] = list(fy)
        runs.append(run(f"f[n={n}]", list(range(9)), **channels))
    (curve,) = envelope_curves(runs)
    for column in ("h.fx", "h.fy"):
        pairs = [
            (r.channels["abscissa.value"], r.channels[column]) for r in runs if column in r.channels
        ]
        upper, lower = _brute_envelope(pairs, curve.x)
        np.testing.assert_allclose(curve.upper[column], upper, rtol=0, atol=1e-12)
        np.testing.assert_allclose(curve.lower[column], lower, rtol=0, atol=1e-12)
    assert np.isfinite(curve.upper["h.fy"]).sum() > 1
    assert 7.0 in curve.upper["h.fy"]  # the point of run 2 (the others stay below 7)
