"""Issue 14 item 2: the global error estimate of a dynamic run, and the accuracy target.

Reference: the verification pendulum (uniform 1 m, 3 kg bar released at rest from 60 deg,
I_hinge = 1 kg*m^2) has the exact solution theta(t) = 2 asin(k sn(K(m) - w0 t | m)),
k = sin 30 deg, m = k^2, w0^2 = m g d / I (Abramowitz & Stegun 16.1, 17.3). Over 2 s at
0.01 s outputs the estimate of `hinge_angle` (largest difference over the run / 3, from a
companion with every step twice as long) must equal its true error against that closed
form: measured 3.52e-4 vs 3.26e-4 at the default settings, 1.340e-3 vs 1.326e-3 at
tolerance 1e-4 (2026-11-25, `output: steps`); accepted within 15 % (60 % at 1e-4 with the
dense output).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import mechlib as ml
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from tests.verification.library_pendulum import run_pendulum
from tests.verification.references import pendulum_angle

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"
THETA0 = math.radians(60.0)


def _exact_angle(t: np.ndarray) -> np.ndarray:
    return pendulum_angle(t, THETA0)


def _run(tmp_path: Path, analysis_lines: str = "", step: float = 0.01):
    outcome = run_pendulum(tmp_path, 2.0, step, analysis_lines)
    solution = outcome.solution
    true = np.abs(solution.channels["hinge_angle.value"] - _exact_angle(solution.time)).max()
    return outcome, float(true) / THETA0


@pytest.mark.parametrize(
    ("lines", "measured_true", "within", "met"),
    [("", 5.00e-4, 0.15, True), ("  tolerance: 1e-4\n", 9.41e-3, 0.6, False)],
    ids=["default", "tolerance-1e-4"],
)
def test_estimate_equals_the_error_against_the_closed_form(
    tmp_path: Path, lines: str, measured_true: float, within: float, met: bool
) -> None:
    """The estimate of the angle's error within 15 % of its error against the closed form
    at the default tolerance, 60 % at 1e-4 (measured 4.62e-4 for 5.00e-4 in 327 steps,
    8.1e-3 for 9.4e-3 in 80 steps, whose time histories miss the target; 6.4e-3 in 85
    steps while a step change carried the integrator's own velocity whole, a lucky point:
    its errors at 3e-5, 5e-5, 1e-4, 2e-4, 4e-4 were 0.0039, 0.0054, 0.0064, 0.0278, 0.0759
    with 31 rejections at 1e-4, now 0.0044, 0.0060, 0.0094, 0.0137, 0.0227 with 16,
    rules.constraint_velocity; with the step-size rules before 0.10.0's fix, 4.16e-4 for
    4.11e-4 in 356 steps and 9.6e-3 for 8.4e-3: about the same error per step squared,
    docs/performance.md; with `output: steps` the errors were 3.26e-4 and 1.33e-3)."""
    outcome, true = _run(tmp_path, lines)
    block = outcome.checks["accuracy"]
    assert true == pytest.approx(measured_true, rel=0.02)  # the run itself is unchanged
    assert block["estimate"]["hinge_angle"]["history"] == pytest.approx(true, rel=within)
    assert block["tightenings"] == 0 and block["target"] == 1e-3
    assert block["met"] is met  # envelope peaks within 1e-3
    history_warned = any("time histories" in w for w in outcome.solution.warnings)
    assert history_warned == (true > 1e-3)


def test_a_target_is_met_by_tightening_the_steps(tmp_path: Path) -> None:
    """accuracy 1e-5 without a tolerance, at 0.002 s outputs: the engine halves every step
    twice; the error falls to 3.3e-5 (1261 steps), the estimate follows it (3.1e-5), the
    envelope peaks meet the target (estimated at most 9.0e-6, the reaction's; of which the
    rows' miss of the crests 6.1e-6; at 0.01 s outputs that alone is 1.6e-4 and the target
    cannot be met: test_accuracy_target.py) and the summary says the time histories do not
    (3.9e-5). With Newton's acceleration floor at 10 eps and the velocity carried at step
    changes (rules.ROUNDOFF, rules.constraint_velocity; measured 2026-11-29 15:20 on main):
    before the carry rule, two halvings left the rate's and the reaction's peaks estimated
    at 1.29e-5 and 1.11e-5 (true 9.5e-6 and 7.6e-6 against Radau at 1e-11) and a third was
    taken. The largest step stays the default, the natural time sqrt(0.5 m / g) (the
    summary's max_step)."""
    outcome, true = _run(tmp_path, "  accuracy: 1e-5\n", step=0.002)
    block = outcome.checks["accuracy"]
    assert block["tightenings"] == 2 and block["outcome"] == "met"
    assert block["tolerance"] == pytest.approx(1e-6 / 64)
    assert block["max_step"] == pytest.approx(math.sqrt(0.5 / 9.81), rel=1e-12)
    assert true == pytest.approx(3.26e-5, rel=0.05)
    assert block["estimate"]["hinge_angle"]["history"] == pytest.approx(true, rel=0.3)
    assert block["met"] is True
    histories = max(e["history"] for e in block["estimate"].values())
    warned = any(
        w.startswith("accuracy: estimated error of the time histories")
        and "above the target 1e-05" in w
        for w in outcome.solution.warnings
    )
    assert warned == (histories > 1e-5)


def test_a_tolerance_set_in_the_case_is_kept(tmp_path: Path) -> None:
    outcome, _ = _run(tmp_path, "  tolerance: 1e-4\n  accuracy: 1e-6\n")
    block = outcome.checks["accuracy"]
    assert block["tightenings"] == 0 and block["tolerance"] == 1e-4 and block["met"] is False
    assert any("at tolerance 0.0001 (not tightened)" in w for w in outcome.solution.warnings)


def test_accuracy_off_solves_once_without_an_estimate(tmp_path: Path) -> None:
    default, _ = _run(tmp_path)
    off, true = _run(tmp_path, "  accuracy: off\n")
    assert "accuracy" not in off.checks
    assert off.solution.stats.steps == default.solution.stats.steps
    assert true == pytest.approx(5.00e-4, rel=0.02)


@pytest.mark.parametrize("rho_inf", [0.0, 1.0])
def test_rho_inf_from_the_case_reaches_the_integrator(tmp_path: Path, rho_inf: float) -> None:
    """`analysis.rho_inf` (issue 14 item 3) sets generalized-alpha's numerical damping: the
    pendulum stays within the accuracy its estimate states at both ends of the range
    (rho_inf 1: no damping; 0: the most), and the two runs differ. Measured at tolerance
    1e-4 with the dense output of 0.7.0: rho_inf 0 gives 2.2e-2 of the peak, estimated
    1.6e-2; rho_inf 1 1.6e-2, estimated 7.7e-3 (the estimate only within a factor 2 at this
    loose tolerance, 84 steps in 2 s: within 15 % with `output: steps`, where rho_inf 0
    gave 7.0e-3 and 0.9 (default) 1.3e-3); rho_inf 0.9 8.4e-3. With Newton's acceleration
    floor at 10 eps (rules.ROUNDOFF) and the integrator's velocity carried at step changes
    (rules.constraint_velocity; main, 2026-11-29 15:20): rho_inf 0 2.0e-2, estimated 1.7e-2;
    rho_inf 1 8.1e-3 (1.6e-2 before), estimated 1.8e-2 (2.25 times: undamped, the
    companion's twice-as-long steps are not yet in the error's asymptotic range here; the
    estimate errs on the safe side, within the factor 3 it is held to)."""
    outcome, true = _run(tmp_path, f"  rho_inf: {rho_inf}\n  tolerance: 1e-4\n")
    estimate = outcome.checks["accuracy"]["estimate"]["hinge_angle"]["history"]
    assert true / 3.0 < estimate < 3.0 * true
    assert true < 2.5e-2
    _, default_true = _run(tmp_path, "  tolerance: 1e-4\n")
    assert true != default_true


def test_rho_inf_out_of_range_is_an_input_error(tmp_path: Path) -> None:
    from loadcases.run import check_case_file

    text = (LIBRARY / "pendulum.case.yaml").read_text(encoding="utf-8")
    path = tmp_path / "pendulum.case.yaml"
    path.write_text(text.replace("  type: dynamic\n", "  type: dynamic\n  rho_inf: 1.5\n"))
    (problem,) = [d for d in check_case_file(path) if d.severity == "error"]
    assert problem.key == "analysis.rho_inf" and problem.message == "must be between 0 and 1"


def test_a_failed_companion_claims_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A companion that fails (here: 20 steps allowed, the grid companion's and then the
    adaptive one it falls back to) estimates nothing: the run stays ok, its accuracy block
    says `met` null, no estimate, and why (it said `met: true`)."""
    from loadcases.run import global_error

    coarser, on_grid = global_error.coarser, global_error.on_grid
    monkeypatch.setattr(
        global_error, "coarser", lambda a: dataclasses.replace(coarser(a), max_steps=20)
    )

    def grid_of_20(analysis: ml.Dynamic, run: ml.Solution, found=None) -> ml.Dynamic:
        grid = on_grid(analysis, run, found)
        assert grid is not None, "the pendulum's run: dense generalized-alpha"
        return dataclasses.replace(grid, max_steps=20)

    monkeypatch.setattr(global_error, "on_grid", grid_of_20)
    outcome, _ = _run(tmp_path)
    block = outcome.checks["accuracy"]
    assert outcome.solution.status == "ok"
    assert block["met"] is None and block["estimate"] == {}
    assert block["note"].startswith("not estimated: the companion run failed (dynamic analysis")
    assert "the limit of 20 steps" in block["note"]


@pytest.mark.parametrize(
    ("lines", "largest"),
    [
        # the default with dense output: the natural time sqrt(size / g); the pendulum's size
        # is the extent of its bar's centre of mass (0, -0.5, 0) and the hinge at the origin
        ("", math.sqrt(0.5 / 9.81)),
        ("  accuracy: 1e-5\n", math.sqrt(0.5 / 9.81)),  # tightened twice: still the default
        ("  output: steps\n", 0.01),  # the default with steps ending on the outputs: `step`
        ("  output: steps\n  max_step: 0.05\n", 0.01),  # a larger max_step has no effect
        ("  max_step: 0.02\n", 0.02),
    ],
    ids=["dense-default", "dense-tightened", "steps-default", "steps-capped", "given"],
)
def test_the_summary_states_the_largest_step_in_force(
    tmp_path: Path, lines: str, largest: float
) -> None:
    """`accuracy.max_step` is the largest step the run's integrator was allowed (s), the
    default's value when `analysis.max_step` is not given (it read 0.0)."""
    outcome, _ = _run(tmp_path, lines)
    assert outcome.checks["accuracy"]["max_step"] == pytest.approx(largest, rel=1e-12)


def test_the_natural_time_follows_size_and_gravity(tmp_path: Path) -> None:
    """Gravity off: g is floored at 1 m/s^2, the natural time is sqrt(0.5 m / 1 m/s^2)."""
    text = (LIBRARY / "pendulum.case.yaml").read_text(encoding="utf-8")
    text = text.replace("end: 4.0 ", "end: 0.5 ").replace("step: 0.001 ", "step: 0.01 ")
    path = tmp_path / "pendulum.case.yaml"
    path.write_text(text.replace("initial:", "effects: {gravity: false}\ninitial:"))
    outcome = run_case(load_case(path))
    assert outcome.checks["accuracy"]["max_step"] == pytest.approx(math.sqrt(0.5), rel=1e-12)
