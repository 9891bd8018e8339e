"""The accuracy companion (loadcases.run.companion): steps twice as long, rows thinned to
about one per companion step, at the run's own output times; the estimate it gives against
the pendulum's closed form (tests/verification/references.py: theta(t) = 2 asin(k sn(K -
w0 t | k^2)), released at rest from 60 deg)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import mechlib as ml
from loadcases.inputs.loader import load_case
from loadcases.run import build_run, run_case
from loadcases.run.companion import STEP_RATIO, coarser, sparser
from loadcases.run.global_error import shared_rows
from mechlib.solvers.genalpha.stepper import GeneralizedAlphaStepper
from tests.verification.flyball import THETA0, Z0, flyball_solve
from tests.verification.references import pendulum_angle

PENDULUM = (
    Path(__file__).resolve().parents[2]
    / "loadcases"
    / "library"
    / "verification"
    / "pendulum.case.yaml"
)

FLYBALL = PENDULUM.parent / "hard" / "iftomm_a05_flyball.case.yaml"


def _run_of(steps: int, rows: int) -> ml.Solution:
    time = np.linspace(0.0, 1.0, rows)
    run = ml.Solution("ok", "", "dynamic", time, {"x.value": np.sin(time)})
    run.stats.steps = steps
    return run


def test_dense_rows_are_thinned_to_the_companions_steps() -> None:
    """1001 rows over 100 steps: the companion's 50 expected steps get 1000 / 2 / 16 = 31
    rows (interval x 32 in all); x 8 would leave 62, more than its steps."""
    analysis = ml.Dynamic(end=1.0, step=0.001, dense=True)
    companion = sparser(coarser(analysis), _run_of(100, 1001))
    assert companion.step == pytest.approx(0.001 * STEP_RATIO * 16)
    assert 1.0 / companion.step <= 100 / STEP_RATIO < 1.0 / (companion.step / 2)


def test_rows_fewer_than_steps_and_steps_mode_are_left_alone() -> None:
    dense = ml.Dynamic(end=1.0, step=0.01, dense=True)
    assert sparser(coarser(dense), _run_of(400, 101)).step == pytest.approx(0.02)
    steps = ml.Dynamic(end=1.0, step=0.001, dense=False)  # the interval bounds the steps
    assert sparser(coarser(steps), _run_of(100, 1001)).step == pytest.approx(0.002)


def test_thinned_companion_rows_lie_on_the_run_rows_and_keep_the_estimate(
    tmp_path: Path,
) -> None:
    """The pendulum over 2 s at 1 ms outputs (2001 rows, about 360 steps): the companion's
    rows are every 16th of the run's, all shared; the angle's estimate is within 15 % of
    its error against the closed form (measured 2026-11-29: 4.16e-4 for 4.11e-4)."""
    text = PENDULUM.read_text(encoding="utf-8").replace("end: 4.0 ", "end: 2.0 ")
    path = tmp_path / "pendulum.case.yaml"
    path.write_text(text, encoding="utf-8")
    case = load_case(path)
    built = build_run(case)
    run = built.solve()
    companion = built.solve(sparser(coarser(built.analysis), run), checks=False)
    _, rows_c = shared_rows(run.time, companion.time)
    assert len(rows_c) == len(companion.time) and len(run.time) == 2001
    assert len(companion.time) <= run.stats.steps / STEP_RATIO + 1
    outcome = run_case(case)
    theta0 = math.radians(60.0)
    exact = pendulum_angle(outcome.solution.time, theta0)
    true = np.abs(outcome.solution.channels["hinge_angle.value"] - exact).max() / theta0
    estimate = outcome.checks["accuracy"]["estimate"]["hinge_angle"]["history"]
    assert estimate == pytest.approx(true, rel=0.15)


def test_companion_steps_stay_compiled_where_newton_stalls_on_an_old_matrix(monkeypatch) -> None:
    """IFToMM A05's stiff springs (8e5 N/m, 4e4 N s/m): at the companion's steps Newton
    stalls on the iteration matrix of an earlier step at most steps. The whole-run kernel
    refreshes it at the iterate, as the Python step does, and goes on
    (mechlib.solvers.genalpha.run), instead of handing each such step to Python: over
    0.6 s 3 of the companion's 78 steps were Python's (61 before; over 10 s 825 of 1051,
    the companion then 3 times the run's CPU, now 0.74: docs/performance.md); 6 since a
    slow step first refactors with the tangent kept (rules.keeps_tangent: a new
    differenced tangent, taken when the next step is slow too, is a Python step). The same
    steps (73 accepted, 5 rejected) and motion against the minimal-coordinate reference
    (tests/verification/flyball.py; measured 6.5e-4 of the travel's peak, 6.0e-4 of the
    angle's, 3.2e-4 of the spin rate's, about 3 times the run's as Richardson expects)."""
    python = {"steps": 0}
    step = GeneralizedAlphaStepper.step

    def counted(self, *args):
        python["steps"] += 1
        return step(self, *args)

    monkeypatch.setattr(GeneralizedAlphaStepper, "step", counted)
    built = build_run(load_case(FLYBALL))
    companion = dataclasses.replace(coarser(built.analysis), end=0.6)
    solved = built.solve(companion, checks=False)
    assert solved.ok and python["steps"] <= 7
    reference = flyball_solve(np.asarray(solved.time))
    for column, exact, bound in (
        ("travel.value", reference[1] - Z0, 1e-3),
        ("angle1.value", reference[0] - THETA0, 1e-3),
        ("spin_rate.value", reference[2], 5e-4),
    ):
        error = np.abs(solved.channels[column] - exact).max() / np.abs(exact).max()
        assert error < bound, (column, error)


def _spiky_run() -> ml.Solution:
    """The door let go's contact force in its first rows (N, every 10 ms): 0, then one row
    of 3834 N at 0.05 s, 0 again at 0.06 s; beside it a smooth crest between rows."""
    time = np.round(np.arange(0.0, 0.2 + 0.005, 0.01), 12)
    force = np.where(np.isclose(time, 0.05), 3834.0, 0.0)
    force[time >= 0.07] = 450.0 + 100.0 * np.sin(40.0 * time[time >= 0.07])
    run = ml.Solution(
        "ok", "", "dynamic", time, {"stop.normal": force, "x.value": np.sin(7.0 * time)}
    )
    run.stats.steps = 20
    return run


def test_a_one_row_spike_gets_a_companion_row_and_a_smooth_crest_its_rows() -> None:
    """The companion's rows, every 20 ms, would step over the run's one-row spike at 50 ms
    (and Richardson compare 3834 N with another place's value): it gets a row there and
    rows every quarter of the run's interval beside it (what the run's rows miss of the
    spike; the 0 N held over several rows is no spike, nor a crest's vertex: no rows; x,
    rising to its last row, has no crest). Without the spike the force's largest value is
    its smooth crest at 0.196 s, between the last two rows: an end row's, compared on the
    end rows both runs have (no rows kept). Shifted to 0.166 s, between the rows at 0.16
    and 0.17 s, it gets the run's rows there: the crest's row and three either side."""
    analysis = ml.Dynamic(end=0.2, step=0.01, dense=True)
    run = _spiky_run()
    rows = sparser(coarser(analysis), run).rows
    assert rows == pytest.approx([0.05 + k * 0.0025 for k in range(-3, 4)], abs=1e-15)
    run.channels["stop.normal"] = np.where(run.time < 0.07, 0.0, run.channels["stop.normal"])
    assert sparser(coarser(analysis), run).rows == ()
    shifted = 450.0 + 100.0 * np.sin(40.0 * (run.time + 0.03))
    run.channels["stop.normal"] = np.where(run.time < 0.07, 0.0, shifted)
    rows = sparser(coarser(analysis), run).rows
    assert rows == pytest.approx([0.14, 0.15, 0.16, 0.17, 0.18, 0.19, 0.2])


def test_a_companion_row_at_a_spike_is_the_dense_row_there(tmp_path: Path) -> None:
    """Rows at extra times (`Dynamic.rows`) come from the same dense steps as the others:
    the pendulum's rows every 20 ms plus 10 and 30 ms equal those of the same run every
    10 ms (its steps do not depend on the output times) to round-off."""
    built = build_run(load_case(PENDULUM))
    every = dataclasses.replace(built.analysis, end=0.1, step=0.01)
    extra = dataclasses.replace(every, step=0.02, rows=(0.01, 0.03, 0.02))
    fine, sparse = built.solve(every, checks=False), built.solve(extra, checks=False)
    assert sparse.time.tolist() == pytest.approx([0.0, 0.01, 0.02, 0.03, 0.04, 0.06, 0.08, 0.1])
    rows, rows_s = shared_rows(fine.time, sparse.time)
    assert len(rows_s) == len(sparse.time)
    for column, values in fine.channels.items():
        np.testing.assert_allclose(sparse.channels[column][rows_s], values[rows], atol=1e-12)
