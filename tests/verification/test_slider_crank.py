"""Slider-crank of SPEC 1.2 (kinematic analysis) against planar Newton-Euler.

Case: loadcases/library/verification/slider_crank.case.yaml. Reference:
references.slider_crank_loads (closed-form kinematics, then the eight planar equations of
the three bodies). The rod has spherical/universal ends in 3D, but with principal axes along
z and in-plane gravity its in-plane reactions are the planar ones and the out-of-plane ones
vanish.
"""

from __future__ import annotations

import numpy as np
import pytest
from references import (
    SliderCrank,
    assert_within_peak,
    channel,
    slider_crank_kinematics,
    slider_crank_loads,
    vector,
    wrap_angle,
)

CRANK_SPEED = 2 * np.pi  # rad/s, `crank_speed: 360 deg/s` in slider_crank.mech.yaml
PEAK_FRACTION = 1e-3
"""Reactions within 0.1% of the channel's peak: a kinematic analysis has no integration
error, only the Newton tolerance of the position/velocity/acceleration solves (far smaller);
0.1% is the accuracy a sizing load needs."""


@pytest.fixture(scope="module")
def outcome(run_case):
    return run_case("slider_crank.case.yaml")


@pytest.fixture(scope="module")
def reference(outcome):
    t = np.asarray(outcome.solution.time, float)
    th = CRANK_SPEED * t
    w, a = np.full_like(t, CRANK_SPEED), np.zeros_like(t)
    return slider_crank_kinematics(th, w, a), slider_crank_loads(th, w, a, SliderCrank())


def test_time_grid(outcome) -> None:
    """One row per 1 ms from 0 to 1 s (end and step of the case)."""
    t = outcome.solution.time
    assert len(t) == 1001
    assert t[0] == pytest.approx(0.0, abs=1e-12) and t[-1] == pytest.approx(1.0, abs=1e-12)


def test_crank_angle_follows_motion(outcome) -> None:
    """crank_angle.value = crank_speed * t (a motion is imposed exactly; 1e-8 rad allows
    for the constraint solver's tolerance). Compared modulo 2 pi: a full turn may wrap."""
    t = outcome.solution.time
    diff = wrap_angle(channel(outcome, "crank_angle.value") - CRANK_SPEED * t)
    assert np.max(np.abs(diff)) < 1e-8


def test_slider_position(outcome, reference) -> None:
    """slider_pos = (r cos th + sqrt(l^2 - r^2 sin^2 th), 0, 0) within 1e-7 m: the
    constraint solver's tolerance, 5e-7 of the 0.2 m stroke."""
    kin, _ = reference
    pos = vector(outcome, "slider_pos")
    assert np.max(np.abs(pos[:, 0] - kin.x)) < 1e-7
    assert np.max(np.abs(pos[:, 1:])) < 1e-7


def test_drive_torque(outcome, reference) -> None:
    """drive_torque.value vs Newton-Euler T, within 0.1% of its peak (about 1.3 N*m)."""
    _, loads = reference
    assert_within_peak(
        channel(outcome, "drive_torque.value"),
        loads.drive_torque,
        PEAK_FRACTION,
        "drive_torque.value",
    )


@pytest.mark.parametrize(
    "request_name, fx, fy",
    [
        ("pivot_force", "pivot_fx", "pivot_fy"),  # on the crank from ground
        ("big_force", "big_fx", "big_fy"),  # on the rod from the crank
        ("small_force", "small_fx", "small_fy"),  # on the slider from the rod
    ],
)
def test_joint_reactions_in_plane(outcome, reference, request_name: str, fx: str, fy: str) -> None:
    """In-plane reaction components within 0.1% of the peak of the resultant in-plane force
    of that joint (a component may pass through zero, so its own peak is not the scale)."""
    _, loads = reference
    ref_x, ref_y = getattr(loads, fx), getattr(loads, fy)
    peak = float(np.max(np.hypot(ref_x, ref_y)))
    assert_within_peak(
        channel(outcome, f"{request_name}.fx"), ref_x, PEAK_FRACTION, f"{request_name}.fx", peak
    )
    assert_within_peak(
        channel(outcome, f"{request_name}.fy"), ref_y, PEAK_FRACTION, f"{request_name}.fy", peak
    )


@pytest.mark.parametrize("request_name", ["pivot_force", "big_force", "small_force"])
def test_joint_reactions_out_of_plane_vanish(outcome, request_name: str) -> None:
    """fz, tx, ty are zero for planar motion with in-plane loads: below 0.1% of the joint's
    peak in-plane force (N) and of that force times the 0.1 m crank (N*m)."""
    peak = float(
        np.max(
            np.hypot(channel(outcome, f"{request_name}.fx"), channel(outcome, f"{request_name}.fy"))
        )
    )
    assert np.max(np.abs(channel(outcome, f"{request_name}.fz"))) <= PEAK_FRACTION * peak
    for moment in ("tx", "ty"):
        values = channel(outcome, f"{request_name}.{moment}")
        assert np.max(np.abs(values)) <= PEAK_FRACTION * peak * 0.1, moment


def test_guide_reaction(outcome, reference) -> None:
    """Frictionless guide: fx = 0 and fy = normal force from the slider equations, both
    within 0.1% of the peak normal force (about 26 N)."""
    _, loads = reference
    peak = float(np.max(np.abs(loads.guide_fy)))
    assert_within_peak(
        channel(outcome, "guide_force.fy"), loads.guide_fy, PEAK_FRACTION, "guide_force.fy", peak
    )
    assert np.max(np.abs(channel(outcome, "guide_force.fx"))) <= PEAK_FRACTION * peak
    assert np.max(np.abs(channel(outcome, "guide_force.fz"))) <= PEAK_FRACTION * peak


def test_force_magnitude_column(outcome) -> None:
    """pivot_force.f is the magnitude of (fx, fy, fz) (round-off)."""
    f = vector(outcome, "pivot_force", "fx fy fz")
    assert np.allclose(
        channel(outcome, "pivot_force.f"), np.linalg.norm(f, axis=1), rtol=1e-12, atol=1e-12
    )
