"""Double pendulum (dynamic analysis, 10 s, chaotic): energy conservation and early motion.

Case: loadcases/library/verification/double_pendulum.case.yaml. References:
references.double_pendulum_energy (energy of the two bars) and double_pendulum_solve
(Lagrange's equations, solve_ivp DOP853 with rtol 1e-10).
"""

from __future__ import annotations

import numpy as np
import pytest
from references import (
    DoublePendulum,
    channel,
    double_pendulum_energy,
    double_pendulum_solve,
    vector,
    wrap_angle,
)

PENDULUM = DoublePendulum()  # data of double_pendulum.case.yaml, SI
PHI0 = (np.radians(90.0), np.radians(135.0))  # absolute angles: j1 = 90, j2 = 45 deg
ENERGY_SCALE = PENDULUM.g * (
    PENDULUM.mass1 * PENDULUM.cm1 + PENDULUM.mass2 * (PENDULUM.length1 + PENDULUM.cm2)
)
"""Depth of the potential well, 32.37 J: the energy scale of the motion (the total energy
is near zero with the datum at the hinge, so it cannot serve as the scale)."""


@pytest.fixture(scope="module")
def outcome(run_case):
    return run_case("double_pendulum.case.yaml")


def _absolute_state(outcome) -> tuple[np.ndarray, ...]:
    """Absolute bar angles and rates from the joint requests (j2 is relative to bar 1)."""
    a1, a2 = channel(outcome, "angle1.value"), channel(outcome, "angle2.value")
    w1, w2 = channel(outcome, "omega1.value"), channel(outcome, "omega2.value")
    return np.unwrap(a1), np.unwrap(a1) + np.unwrap(a2), w1, w1 + w2


def test_energy_drift(outcome) -> None:
    """Energy from the joint requests drifts less than 1e-4 of the well depth over 10 s at
    the default tolerance with max_step 0.5 ms (generalized-alpha's energy error is O(h^2):
    1.4e-4 at 1 ms, 3.5e-5 at 0.5 ms), the drift asked for conservative systems."""
    assert outcome.solution.time[-1] == pytest.approx(10.0)
    energy = double_pendulum_energy(*_absolute_state(outcome), PENDULUM)
    assert np.max(np.abs(energy - energy[0])) <= 1e-4 * ENERGY_SCALE


def test_energy_from_point_requests(outcome) -> None:
    """The energy rebuilt from the centre-of-mass positions and velocities (plus the bar
    rates) equals the one from joint coordinates to 1e-4 of the well depth: both describe
    one state, but an index-3 integrator meets the velocity constraints only to its
    tolerance, so body and joint velocities may disagree at that level. The `potential`
    expression request equals m1 g y1 + m2 g y2 from the point positions (1e-9 of the well
    depth: same positions, no integration involved)."""
    p = PENDULUM
    _, _, w1, w2 = _absolute_state(outcome)
    v1, v2 = vector(outcome, "cm1_vel"), vector(outcome, "cm2_vel")
    y1, y2 = channel(outcome, "cm1_pos.y"), channel(outcome, "cm2_pos.y")
    potential = p.g * (p.mass1 * y1 + p.mass2 * y2)
    kinetic = 0.5 * (
        p.mass1 * np.sum(v1**2, 1) + p.izz1 * w1**2 + p.mass2 * np.sum(v2**2, 1) + p.izz2 * w2**2
    )
    from_joints = double_pendulum_energy(*_absolute_state(outcome), p)
    assert np.max(np.abs(kinetic + potential - from_joints)) <= 1e-4 * ENERGY_SCALE
    assert np.max(np.abs(channel(outcome, "potential.value") - potential)) <= 1e-9 * ENERGY_SCALE


def test_early_motion_matches_lagrange(outcome) -> None:
    """For the first second (before chaos amplifies differences) the bar angles follow the
    reference integration within 1e-3 rad (modulo 2 pi). Integrators that hold the energy
    to 1e-4 over 10 s stay within ~1e-4 rad over the first second (checked with scipy's
    RK45 and Radau), so 1e-3 rad leaves a margin of ten."""
    t = np.asarray(outcome.solution.time, float)
    first = t <= 1.0 + 1e-12
    phi1, phi2, _, _ = _absolute_state(outcome)
    ref = double_pendulum_solve(t[first], PHI0, PENDULUM)
    assert np.max(np.abs(wrap_angle(phi1[first] - ref[:, 0]))) < 1e-3
    assert np.max(np.abs(wrap_angle(phi2[first] - ref[:, 1]))) < 1e-3
