"""Landing-gear free fall onto the down-stop: an event whose zero lies on a load jump.

The event `angle(trunnion) <= 0` switches the 5e6 N*m/rad down-stop on at the angle where the
preloaded downlock wire (tension only, 500 N) goes taut. Re-solving the step to the event
used to fail ("Newton iterations did not converge" at 1.256 s, no event listed).
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from loadcases.run import run_file
from mechlib.solvers.events import EVENT_TIME_TOLERANCE

CASES = Path(__file__).resolve().parent / "cases" / "landing_gear"
STOP_STIFFNESS = 5.0e6  # N*m/rad, mlg.mech.yaml downstop
DRAG = 0.5 * 1.225 * (150 * 1852 / 3600) ** 2 * 0.45  # N, 0.5 rho V^2 CdA at 150 knot
AXLE = 1.8  # m below the trunnion


def _case(
    tmp_path: Path,
    when: str,
    then: str = "[{activate: downstop}]",
    settings: tuple[float, float] | None = None,
) -> Path:
    """The free-fall case (and its mechanism) in tmp_path with another event condition;
    `settings`: the (tolerance, max_step) to solve it with, once (no accuracy estimate)."""
    shutil.copy(CASES / "mlg.mech.yaml", tmp_path)
    text = (CASES / "freefall_dyn.case.yaml").read_text(encoding="utf-8")
    text = text.replace(
        'when: "angle(trunnion) <= 0", then: [{activate: downstop}]',
        f'when: "{when}", then: {then}',
    )
    if settings is not None:  # max_step: the summary's, the largest step in force
        largest = f"max_step: {settings[1]!r}, " if settings[1] else ""
        text = text.replace(
            "analysis: {type: dynamic, ",
            f"analysis: {{tolerance: {settings[0]!r}, {largest}accuracy: off, type: dynamic, ",
        )
    path = tmp_path / "freefall.case.yaml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def freefall_outcome(tmp_path_factory: pytest.TempPathFactory):
    """The shipped-in-tests case as written: event at angle 0 exactly."""
    out = tmp_path_factory.mktemp("freefall")
    (outcome,) = run_file(CASES / "freefall_dyn.case.yaml", output_dir=out)
    return outcome


@pytest.fixture(scope="module")
def freefall(freefall_outcome):
    return freefall_outcome.solution


@pytest.fixture(scope="module")
def freefall_accuracy(freefall_outcome) -> dict:
    """The tolerance and largest step the shipped case was solved with (its accuracy block)."""
    return freefall_outcome.checks["accuracy"]


def _toggle_angle() -> float:
    """Leg angle (rad, < 0) where the drag brace goes straight: brace_top to the brace
    point on the leg (700 mm below the trunnion) as long as both brace halves together."""
    top, knee, leg = np.array([0.9, -0.1]), np.array([0.412686, -0.344030]), 0.7
    reach = np.linalg.norm(knee - top) + np.linalg.norm(np.array([0.0, -leg]) - knee)

    def gap(theta: float) -> float:
        return (
            np.linalg.norm(np.array([leg * math.sin(theta), -leg * math.cos(theta)]) - top) - reach
        )

    return brentq(gap, math.radians(-5.0), 0.0)


def test_event_at_the_wire_jump_fires_where_the_angle_is_zero(
    freefall, freefall_accuracy, tmp_path
) -> None:
    """The event fires, within 1e-6 s of the same run with the threshold 1e-7 rad earlier
    (independent location, away from the jump; the offset itself is 1e-7 rad / 0.93 rad/s
    = 1.1e-7 s), and the recorded angle at the event is zero within |omega| times the
    location tolerance."""
    assert freefall.ok, freefall.message
    (event,) = freefall.events
    assert event.name == "down" and event.actions == ("activate downstop",)
    assert "down at t = 1.25654 s" in freefall.message  # 1.25653 before 0.10.0's step rules
    # the same settings as the shipped run wrote (its accuracy estimate may tighten them)
    settings = freefall_accuracy["tolerance"], freefall_accuracy["max_step"]
    (earlier,) = run_file(
        _case(tmp_path, "angle(trunnion) <= 1.0e-7", "[stop]", settings),
        output_dir=tmp_path / "out",
    )
    (offset,) = earlier.solution.events
    assert abs(event.time - offset.time) < 1e-6
    row = int(np.flatnonzero(freefall.time == event.time)[0])
    omega = abs(freefall.channels["leg_rate.value"][row])
    assert abs(freefall.channels["leg_angle.value"][row]) <= 2 * omega * EVENT_TIME_TOLERANCE


def test_the_stop_catches_the_leg(freefall) -> None:
    """After the event the leg stays between 0 and the toggle of the drag brace (-0.82 deg,
    geometry closed form) and settles at the static deflection of the stop under the air
    load, -D * 1.8 m / k = -5.9e-4 rad: 10 % covers the downlock wire and the braces'
    weight, which the closed form leaves out."""
    angle = freefall.channels["leg_angle.value"][freefall.time > freefall.events[0].time]
    assert _toggle_angle() < angle.min() < 0.0
    static = -DRAG * AXLE / STOP_STIFFNESS
    assert angle[-1] == pytest.approx(static, rel=0.10)
    assert abs(freefall.channels["downstop.value"][-1] / STOP_STIFFNESS - angle[-1]) < 2e-5
