"""The grid companion four at a time (loadcases.run.companion.on_grid with ratio FOUR; not
the engine's default, GRID_RATIOS: measured, see companion.py): the run's own accepted
steps merged four by four, no error test, Richardson's divisor of the steps it took
(grid_divisor: 4^p - 1 = 15 a merged step of four, 3 of a stretch's leftover pair, 0 of a
single step); its estimate against a linear oscillator's closed form
x(t) = X0 cos(omega_n t); with GRID_RATIOS (FOUR, 2), the fall back to two at a time where
Newton cannot take the steps four times as long, or they do not resolve a flexible body's
modes or a one-row spike's pulse."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechlib as ml
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from loadcases.run.companion import (
    FOUR,
    grid_divisor,
    observed_order,
    on_grid,
    pulses_resolved,
    resolved,
)
from loadcases.run.global_error import shared_rows
from mechlib.solvers.genalpha import rules
from tests.loadcases.test_grid_companion import OMEGA_N, PENDULUM, X0, _solved


def test_fours_keep_stops_as_step_ends_and_end_a_stretch_with_its_leftovers() -> None:
    """Steps ending at 1..11 s, an event at 5 s: (1-4) (5) | (6-9) (10, 11): a stretch's
    leftovers of fewer than four merged two at a time, an odd one single."""
    steps = [float(k) for k in range(1, 12)]
    grid = ml.StepGrid.grouped(steps, stops=[5.0], ratio=4)
    np.testing.assert_array_equal(grid.ends, [4.0, 5.0, 9.0, 11.0])
    np.testing.assert_array_equal(grid.middles, [2.0, np.nan, 7.0, 10.0])
    three = ml.StepGrid.grouped([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0], ratio=4)
    np.testing.assert_array_equal(three.ends, [4.0, 6.0, 7.0])
    np.testing.assert_array_equal(three.middles, [2.0, 5.0, np.nan])
    with pytest.raises(ValueError, match="2 or 4"):
        ml.StepGrid.grouped(steps, ratio=3)


def test_a_split_step_of_four_goes_to_its_middle_then_on() -> None:
    """Newton failing on a step of four of the run's: two steps of two (rules.on_grid)."""
    grid = ml.StepGrid.grouped([1.0, 2.0, 3.0, 4.0], ratio=4)
    assert rules.on_grid(0.0, 9.0, grid.ends, grid.middles, False) == 4.0
    assert rules.on_grid(0.0, 9.0, grid.ends, grid.middles, True) == 2.0
    assert rules.on_grid(2.0, 9.0, grid.ends, grid.middles, False) == 2.0


def test_the_divisor_counts_the_run_steps_each_companion_step_merged() -> None:
    """Mean over the run's steps of m^p - 1 (p = 2): all fours 15; fours with a split (two
    steps of two) and a leftover single; the pairs' 3; a companion of the run's own steps 0."""
    run = [float(k) for k in range(1, 13)]
    assert grid_divisor("generalized-alpha", run, [4.0, 8.0, 12.0]) == pytest.approx(15.0)
    # 1-4 a four, 5-6 and 7-8 a split four, 9-11 a leftover pair and single, 12 single
    taken = [4.0, 6.0, 8.0, 10.0, 11.0, 12.0]
    expected = (4 * 15 + 3 * 2 * 3 + 0 + 0) / 12
    assert grid_divisor("generalized-alpha", run, taken) == pytest.approx(expected)
    assert grid_divisor("generalized-alpha", run, run[1::2]) == pytest.approx(3.0)
    assert grid_divisor("generalized-alpha", run, run) == 0.0


@pytest.mark.parametrize("ratio", [2, 4])
def test_the_observed_order_of_errors_of_order_two(ratio: int) -> None:
    """Errors C h^p, p = 2, at h/2, h and ratio h: the observed order reads 2."""
    error = {h: 0.3 * h**2 for h in (0.5, 1.0, float(ratio))}
    coarse, fine = error[float(ratio)] - error[1.0], error[1.0] - error[0.5]
    assert observed_order(coarse, fine, ratio) == pytest.approx(2.0, abs=1e-12)
    assert observed_order(0.0, fine, ratio) is None


@pytest.mark.parametrize(("tolerance", "low", "high"), [(1e-5, 0.78, 0.86), (1e-7, 0.91, 0.99)])
def test_four_at_a_time_estimates_the_oscillators_error(
    tolerance: float, low: float, high: float
) -> None:
    """|run - companion| / grid_divisor against the closed form's largest error over the
    run's rows: within [1/3, 3] (the issue's factor), and guarded at the measured ratios
    (2026-11-30, branch grid4): 0.816 at tolerance 1e-5 (91 steps, the companion's 24,
    divisor 14.57), 0.855 at 1e-6, 0.948 at 1e-7 (divisor 14.96), nearing 1 as the steps
    shrink (Richardson's asymptotics); two at a time read 0.898, 0.941, 0.984."""
    analysis = ml.Dynamic(1.0, 0.001, dense=True, tolerance=tolerance)
    run = _solved(analysis)
    companion_analysis = on_grid(analysis, run, FOUR)
    assert companion_analysis is not None and companion_analysis.grid is not None
    assert companion_analysis.grid.ratio == 4
    companion = _solved(companion_analysis)
    assert companion.ok and companion.stats.rejected_steps == 0
    assert companion.stats.steps == companion_analysis.grid.steps <= math.ceil(run.stats.steps / 3)
    rows, rows_c = shared_rows(run.time, companion.time)
    x = run.channels["x.value"]
    difference = np.abs(x[rows] - companion.channels["x.value"][rows_c]).max()
    estimate = difference / grid_divisor(
        "generalized-alpha", run.stats.step_ends, companion.stats.step_ends
    )
    true = np.abs(x - X0 * np.cos(OMEGA_N * run.time)).max()
    assert 1 / 3 <= estimate / true <= 3
    assert low <= estimate / true <= high


def test_newton_failing_on_steps_four_times_as_long_falls_back_to_two_at_a_time(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The four-at-a-time grid stops (no split allowed, Newton's first step fails, made
    so): the estimate is made two at a time, with Richardson's 2^p - 1 of its steps, and
    the summary says which and why."""
    from loadcases.run import global_error
    from mechlib.solvers.genalpha.stepper import GeneralizedAlphaStepper

    on_grid_of = global_error.on_grid

    def strict_fours(analysis: ml.Dynamic, run: ml.Solution, ratio: int) -> ml.Dynamic | None:
        grid = on_grid_of(analysis, run, ratio)
        assert grid is not None and grid.grid is not None
        if ratio == 4:
            return dataclasses.replace(grid, grid=dataclasses.replace(grid.grid, most_splits=0))
        return grid

    attempt = GeneralizedAlphaStepper._attempt

    def failing(self, s, t_out):  # the stepper's own signature
        if self.grid is not None and self.grid.ratio == 4:
            self.newton_failed(s, 1e-3)
        return attempt(self, s, t_out)

    monkeypatch.setattr(global_error, "GRID_RATIOS", (FOUR, 2))
    monkeypatch.setattr(global_error, "on_grid", strict_fours)
    monkeypatch.setattr(GeneralizedAlphaStepper, "_attempt", failing)
    block = run_case(load_case(PENDULUM)).checks["accuracy"]
    assert block["companion"] == "grid" and block["step_ratio"] == 2 and block["estimate"]
    assert "own steps two at a time" in block["method"]
    assert "the companion on the run's own steps four at a time failed" in block["note"]
    assert "error-controlled" not in block["note"]


def test_the_pendulums_estimate_four_at_a_time_is_close_to_two_at_a_time(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The library pendulum's summary: companion four at a time (GRID_RATIOS (FOUR, 2)),
    its estimate of each request within 25 % of the one two at a time (the default;
    measured 2026-11-30: histories 0.99-1.01 of it)."""
    from loadcases.run import global_error

    two = run_case(load_case(PENDULUM)).checks["accuracy"]
    monkeypatch.setattr(global_error, "GRID_RATIOS", (FOUR, 2))
    four = run_case(load_case(PENDULUM)).checks["accuracy"]
    assert four["step_ratio"] == 4 and two["step_ratio"] == 2
    for name, error in four["estimate"].items():
        assert error["history"] == pytest.approx(two["estimate"][name]["history"], rel=0.25)


FLEXIBLE_PENDULUM = PENDULUM.parents[1] / "examples" / "flexible" / "flexible_pendulum.case.yaml"


def test_steps_four_times_as_long_must_resolve_the_flexible_modes() -> None:
    """companion.resolved (mechlib.flexible.guards.resolves, STEPS_PER_PERIOD = 20 steps a
    period): a rigid run (no mode) always; a mode of 10 Hz at a companion mean step of
    5 ms (20 a period) yes, of 4 ms yes, of 6 ms no; on_grid gives no grid four at a time
    on a run of mean step 1.5 ms with a 10 Hz mode (6 ms steps), one two at a time."""
    analysis = ml.Dynamic(1.0, 0.001, dense=True, tolerance=1e-6)
    run = _solved(analysis)
    assert run.fastest_mode == 0.0 and on_grid(analysis, run, FOUR) is not None
    for step, expected in ((0.004, True), (0.005, True), (0.006, False)):
        assert resolved(dataclasses.replace(run, fastest_mode=10.0), step) is expected
    mean = (run.stats.step_ends[-1] - analysis.start) / run.stats.steps
    slow = dataclasses.replace(run, fastest_mode=1.0 / (20 * 4 * mean) * 0.99)
    fast = dataclasses.replace(run, fastest_mode=1.0 / (20 * 4 * mean) * 1.01)
    assert on_grid(analysis, slow, FOUR) is not None
    assert on_grid(analysis, fast, FOUR) is None and on_grid(analysis, fast, 2) is not None


def test_a_flexible_run_with_unresolved_modes_is_estimated_two_at_a_time(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With GRID_RATIOS (FOUR, 2): the library's flexible pendulum (four modes to 141.5
    Hz, mean step 1.6 ms: three of them unresolved, its own warning) has its companion two
    at a time (measured 2026-11-30: four at a time its tip deformation's history read 0.11
    of the true error, observed order -1.1; two at a time 0.47)."""
    from loadcases.run import global_error

    monkeypatch.setattr(global_error, "GRID_RATIOS", (FOUR, 2))
    outcome = run_case(load_case(FLEXIBLE_PENDULUM))
    assert outcome.solution.fastest_mode > 100.0
    assert any("are not resolved by the mean step" in w for w in outcome.solution.warnings)
    block = outcome.checks["accuracy"]
    assert block["companion"] == "grid" and block["step_ratio"] == 2
    assert "own steps two at a time" in block["method"]


def test_steps_four_times_as_long_must_resolve_a_one_row_spikes_pulse() -> None:
    """companion.pulses_resolved: a one-row spike (a load of 100 at 0.5 s between rows of
    0, 0.1 s apart) needs STEPS_PER_PERIOD / 2 = 10 companion steps within 0.4-0.6 s: 40
    of the run's four at a time, 20 two at a time; no spike, no condition."""
    time = np.linspace(0.0, 1.0, 11)
    load = np.zeros(11)
    load[5] = 100.0
    level = np.linspace(1.0, 2.0, 11)

    def run_of(steps: int, channels: dict[str, np.ndarray]) -> ml.Solution:
        ends = np.linspace(0.4, 0.6, steps + 1)[1:].tolist()
        stats = ml.SolverStats(steps=steps + 1, step_ends=[0.2, *ends, 1.0])
        return ml.Solution("ok", "", "dynamic", time, channels, stats)

    spiky = {"stop.value": load, "angle.value": level}
    assert pulses_resolved(run_of(40, spiky), FOUR)
    assert not pulses_resolved(run_of(39, spiky), FOUR)
    assert pulses_resolved(run_of(20, spiky), 2)
    assert pulses_resolved(run_of(3, {"angle.value": level}), FOUR)
