"""Bar held by a spring under gravity (static analysis) against the moment balance.

Case: loadcases/library/verification/static_spring_bar.case.yaml. Reference:
references.spring_bar_equilibrium (moment balance about the hinge solved with brentq):
0.46595 rad, tension 30.825 N, hinge force on the bar (29.214, 29.406) N.
"""

from __future__ import annotations

import numpy as np
import pytest
from references import SpringBar, channel, spring_bar_equilibrium

SPRING_BAR = SpringBar()  # the data of static_spring_bar.case.yaml, SI
EQUILIBRIUM = spring_bar_equilibrium(SPRING_BAR)
HINGE_PEAK = float(np.hypot(EQUILIBRIUM["hinge_fx"], EQUILIBRIUM["hinge_fy"]))


@pytest.fixture(scope="module")
def outcome(run_case):
    return run_case("static_spring_bar.case.yaml")


def test_single_row_at_time_zero(outcome) -> None:
    """A static analysis gives one row at t = 0 (SPEC 1.3)."""
    assert np.asarray(outcome.solution.time).shape == (1,)
    assert outcome.solution.time[0] == pytest.approx(0.0, abs=1e-15)


def test_equilibrium_angle(outcome) -> None:
    """hinge_angle.value within 1e-6 rad of the brentq root: the static solve is an exact
    Newton solve with a stiffness of about 51 N*m/rad, so a 1e-6 rad error would leave a
    5e-5 N*m unbalanced moment, well above any converged residual."""
    assert channel(outcome, "hinge_angle.value")[0] == pytest.approx(EQUILIBRIUM["angle"], abs=1e-6)


def test_spring_tension_and_length(outcome) -> None:
    """spring_force.value (tension positive) within 0.1% of the reference tension (reaction
    accuracy of the verification suite); the spring length (expression `dist`) within
    1e-6 m (follows from the angle tolerance times the 0.8 m lever)."""
    assert channel(outcome, "spring_force.value")[0] == pytest.approx(
        EQUILIBRIUM["tension"], rel=1e-3
    )
    assert channel(outcome, "spring_length.value")[0] == pytest.approx(
        EQUILIBRIUM["length"], abs=1e-6
    )


def test_hinge_reaction(outcome) -> None:
    """Force on the bar from ground, R = -F_spring - m g, within 0.1% of |R|; no
    out-of-plane force or moment (0.1% of |R|, moments per metre of bar)."""
    fx = channel(outcome, "hinge_force.fx")[0]
    fy = channel(outcome, "hinge_force.fy")[0]
    assert abs(fx - EQUILIBRIUM["hinge_fx"]) <= 1e-3 * HINGE_PEAK
    assert abs(fy - EQUILIBRIUM["hinge_fy"]) <= 1e-3 * HINGE_PEAK
    for column in ("fz", "tx", "ty"):
        assert abs(channel(outcome, f"hinge_force.{column}")[0]) <= 1e-3 * HINGE_PEAK, column
