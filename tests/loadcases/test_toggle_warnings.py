"""A user's landing gear whose leg turns back where its drag brace goes straight: no
near-singular warning. Nothing drives the leg: the constraint Jacobian keeps its rank there
(the leg's angle merely stops and reverses, as a four-bar's rocker at its limit), and the
knee load peaks (the leg's momentum taken by the light brace) without growing without
bound. Before, the leg's stationary angle gave a warning ("trunnion: angle cannot change").

Reference: the brace is straight when the distance from its top pivot B = (900, -100) mm to
the leg pin P (at (0, -700) mm on the leg at design, turning about the trunnion at the
origin, axis -y) equals the sum of the brace links |B - K| + |K - P| (knee K at design):
closed form of the leg angle by root finding on that distance (brentq, 1e-12 rad).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

CASE = Path(__file__).parent / "cases" / "landing_gear" / "freefall_toggle.case.yaml"
STEP = 0.002  # s, the case's output interval


def _straight_brace_leg_angle() -> float:
    """Leg angle (rad) at which the drag brace is straight, from the design geometry (mm)."""
    top, knee, pin = (
        np.array([900.0, -100.0]),
        np.array([412.686, -344.030]),
        np.array([0.0, -700.0]),
    )
    span = np.linalg.norm(top - knee) + np.linalg.norm(knee - pin)

    def stretch(angle: float) -> float:  # (x, z) of the pin turned by `angle` about -y
        c, s = math.cos(angle), math.sin(angle)
        turned = np.array([pin[0] * c - pin[1] * s, pin[0] * s + pin[1] * c])
        return float(np.linalg.norm(turned - top) - span)

    return brentq(stretch, math.radians(-3.0), 0.0, xtol=1e-12)


def test_freefall_to_the_straight_brace_has_no_warning() -> None:
    outcome = run_case(load_case(CASE))
    solution = outcome.solution
    assert solution.ok, solution.message
    leg = solution.channels["leg_angle.value"]
    deepest = int(np.argmin(leg))
    # the leg turns back where the brace is straight, and the knee load peaks there
    assert 0 < deepest < len(leg) - 1
    assert abs(leg[deepest] - _straight_brace_leg_angle()) < math.radians(0.01)
    knee_peak = int(np.argmax(solution.channels["knee_force.f"]))
    assert abs(solution.time[knee_peak] - solution.time[deepest]) <= STEP
    assert not [w for w in solution.warnings if "near-singular" in w], solution.warnings
