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
