"""Joint friction in dynamic runs: the motion it produces against closed forms and against an
independent integration with exact stick/slip switching (tests/verification/stick_slip.py).

The friction a dynamic run applies must be the friction its requests report, mu r |F| +
preload from the joint's own reaction (seed 003 eq. 2.2), on revolute, cylindrical,
spherical and prismatic joints, with and without preload; a joint loaded below its capacity
sticks. Tolerance 1e-3 relative unless stated (the acceptance of issue 9); each test also
guards the accuracy measured at the time of writing (2026-11-23) a little above it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import LIBRARY, estimate_off
from stick_slip import friction_pendulum, integrate_stick_slip

import mechlib

G = 9.81


def _run_case(name: str, **parameters: float):
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    solution = run_case(estimate_off(load_case(LIBRARY / "elements" / name, parameters))).solution
    assert solution.ok, solution.message
    return solution


# ---- the wheel (revolute, cylindrical) -----------------------------------------------------
WHEEL_MASS, WHEEL_INERTIA, MU, PIN = 10.0, 0.1, 0.2, 0.05  # kg, kg*m^2, -, m


def test_wheel_accelerates_with_the_full_friction_torque() -> None:
    """wheel_friction.case.yaml: angle(1 s) = (2 - mu r m g) / I / 2 = 5.095 rad; the
    friction request reports mu r m g = 0.981 N*m. Measured: 5.09328 (3.4e-4 relative, the
    integrator's phase error on a rotation at tolerance 1e-6 with the dense output of 0.7.0;
    5.09405, 1.9e-4, with `output: steps`; 5.0952 at 1e-9, where the
    regularised law's start adds 2e-4 rad). Rejected steps below 10 % of accepted (measured
    9 of 148; 29 of 154 while a step change carried the integrator's own velocity whole:
    at a constant step the error estimate then alternated by +-12 %, an index-3 transient,
    and a growth the error law allowed after a low one was rejected after the next high
    one; rules.constraint_velocity)."""
    sol = _run_case("wheel_friction.case.yaml")
    torque = MU * PIN * WHEEL_MASS * G
    expected = 0.5 * (2.0 - torque) / WHEEL_INERTIA
    assert sol.channels["a.value"][-1] == pytest.approx(expected, rel=1e-3)
    assert sol.channels["a.value"][-1] == pytest.approx(expected, rel=7e-4)  # measured 3.4e-4
    np.testing.assert_allclose(sol.channels["rub.value"][1:], torque, rtol=1e-9)
    assert sol.stats.rejected_steps < 0.1 * sol.stats.steps


def test_wheel_driven_below_its_friction_torque_does_not_turn() -> None:
    """Drive 0.9 N*m < mu r m g = 0.981 N*m: the wheel sticks (within the 1e-6 rad stick
    threshold of the elasto-plastic anchor) and the friction carries the whole drive."""
    sol = _run_case("wheel_friction.case.yaml", drive_torque=0.9)
    assert np.abs(sol.channels["a.value"]).max() < 1e-5
    assert sol.channels["rub.value"][-1] == pytest.approx(0.9, rel=1e-3)
    assert sol.stats.rejected_steps < 0.1 * sol.stats.steps


def _disc(joint_type: str, preload: float, omega0: float) -> mechlib.Mechanism:
    """A disc (m = 10 kg, I = 0.1 kg*m^2 about z) on a horizontal axle through its centre,
    spinning at omega0 (rad/s), pin (or ball) friction mu 0.2, r 0.05 m and `preload`."""
    mech = mechlib.Mechanism(name="disc", gravity=(0.0, -G, 0.0))
    mech.add_body("disc", mass=WHEEL_MASS, cm=(0, 0, 0), inertia=[0.05, 0.05, WHEEL_INERTIA])
    mech.add_point("rim", body="disc", at=(0.2, 0.0, 0.0))
    axis = {} if joint_type == "spherical" else {"axis": (0, 0, 1)}
    mech.add_joint("axle", joint_type, bodies=("disc", "ground"), at=(0, 0, 0), **axis)
    mech.add_force(mechlib.JointFriction("rub", "axle", MU, PIN, preload))
    return mech


@pytest.mark.parametrize("joint_type", ["revolute", "cylindrical", "spherical"])
@pytest.mark.parametrize("preload", [0.0, 0.3])
def test_disc_spins_down_at_constant_rate_and_stops(joint_type: str, preload: float) -> None:
    """The issue's disc decelerated at 4.5, 4.8, 4.1, 3.8 rad/s^2 over successive seconds
    instead of a constant 4.81. Here: omega0 = 10 rad/s, deceleration T / I with
    T = mu r m g + preload (0.981 or 1.281 N*m) constant until it stops at t = omega0 I / T,
    then it stays at rest (stick). The rim point's speed is omega * 0.2 m. Tolerance 1e-3
    of omega0 on the rate history, 1e-3 relative on the angle turned."""
    torque = MU * PIN * WHEEL_MASS * G + preload
    mech = _disc(joint_type, preload, 10.0)
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=1.5, step=0.01),
        initial=[mechlib.InitialBodyVelocity("disc", omega=(0, 0, 10.0))],
        requests=[mechlib.PointKinematics("rim", "rim", "velocity")],
    )
    assert sol.ok, sol.message
    t = sol.time
    omega = np.hypot(sol.channels["rim.x"], sol.channels["rim.y"]) / 0.2
    expected = np.maximum(10.0 - torque / WHEEL_INERTIA * t, 0.0)
    np.testing.assert_allclose(omega, expected, atol=1e-3 * 10.0)
    turned = np.sum(0.5 * (omega[1:] + omega[:-1]) * np.diff(t))  # trapezoid of the outputs
    assert turned == pytest.approx(0.5 * 10.0**2 * WHEEL_INERTIA / torque, rel=2e-3)
    assert sol.stats.rejected_steps < 0.1 * sol.stats.steps


# ---- the block on a ramp (prismatic) ---------------------------------------------------------
RAMP = math.radians(25.0)


@pytest.mark.parametrize("mu, preload", [(0.35, 0.0), (0.2, 2.0)])
def test_block_slides_down_the_ramp_with_the_full_friction(mu: float, preload: float) -> None:
    """a = g (sin 25 - mu cos 25) - preload / m; travel(1 s) = a / 2 (0.5174 m for mu
    0.35, the issue's repro, which travelled 0.893 m). Measured 5e-5 relative."""
    sol = _run_case("block_on_ramp.case.yaml", mu=mu, preload=preload)
    a = G * (math.sin(RAMP) - mu * math.cos(RAMP)) - preload / 2.5
    assert sol.channels["travel.value"][-1] == pytest.approx(0.5 * a, rel=1e-3)
    assert sol.channels["travel.value"][-1] == pytest.approx(0.5 * a, rel=2e-4)
    np.testing.assert_allclose(
        sol.channels["rub.value"][1:], mu * 2.5 * G * math.cos(RAMP) + preload, rtol=1e-9
    )
    assert sol.stats.rejected_steps < 0.1 * sol.stats.steps


def test_block_held_by_friction_stays_put() -> None:
    """mu 0.5 > tan 25 deg = 0.466: the block must not move: within 1e-4 m over 1 s (the
    elasto-plastic anchor allows 1e-6 m), and the friction holds m g sin 25 deg."""
    sol = _run_case("block_on_ramp.case.yaml", mu=0.5)
    assert np.abs(sol.channels["travel.value"]).max() < 1e-4
    assert np.abs(sol.channels["travel.value"]).max() < 2e-6
    assert sol.channels["rub.value"][-1] == pytest.approx(2.5 * G * math.sin(RAMP), rel=1e-3)


# ---- a pendulum with pin friction, swinging down to rest --------------------------------------
BAR_MASS, BAR_LENGTH, BAR_MU, BAR_PIN, BAR_PRELOAD = 2.0, 1.0, 0.2, 0.02, 1.0


def _friction_pendulum(joint_type: str) -> mechlib.Mechanism:
    """A 2 kg, 1 m bar hinged at one end (axis z for a revolute; a ball of radius 0.02 m
    for a spherical joint), lying along +x, pin friction mu 0.2 r 0.02 m + 1 N*m preload."""
    mech = mechlib.Mechanism(name="bar", gravity=(0.0, -G, 0.0))
    i_cm = BAR_MASS * BAR_LENGTH**2 / 12.0
    mech.add_body("bar", mass=BAR_MASS, cm=(BAR_LENGTH / 2, 0, 0), inertia=[1e-4, i_cm, i_cm])
    mech.add_point("tip", body="bar", at=(BAR_LENGTH, 0.0, 0.0))
    axis = {} if joint_type == "spherical" else {"axis": (0, 0, 1)}
    mech.add_joint("hinge", joint_type, bodies=("bar", "ground"), at=(0, 0, 0), **axis)
    mech.add_force(mechlib.JointFriction("rub", "hinge", BAR_MU, BAR_PIN, BAR_PRELOAD))
    return mech


@pytest.fixture(scope="module")
def pendulum_reference():
    """Exact stick/slip solution: released horizontally at rest, it swings five times and
    sticks at -88.35 deg (where the weight moment falls within the friction capacity)."""
    system = friction_pendulum(BAR_MASS, BAR_LENGTH, BAR_MU * BAR_PIN, BAR_PRELOAD, G)
    return integrate_stick_slip(system, 0.0, 0.0, 6.0)


@pytest.mark.parametrize("joint_type", ["revolute", "spherical"])
def test_pendulum_with_pin_friction_decays_to_rest(joint_type: str, pendulum_reference) -> None:
    """Angle history within 1e-3 of the first amplitude (2.81 rad) and the final rest angle
    within 1e-4 rad of the exact one (measured 1.1e-3 rad and 9e-5 rad at 0.02 s outputs);
    every turning point of the reference is matched by the engine's swing extremes
    (within 1e-3 rad at 0.02 s outputs, 1e-5 rad measured at 1 ms outputs). A spherical
    joint's friction uses the whole reaction force, which is in the swing plane here: the
    same motion."""
    sol = mechlib.solve(
        _friction_pendulum(joint_type),
        mechlib.Dynamic(end=6.0, step=0.02),
        requests=[mechlib.PointKinematics("tip", "tip")],
    )
    assert sol.ok, sol.message
    angle = np.arctan2(sol.channels["tip.y"], sol.channels["tip.x"])
    exact = pendulum_reference.position(sol.time)
    first_amplitude = abs(pendulum_reference.turns[0][1])
    assert np.abs(angle - exact).max() < 1e-3 * first_amplitude
    assert len(pendulum_reference.turns) == 6
    stuck_at = pendulum_reference.stuck_at[1]
    # a spherical joint has no exact stick: it creeps below v_threshold once at rest
    assert angle[-1] == pytest.approx(stuck_at, abs=1e-4 if joint_type == "revolute" else 5e-4)
    for t_turn, x_turn in pendulum_reference.turns:
        near = np.abs(sol.time - t_turn) < 0.05
        extreme = angle[near].min() if x_turn < angle[near].mean() + 1e-12 else angle[near].max()
        assert extreme == pytest.approx(x_turn, abs=1e-3)
    assert sol.stats.rejected_steps < 0.1 * sol.stats.steps


def test_engine_friction_matches_what_the_integrator_applied() -> None:
    """The friction torque reported along the pendulum's swing equals I alpha + the weight
    moment (the torque balance about the hinge with the motion the run produced,
    differentiated from the outputs), so the reported friction is the applied one.
    Tolerance 2 % of the capacity (second differences of 1 ms outputs)."""
    mech = _friction_pendulum("revolute")
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=0.8, step=0.001),
        requests=[mechlib.JointCoordinate("a", "hinge"), mechlib.ElementOutput("rub", "rub")],
    )
    assert sol.ok, sol.message
    a, t = sol.channels["a.value"], sol.time
    alpha = np.gradient(np.gradient(a, t), t)
    inertia = BAR_MASS * BAR_LENGTH**2 / 3.0
    applied = -(inertia * alpha + BAR_MASS * G * BAR_LENGTH / 2 * np.cos(a))
    inside = slice(5, -5)
    capacity = sol.channels["rub.capacity"][inside]
    np.testing.assert_allclose(
        sol.channels["rub.value"][inside], applied[inside], atol=0.02 * capacity.max()
    )
