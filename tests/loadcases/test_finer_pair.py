"""The estimate of a run that passed a near-singular position (loadcases.run.global_error,
loadcases.run.companion): a third run of steps half as long, and the error from that finer
pair, on solutions built from a closed form with known errors. A run without the warning
costs its companion only."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from loadcases.run.global_error import (
    COMPANION_STAGE,
    FINER_STAGE,
    Budget,
    Solver,
    solve_to_accuracy,
    tighter_stage,
)
from mechlib.checks.singularity import NEAR_SINGULAR

TIME = np.linspace(0.0, 2.0, 201)
OMEGA = 3.0  # rad/s
TOLERANCE = 1e-6


def _relative(error: float, run_error: float) -> float:
    """`error` x max |sin t| over the run's peak |value| (the estimate is of the peak)."""
    peak = float(np.abs(np.sin(OMEGA * TIME) + run_error * np.sin(TIME)).max())
    return error * float(np.abs(np.sin(TIME)).max()) / peak


def _solver(
    errors: dict[float, float], warning: str, stages: list[str] | None = None
) -> tuple[list[float], Solver]:
    """A solver whose run at tolerance t is sin(omega t) + errors[t] sin(t) (the error a
    smooth function of time, as Richardson assumes per pair) and warns `warning`; with
    the tolerances it was called at (and the stages, into `stages`)."""
    calls: list[float] = []

    def solve(analysis: ml.Dynamic, checks: bool = True, stage: str = "") -> ml.Solution:
        calls.append(analysis.tolerance)
        if stages is not None:
            stages.append(stage)
        error = errors[round(analysis.tolerance / TOLERANCE, 6)]
        values = np.sin(OMEGA * TIME) + error * np.sin(TIME)
        stats = ml.SolverStats(steps=100)
        return ml.Solution(
            "ok", "", "dynamic", TIME, {"x.value": values}, stats, [warning] if checks else []
        )

    return calls, solve


def test_a_singular_crossing_is_estimated_from_the_finer_pair() -> None:
    """The run's error 0.1 does not fall with the step as Richardson assumes: the
    companion's (steps twice as long) is 0.11, the finer run's 0.03. The companion's
    difference / 3 reads 0.0033 (a thirtieth); the finer pair (0.1 - 0.03) x 4/3 = 0.093;
    the observed order log2(0.01 / 0.07) = -2.8."""
    errors = {1.0: 0.1, 8.0: 0.11, 0.125: 0.03}
    calls, solve = _solver(errors, f"{NEAR_SINGULAR} 0.9 s: toggle measure 0.006")
    _, estimate = solve_to_accuracy(
        solve, ml.Dynamic(end=2.0, step=0.01, tolerance=TOLERANCE), 1e-3, budget=None
    )
    assert estimate is not None
    assert calls == pytest.approx([TOLERANCE, 8 * TOLERANCE, TOLERANCE / 8])
    assert estimate.requests["x"].history == pytest.approx(_relative(0.07 * 4 / 3, 0.1))
    assert estimate.observed_order == pytest.approx(math.log2(0.01 / 0.07))
    summary = estimate.summary()
    assert summary["observed_order"] == estimate.observed_order and summary["step_ratio"] == 0.5
    assert "finer one with every step half as long" in summary["method"]


def test_without_a_singular_position_only_the_companion_is_solved() -> None:
    """The same run without the warning (another warning only): the companion alone, its
    difference / 3, and no observed order in the summary."""
    errors = {1.0: 0.1, 8.0: 0.4}
    calls, solve = _solver(errors, "near-singular position (toggle or dead point, measure")
    _, estimate = solve_to_accuracy(
        solve, ml.Dynamic(end=2.0, step=0.01, tolerance=TOLERANCE), 1e-3, budget=None
    )
    assert estimate is not None
    assert calls == pytest.approx([TOLERANCE, 8 * TOLERANCE])
    assert estimate.requests["x"].history == pytest.approx(_relative(0.1, 0.1))
    assert "observed_order" not in estimate.summary() and estimate.summary()["step_ratio"] == 2


def test_a_tightening_starts_from_the_finer_run() -> None:
    """With a target of 0.01 the estimates miss (0.093 from the finer pair, then the finer
    run's 0.023 against the run), the finer run already solved is the first tighter run
    (not solved again): tolerances 1, 8, 1/8 and then 1/64 of the run's; the run written is
    the last, estimated against the one before (its companion): (0.03 - 0.0075) / 3."""
    errors = {1.0: 0.1, 8.0: 0.11, 0.125: 0.03, 0.015625: 0.0075}
    stages: list[str] = []
    calls, solve = _solver(errors, f"{NEAR_SINGULAR} 0.9 s: toggle measure 0.006", stages)
    run, estimate = solve_to_accuracy(
        solve,
        ml.Dynamic(end=2.0, step=0.01, tolerance=TOLERANCE),
        0.01,
        budget=Budget(cpu_seconds=None, refinements=2),
        measure="histories",
    )
    assert estimate is not None
    assert calls == pytest.approx([TOLERANCE, 8 * TOLERANCE, TOLERANCE / 8, TOLERANCE / 64])
    # what a progress bar names each solve: the finer run is the first tighter one
    assert stages == ["", COMPANION_STAGE, FINER_STAGE, tighter_stage(2)]
    assert tighter_stage(2) == "accuracy: tighter run 2"
    assert estimate.tightenings == 2 and estimate.tolerance == pytest.approx(TOLERANCE / 64)
    assert estimate.requests["x"].history == pytest.approx(_relative(0.0075, 0.0075))
    assert estimate.met and estimate.observed_order is None  # of the first run only
    assert estimate.step_ratio == 2  # against the run before it, of steps twice as long
    written = np.sin(OMEGA * TIME) + 0.0075 * np.sin(TIME)  # the tolerance-1/64 run's
    assert np.array_equal(run.channels["x.value"], written)
