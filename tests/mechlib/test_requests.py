"""Requests: reaction frames and moment point, motion-effort sign, point kinematics.

Conventions under test (mechlib/outputs/requests.py): a joint reaction is the force and torque on
body 1 from body 2, the torque about the joint point, components in the requested frame's
axes; a motion effort is positive in the direction of increasing joint coordinate.
Models: uniform bar (m = 2 kg, L = 1 m) along +x from its hinge, axis +z, gravity -y.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib

from ._models import Bar, G, Ramp, Sine, hinged_bar, rz

BAR = Bar()
WEIGHT = BAR.mass * G
HINGE = (0.3, 0.2, 0.0)  # off the origin: a moment about the origin would differ
FORCE = ("fx", "fy", "fz")
TORQUE = ("tx", "ty", "tz")


def _vector(sol: mechlib.Solution, name: str, comps: tuple[str, ...]) -> np.ndarray:
    return np.column_stack([sol.channels[f"{name}.{c}"] for c in comps])


def test_reaction_in_a_body_frame_is_the_rotated_ground_one() -> None:
    """Driven bar (theta = 0.4 + 2 t): the reaction in the bar's frame equals
    A^T (ground-frame reaction), A = Rz(theta); in a named frame F on the bar with axes
    (y, -x, z) it equals F^T A^T (ground). Linear algebra only: 1e-12 of the weight."""
    mech = hinged_bar(BAR, hinge_at=HINGE)
    mech.add_motion("drive", joint="hinge", function=Ramp(0.4, 2.0))
    mech.add_frame("side", body="bar", x=(0.0, 1.0, 0.0), y=(-1.0, 0.0, 0.0))
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(1.0, 0.1),
        requests=[
            mechlib.JointReaction("G", "hinge"),
            mechlib.JointReaction("B", "hinge", frame="bar"),
            mechlib.JointReaction("S", "hinge", frame="side"),
            mechlib.JointCoordinate("angle", "hinge"),
        ],
    )
    side = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # columns: axes
    for comps in (FORCE, TORQUE):
        ground, body, named = (_vector(sol, n, comps) for n in ("G", "B", "S"))
        for i, theta in enumerate(sol.channels["angle.value"]):
            a = rz(theta)
            assert np.abs(body[i] - a.T @ ground[i]).max() < 1e-12 * WEIGHT
            assert np.abs(named[i] - side.T @ a.T @ ground[i]).max() < 1e-12 * WEIGHT
    norms = np.linalg.norm(_vector(sol, "G", FORCE), axis=1)
    assert np.abs(sol.channels["B.f"] - norms).max() < 1e-12 * WEIGHT


def test_hinge_reaction_is_about_the_joint_point() -> None:
    """Bar on an off-origin hinge held by a torsion spring (static): the hinge carries the
    weight, F = (0, m g, 0), and no moment about its axis, tz = 0 (the spring holds the
    bar); about the cm or the origin tz would be m g (L/2) cos(theta) or
    m g x_hinge = 5.9 N*m. Static solution to 1e-10 of the weight: tolerance 1e-8."""
    mech = hinged_bar(BAR, hinge_at=HINGE)
    mech.add_force(mechlib.TorsionSpring("spring", joint="hinge", stiffness=20.0))
    sol = mechlib.solve(mech, mechlib.Static(), requests=[mechlib.JointReaction("R", "hinge")])
    force, torque = _vector(sol, "R", FORCE)[0], _vector(sol, "R", TORQUE)[0]
    assert np.abs(force - [0.0, WEIGHT, 0.0]).max() < 1e-8 * WEIGHT
    assert np.abs(torque).max() < 1e-8 * WEIGHT


def test_cantilever_fixed_joint_reaction() -> None:
    """A bar fixed at its end (off-origin point): the wall pushes up m g = 19.62 N and
    holds the moment tz = +m g L/2 = 9.81 N*m on the bar (counter-clockwise, against
    the weight's -m g L/2), tx = ty = 0. Static: 1e-8 of the weight."""
    mech = hinged_bar(BAR, hinge_at=HINGE, joint_type="fixed")
    sol = mechlib.solve(mech, mechlib.Static(), requests=[mechlib.JointReaction("R", "hinge")])
    force, torque = _vector(sol, "R", FORCE)[0], _vector(sol, "R", TORQUE)[0]
    assert np.abs(force - [0.0, WEIGHT, 0.0]).max() < 1e-8 * WEIGHT
    assert np.abs(torque - [0.0, 0.0, BAR.weight_moment]).max() < 1e-8 * WEIGHT
    assert sol.channels["R.t"][0] == pytest.approx(BAR.weight_moment, rel=1e-8)


@pytest.mark.parametrize("order", [("b2", "b1"), ("b1", "b2")])
def test_reactions_along_a_two_bar_cantilever(order: tuple[str, str]) -> None:
    """Bars b1 (2 kg, x in [0, 1] m) and b2 (1 kg, x in [1, 2] m) welded to each other
    at x = 1 m and to the wall at the origin. Wall on b1: F = (0, 3 g, 0),
    tz = 2 g 0.5 + 1 g 1.5 = 24.525 N*m. Weld on b2 from b1: (0, g, 0), tz = g 0.5;
    with the weld's bodies listed (b1, b2) it is the opposite wrench, on b1 from b2
    (action and reaction). Static: 1e-8 of the total weight."""
    mech = mechlib.Mechanism(gravity=(0.0, -G, 0.0))
    mech.add_body("b1", mass=2.0, cm=(0.5, 0.0, 0.0), inertia=[1e-4, 1 / 6, 1 / 6])
    mech.add_body("b2", mass=1.0, cm=(1.5, 0.0, 0.0), inertia=[1e-4, 1 / 12, 1 / 12])
    mech.add_joint("wall", "fixed", bodies=("b1", "ground"), at=(0.0, 0.0, 0.0))
    mech.add_joint("weld", "fixed", bodies=order, at=(1.0, 0.0, 0.0))
    sol = mechlib.solve(
        mech,
        mechlib.Static(),
        requests=[mechlib.JointReaction("W", "wall"), mechlib.JointReaction("J", "weld")],
    )
    tol = 1e-8 * 3.0 * G
    sign = 1.0 if order[0] == "b2" else -1.0
    wall = np.r_[_vector(sol, "W", FORCE)[0], _vector(sol, "W", TORQUE)[0]]
    weld = np.r_[_vector(sol, "J", FORCE)[0], _vector(sol, "J", TORQUE)[0]]
    assert np.abs(wall - [0.0, 3.0 * G, 0.0, 0.0, 0.0, 2.5 * G]).max() < tol
    assert np.abs(weld - sign * np.array([0.0, G, 0.0, 0.0, 0.0, 0.5 * G])).max() < tol


def test_reaction_on_ground_as_body_1() -> None:
    """Cantilever declared with the ground first: the reaction on the ground from the bar
    is the opposite of the one on the bar, F = (0, -m g, 0), tz = -m g L/2 (1e-8)."""
    mech = hinged_bar(BAR, hinge_at=HINGE, joint_type="fixed", reversed_bodies=True)
    sol = mechlib.solve(mech, mechlib.Static(), requests=[mechlib.JointReaction("R", "hinge")])
    force, torque = _vector(sol, "R", FORCE)[0], _vector(sol, "R", TORQUE)[0]
    assert np.abs(force - [0.0, -WEIGHT, 0.0]).max() < 1e-8 * WEIGHT
    assert np.abs(torque - [0.0, 0.0, -BAR.weight_moment]).max() < 1e-8 * WEIGHT


@pytest.mark.parametrize("reversed_bodies", [False, True])
def test_motion_effort_sign_on_a_revolute(reversed_bodies: bool) -> None:
    """A motion holds the bar at theta = 0.4 rad against gravity. Joint (bar, ground):
    the coordinate is theta and the effort +m g (L/2) cos(0.4) (it lifts the bar,
    increasing the coordinate). Joint (ground, bar): the coordinate is -theta and the
    effort -m g (L/2) cos(0.4) (the conjugate force of -theta). 1e-8 of m g L/2."""
    sign = -1.0 if reversed_bodies else 1.0
    mech = hinged_bar(BAR, reversed_bodies=reversed_bodies)
    mech.add_motion("hold", joint="hinge", function=Ramp(sign * 0.4, 0.0))
    sol = mechlib.solve(
        mech,
        mechlib.Static(),
        requests=[mechlib.MotionEffort("E", "hold"), mechlib.PointKinematics("tip", "tip")],
    )
    assert sol.channels["tip.y"][0] == pytest.approx(BAR.length * math.sin(0.4), abs=1e-10)
    expected = sign * BAR.weight_moment * math.cos(0.4)
    assert sol.channels["E.value"][0] == pytest.approx(expected, abs=1e-8 * BAR.weight_moment)


@pytest.mark.parametrize("axis_sign", [1.0, -1.0])
def test_motion_effort_sign_on_a_prismatic(axis_sign: float) -> None:
    """A 2 kg slider on a vertical prismatic held by a motion: with the axis up the effort
    is +m g (pushing towards increasing travel), with the axis down -m g. 1e-8 of m g."""
    mech = mechlib.Mechanism(gravity=(0.0, -G, 0.0))
    mech.add_body("slider", mass=BAR.mass, cm=(0.0, 0.0, 0.0), inertia=[1e-2] * 3)
    mech.add_joint(
        "slide",
        "prismatic",
        bodies=("slider", "ground"),
        at=(0.0, 0.0, 0.0),
        axis=(0.0, axis_sign, 0.0),
    )
    mech.add_motion("hold", joint="slide", function=Ramp(0.1, 0.0))
    sol = mechlib.solve(mech, mechlib.Static(), requests=[mechlib.MotionEffort("E", "hold")])
    assert sol.channels["E.value"][0] == pytest.approx(axis_sign * WEIGHT, abs=1e-8 * WEIGHT)


def test_point_acceleration_matches_finite_differences() -> None:
    """Tip of a bar driven by theta = 0.3 sin(5 t) (kinematic, exact to 1e-10): velocity
    and acceleration equal central differences of position and velocity over 1e-4 s
    (truncation ~ dt^2/6 |x'''| ~ 1e-7 of the peak; tolerance 1e-6 of the peak), and the
    acceleration equals alpha x r - omega^2 r exactly (1e-9 of the peak)."""
    motion = Sine(0.0, 0.3, 5.0)
    mech = hinged_bar(BAR)
    mech.add_motion("drive", joint="hinge", function=motion)
    dt = 1e-4
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(0.6, dt),
        requests=[
            mechlib.PointKinematics(q, "tip", q) for q in ("position", "velocity", "acceleration")
        ],
    )
    pos, vel, acc = (
        _vector(sol, q, ("x", "y", "z")) for q in ("position", "velocity", "acceleration")
    )
    v_fd = (pos[2:] - pos[:-2]) / (2 * dt)
    a_fd = (vel[2:] - vel[:-2]) / (2 * dt)
    assert np.abs(vel[1:-1] - v_fd).max() < 1e-6 * np.abs(vel).max()
    assert np.abs(acc[1:-1] - a_fd).max() < 1e-6 * np.abs(acc).max()
    t = sol.time
    theta = np.array([motion.value(x) for x in t])
    omega = np.array([motion.rate(x) for x in t])
    alpha = np.array([motion.accel(x) for x in t])
    r = BAR.length * np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(t)])
    exact = alpha[:, None] * np.column_stack([-r[:, 1], r[:, 0], r[:, 2]]) - omega[:, None] ** 2 * r
    assert np.abs(acc - exact).max() < 1e-9 * np.abs(exact).max()


def test_point_velocity_in_a_body_frame() -> None:
    """The tip velocity in the bar's own frame is (0, omega L, 0) (1e-9 of the peak)."""
    mech = hinged_bar(BAR)
    mech.add_motion("drive", joint="hinge", function=Ramp(0.2, 3.0))
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(0.5, 0.1),
        requests=[mechlib.PointKinematics("v", "tip", "velocity", frame="bar")],
    )
    v = _vector(sol, "v", ("x", "y", "z"))
    assert np.abs(v - [0.0, 3.0 * BAR.length, 0.0]).max() < 1e-9 * 3.0 * BAR.length


def test_angle_channel_of_a_fast_wheel() -> None:
    """A free wheel (no gravity) spinning at 7.5 rev/s, outputs every 0.1 s: its angle
    channel is omega t (gen-alpha accuracy at default tolerance: 1e-3 rad)."""
    omega = 2.0 * math.pi * 7.5
    sol = mechlib.solve(
        hinged_bar(BAR, gravity=0.0),
        mechlib.Dynamic(0.3, 0.1),
        initial=[mechlib.InitialValue("hinge", 0.0, omega)],
        requests=[mechlib.JointCoordinate("angle", "hinge")],
    )
    assert sol.ok
    assert np.abs(sol.channels["angle.value"] - omega * sol.time).max() < 1e-3
