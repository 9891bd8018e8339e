"""Ball dropped into its socket (seed 004 section 3.3): settles at the clearance.

Case: loadcases/library/verification/ball_in_socket.case.yaml (0.2 kg steel ball, R = 10 mm,
0.5 mm clearance, Hertz K from E = 210 GPa, nu = 0.3, LN damping e = 0.5). References: the
resting contact force equals the weight m g = 1.962 N (within 0.1 %, the thesis' check);
the eccentricity equals the clearance plus the Hertz deflection (F/K)^(1/1.5) (1e-9 m);
no friction force (the ball falls straight, nothing slides).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from references import channel

WEIGHT = 0.2 * 9.81  # N
E_STAR = 210e9 / (2 * (1 - 0.3**2))  # Pa, two equal steels
K = 4 / 3 * E_STAR * math.sqrt(0.01 * 0.0105 / 0.0005)  # N/m^1.5, internal contact radius


@pytest.fixture(scope="module")
def outcome(run_case):
    return run_case("ball_in_socket.case.yaml")


def test_settles_with_contact_force_equal_to_weight(outcome) -> None:
    t = np.asarray(outcome.solution.time, float)
    late = t >= 0.2
    normal = channel(outcome, "contact_force.normal")[late]
    assert np.all(np.abs(normal - WEIGHT) <= 1e-3 * WEIGHT)
    assert np.abs(channel(outcome, "contact_force.friction")[late]).max() < 1e-6


def test_settles_at_the_clearance(outcome) -> None:
    deflection = (WEIGHT / K) ** (1 / 1.5)
    ecc = channel(outcome, "eccentricity.value")[-1]
    assert ecc == pytest.approx(0.0005 + deflection, abs=1e-9)
    assert channel(outcome, "eccentricity.angle")[-1] == pytest.approx(-math.pi / 2)
    assert channel(outcome, "ball_pos.y")[-1] == pytest.approx(-ecc, abs=1e-12)
