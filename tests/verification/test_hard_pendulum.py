"""IFToMM benchmark A01, the simple pendulum released horizontal (issue 14 item 6).

Cases: loadcases/library/verification/hard/iftomm_a01_pendulum.case.yaml (10 s, default
integrator and tolerance) and iftomm_a01_pendulum_tight.case.yaml (Radau IIA at 1e-8); the
2000 s run is opt-in (`pytest --long`). References: the closed form of the pendulum
theta(t) = 2 asin(k sn(K(m) - w0 t | m)), its period 4 K(1/2) / w0 = 2.3678 s (complete
elliptic integral, references.pendulum_angle / pendulum_period), the hinge reaction from
the energy integral (references.pendulum_hinge_reaction) and the energy itself (zero: the
datum is the hinge). Acceptance: 1e-3 of each request's peak. Measured 2026-11-25 with the
dense output of 0.7.0: default angle 6.9e-4 of its peak after 10 s, hinge reaction 1.1e-3
(missed: the run's accuracy warning says so), energy drift 1.2e-3 of m g L (with `output:
steps`, 0.6.0: angle 1.5e-3, reaction 2.5e-3, energy 2.7e-4); tight angle 3.4e-9, energy
4.6e-9 (1.1e-9 and 1.0e-10 with `output: steps`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from references import (
    Pendulum,
    all_warnings,
    channel,
    pendulum_angle,
    pendulum_hinge_reaction,
    pendulum_period,
    vector,
)

HARD = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification" / "hard"
G = 9.81  # m/s^2, the benchmark's gravity
BALL = Pendulum(mass=1.0, cm_distance=1.0, izz_cm=1e-6, g=G)  # as in the mechanism file
THETA0 = np.pi / 2  # rad from the lowest position: released horizontal
ACCEPTANCE = 1e-3  # of each request's peak: the sizing accuracy (DEFAULT_ACCURACY)


@pytest.fixture(scope="module")
def default(run_case):
    return run_case("hard/iftomm_a01_pendulum.case.yaml")


@pytest.fixture(scope="module")
def tight(run_case):
    return run_case("hard/iftomm_a01_pendulum_tight.case.yaml")


def _swing(outcome) -> np.ndarray:
    """Angle from the lowest position (rad): the hinge angle is 0 horizontal, -pi/2 lowest."""
    return channel(outcome, "angle.value") + np.pi / 2


def _angle_error(outcome) -> float:
    """Largest error of the swing angle against the closed form, of its peak pi/2."""
    t = np.asarray(outcome.solution.time, float)
    return float(np.max(np.abs(_swing(outcome) - pendulum_angle(t, THETA0, BALL)))) / THETA0


def _energy_drift(outcome) -> float:
    """Largest |m g y + m v^2 / 2 + I w^2 / 2| over the run (zero at release), of m g L."""
    y = channel(outcome, "bob_pos.y")
    v = vector(outcome, "bob_vel")
    w = channel(outcome, "rate.value")
    energy = BALL.mass * (G * y + 0.5 * np.sum(v**2, axis=1)) + 0.5 * BALL.izz_cm * w**2
    return float(np.max(np.abs(energy))) / (BALL.mass * G * BALL.cm_distance)


def _period(outcome) -> float:
    """Mean period (s) from the passages through the lowest position (two per period),
    located by linear interpolation between output rows (the angle is straight there)."""
    t, swing = np.asarray(outcome.solution.time, float), _swing(outcome)
    i = np.nonzero(np.sign(swing[:-1]) * np.sign(swing[1:]) < 0)[0]
    passes = t[i] - swing[i] * (t[i + 1] - t[i]) / (swing[i + 1] - swing[i])
    return 2.0 * float(passes[-1] - passes[0]) / (len(passes) - 1)


def _reaction_error(outcome) -> float:
    """Largest hinge reaction error against the energy solution, of its peak (about 3 m g)."""
    t = np.asarray(outcome.solution.time, float)
    fx, fy = pendulum_hinge_reaction(pendulum_angle(t, THETA0, BALL), THETA0, BALL)
    error = np.hypot(
        channel(outcome, "hinge_force.fx") - fx, channel(outcome, "hinge_force.fy") - fy
    )
    return float(np.max(error) / np.max(np.hypot(fx, fy)))


def test_default_settings(default) -> None:
    """Default settings (dense output, 1582 steps), 10 s: the angle within 2.8e-3 of its
    peak (measured 2.2e-3), the hinge reaction within 4.5e-3 of its peak (measured 3.6e-3:
    above the 1e-3 acceptance, and the run's accuracy warning names the bob's position),
    the energy within 1.2e-3 of m g L (measured 6.1e-4), the period within 1.2e-4 of the
    closed form 2.3678 s (measured 8.3e-5: generalized-alpha's own period error at these
    steps; fixed steps of 6.25 ms, 1600 of them, end 4.6e-3 m off against this run's 3.5e-3).
    Before 0.10.0 (1726 steps) the angle read 6.9e-4, the reaction 1.1e-3 and the period
    1.2e-6: the energy the step-size loops drained (1.2e-3 here) shortened the period
    against the method's own lag, two errors that cancelled near 10 s and not after
    (angle 7.6e-3 rad at 20 s, 7.7e-2 at 50 s, against 5.5e-3 and 5.9e-3 now:
    tests/mechlib/test_genalpha_order.py, docs/performance.md)."""
    assert default.solution.time[-1] == pytest.approx(10.0)
    assert _angle_error(default) < 2.8e-3
    assert _reaction_error(default) < 4.5e-3
    assert _energy_drift(default) < 1.2e-3
    assert _period(default) == pytest.approx(pendulum_period(THETA0, BALL), rel=1.2e-4)
    warned = [w for w in all_warnings(default) if w.startswith("accuracy") and "histories" in w]
    assert warned and "bob_pos" in warned[0]


def test_tight_setting(tight) -> None:
    """Radau IIA at tolerance 1e-8, 10 s, dense output (one solver over the run, 1942
    steps): the angle within 7e-9 of its peak against the closed form (measured 3.4e-9;
    the issue asks 1e-6), the hinge reaction within 1e-8 of its peak (measured 5.1e-9),
    the energy within 1e-8 of m g L (measured 4.6e-9: the solver no longer restarts from a
    projected state at each output time; with `output: steps` 1.1e-9, 1.7e-9, 1.0e-10),
    the period within 1e-7 (measured 2.9e-8)."""
    assert _angle_error(tight) < 7e-9
    assert _reaction_error(tight) < 1e-8
    assert _energy_drift(tight) < 1e-8
    assert _period(tight) == pytest.approx(pendulum_period(THETA0, BALL), rel=1e-7)


PERIOD_2000 = 2e-2  # measured -1.5e-2 (dense output); -2.3e-3 with `output: steps`


@pytest.mark.long
def test_2000_seconds(tmp_path: Path) -> None:
    """The benchmark's full length, 2000 s (845 periods) at the default settings (one
    solve, about 2 min of CPU): no failure, the energy within 0.16 of m g L (measured
    0.134 with the dense output of 0.7.0 on, 2026-11-28, 0.9.0 and 0.10.0 alike; 2.1e-2
    with `output: steps`, 401070 steps, 2026-11-25: generalized-alpha's numerical
    dissipation, larger with the dense output's longer steps; it lowers the energy, never
    raises it) and the mean period within PERIOD_2000 of the closed form (measured
    -1.5e-2: the lost energy lowers the amplitude, which shortens the period; over the
    first 10 s it is 5.6e-5)."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    text = (HARD / "iftomm_a01_pendulum.case.yaml").read_text(encoding="utf-8")
    text = text.replace("  end: 10.0\n", '  end: 2000.0\n  accuracy: "off"\n')
    path = tmp_path / "iftomm_a01_pendulum.case.yaml"
    path.write_text(text.replace("mechanism: ", f"mechanism: {HARD}/"), encoding="utf-8")
    outcome = run_case(load_case(path))
    assert outcome.solution.status == "ok", outcome.solution.message
    assert outcome.solution.time[-1] == pytest.approx(2000.0)
    assert _energy_drift(outcome) < 0.16
    assert _period(outcome) == pytest.approx(pendulum_period(THETA0, BALL), rel=PERIOD_2000)


def _tightened(tolerance: float):
    """The 10 s default case at `tolerance` (generalized-alpha, dense output), one solve."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    cf = load_case(HARD / "iftomm_a01_pendulum.case.yaml")
    analysis = cf.case.analysis.model_copy(update={"tolerance": tolerance, "accuracy": "off"})
    case = cf.case.model_copy(update={"analysis": analysis})
    outcome = run_case(dataclasses.replace(cf, case=case))
    assert outcome.solution.ok, outcome.solution.message
    return outcome


@pytest.fixture(scope="module")
def tightened():
    """The case at tolerances 3e-11 and 3.75e-12 (a halving of every step apart)."""
    return {tolerance: _tightened(tolerance) for tolerance in (3e-11, 3.75e-12)}


def _energy_trend(outcome) -> float:
    """The energy's least-squares slope over the run, of m g L per s (negative: lost)."""
    t = np.asarray(outcome.solution.time, float)
    y = channel(outcome, "bob_pos.y")
    v = vector(outcome, "bob_vel")
    w = channel(outcome, "rate.value")
    energy = BALL.mass * (G * y + 0.5 * np.sum(v**2, axis=1)) + 0.5 * BALL.izz_cm * w**2
    return float(np.polyfit(t, energy, 1)[0]) / (BALL.mass * G * BALL.cm_distance)


def test_error_falls_with_tolerance_below_newton_floor(tightened) -> None:
    """Generalized-alpha at tolerances 3e-11 and 3.75e-12 over 10 s (issue 35, the error
    floor of IFToMM A01 over 2000 s), against the closed form: the energy's trend within
    1.5e-8 m g L per s at both (measured -5.0e-9 and -2.9e-9), the angle's error falling
    at least 2.5 times with the halving of the steps (measured 2.5e-6 to 5.9e-7 of its
    peak, 4.2 times: second order) and the mean period within 3e-8 of 2.3678 s at the
    tighter one (measured -6.8e-9). Before, with Newton's acceleration test floored at
    1e3 eps of q (rules.ROUNDOFF), the energy's trend was -3.3e-8 and -2.2e-7, the angle's
    error rose from 3.0e-6 to 4.0e-6 and the period was 1.5e-7 off: the remainder Newton
    left in each step, a velocity error of every step (x gamma'), grew as the steps
    shrank."""
    coarse, fine = tightened[3e-11], tightened[3.75e-12]
    assert abs(_energy_trend(coarse)) < 1.5e-8
    assert abs(_energy_trend(fine)) < 1.5e-8
    assert _angle_error(fine) < _angle_error(coarse) / 2.5
    assert _period(fine) == pytest.approx(pendulum_period(THETA0, BALL), rel=3e-8)
