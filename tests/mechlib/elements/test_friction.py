"""Joint friction: T = mu r |F_r| + preload (seed 003 eq. 2.2) in quasi-static and
kinematic analyses, on a bar hinged at one end (m = 2 kg, L = 1 m, gravity -y, axis +z)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechlib
from mechlib.elements.regularize import coulomb_factor, coulomb_vector

from .._models import Bar, G, Ramp, Sine, hinged_bar

BAR = Bar()
MU, RADIUS, PRELOAD = 0.2, 0.01, 0.5  # -, m, N*m


def _drive(friction: bool, analysis, joint_type: str = "revolute", slope: float = 0.5):
    mech = hinged_bar(BAR, joint_type=joint_type)
    if friction:
        mech.add_force(mechlib.JointFriction("rub", "hinge", MU, RADIUS, PRELOAD))
    mech.add_motion("drive", joint="hinge", function=Ramp(0.0, slope))
    sol = mechlib.solve(mech, analysis, requests=[mechlib.MotionEffort("drive", "drive")])
    assert sol.ok, sol.message
    return sol.channels["drive.value"]


def test_quasi_static_drive_needs_mu_r_f_plus_preload_more() -> None:
    """Raising the bar quasi-statically: the hinge carries the weight m g whatever the
    angle (no inertia), so the drive torque grows by mu r m g + preload = 0.53924 N*m
    exactly once the bar moves (the first state has no travel yet: no friction).
    Tolerance 1e-9 N*m (static Newton converges to 1e-10 of the weight)."""
    analysis = mechlib.QuasiStatic(end=1.0, step=0.25)
    extra = _drive(True, analysis) - _drive(False, analysis)
    expected = MU * RADIUS * BAR.mass * G + PRELOAD
    assert extra[0] == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(extra[1:], expected, atol=1e-9)


def test_quasi_static_friction_opposes_the_direction_of_travel() -> None:
    """Lowering the bar: the drive torque drops by the same amount."""
    analysis = mechlib.QuasiStatic(end=1.0, step=0.25)
    extra = _drive(True, analysis, slope=-0.5) - _drive(False, analysis, slope=-0.5)
    np.testing.assert_allclose(extra[1:], -(MU * RADIUS * BAR.mass * G + PRELOAD), atol=1e-9)


def test_kinematic_friction_uses_the_inertial_reaction() -> None:
    """Turning at 0.5 rad/s (above the 1e-3 rad/s threshold): the hinge force is the
    weight plus the centripetal force m w^2 L/2 along the bar; the extra drive torque is
    mu r |F| + preload with that force. Tolerance 1e-9 N*m."""
    omega = 0.5
    analysis = mechlib.Kinematic(end=1.0, step=0.25)
    extra = _drive(True, analysis, slope=omega) - _drive(False, analysis, slope=omega)
    angle = omega * np.linspace(0.0, 1.0, 5)
    weight = np.stack([np.zeros(5), -np.full(5, BAR.mass * G)])
    # force on the bar from the hinge = m a_cm - m g; a_cm = -w^2 L/2 (cos, sin)
    a_cm = -(omega**2) * BAR.length / 2 * np.stack([np.cos(angle), np.sin(angle)])
    hinge = BAR.mass * a_cm - weight
    np.testing.assert_allclose(
        extra, MU * RADIUS * np.linalg.norm(hinge, axis=0) + PRELOAD, atol=1e-9
    )


def test_regularised_law_is_smooth_and_saturates() -> None:
    """g(s) = s (3 - s^2)/2: 0 at rest, slope 1.5/threshold, exactly 1 from the threshold."""
    assert coulomb_factor(0.0, 1e-3) == 0.0
    assert coulomb_factor(2e-3, 1e-3) == 1.0 and coulomb_factor(-5.0, 1e-3) == -1.0
    assert coulomb_factor(1e-9, 1e-3) == pytest.approx(1.5e-6)
    v = coulomb_vector(np.array([3e-3, 4e-3, 0.0]), 1e-3)
    np.testing.assert_allclose(v, [0.6, 0.8, 0.0])
    assert np.all(coulomb_vector(np.zeros(3), 1e-3) == 0.0)


def test_free_swing_with_pin_friction_stops_without_chatter() -> None:
    """A bar released horizontally with a 3 N*m friction preload swings down, and back,
    losing energy to friction, and comes to rest near the bottom; the regularised law
    (continuous, finite slope) lets the integrator pass the stops without chatter.
    Step count bounded (< 3000), mechanical energy never grows (1e-6 J allowance for the
    integrator), at rest at the end (below the 1e-3 rad/s threshold speed x 5)."""
    mech = hinged_bar(BAR)
    mech.add_force(mechlib.JointFriction("rub", "hinge", MU, RADIUS, 3.0))
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=3.0, step=0.01),
        requests=[
            mechlib.JointCoordinate("a", "hinge"),
            mechlib.JointCoordinate("w", "hinge", "omega"),
        ],
    )
    assert sol.ok, sol.message
    a, w = sol.channels["a.value"], sol.channels["w.value"]
    energy = 0.5 * BAR.i_end * w**2 + BAR.mass * G * BAR.length / 2 * np.sin(a)
    assert np.all(np.diff(energy) <= 1e-6)
    assert abs(w[-1]) < 5e-3  # at rest (creeping below the threshold speed)
    assert sol.stats.steps < 3000


def test_dynamic_friction_on_a_driven_joint_never_tries_to_stick_against_the_motion() -> None:
    """A motion swings the bar to and fro (sine): the hinge's slip rate passes through zero
    twice a period, but the motion already fixes the coordinate, so the friction does not
    stick (its hold equation would be redundant) and the run does not fail. The motion
    prescribes the same kinematics with and without friction, so the drive torque with
    friction exceeds the one without by the friction it reports (1e-3 N*m: the outputs'
    one-step correction to the equations of motion, measured 4e-4 N*m against a friction of
    0.54 N*m), which never exceeds its capacity mu r |F| + preload."""
    analysis = mechlib.Dynamic(end=1.0, step=0.01)
    solutions = []
    for friction in (True, False):
        mech = hinged_bar(BAR)
        if friction:
            mech.add_force(mechlib.JointFriction("rub", "hinge", MU, RADIUS, PRELOAD))
        mech.add_motion("drive", joint="hinge", function=Sine(0.0, 0.3, 2.0 * np.pi))
        requests = [mechlib.MotionEffort("drive", "drive")]
        requests += [mechlib.ElementOutput("rub", "rub")] if friction else []
        solutions.append(mechlib.solve(mech, analysis, requests=requests))
        assert solutions[-1].ok, solutions[-1].message
    rub, bare = solutions
    capacity, value = rub.channels["rub.capacity"], rub.channels["rub.value"]
    np.testing.assert_allclose(
        rub.channels["drive.value"] - bare.channels["drive.value"], value, atol=1e-3
    )
    assert np.all(np.abs(value) <= capacity * (1 + 1e-12)) and capacity.min() >= PRELOAD
    assert np.abs(value).max() > 0.99 * PRELOAD


def _two_link_arm(shoulder_hold: float, elbow_hold: float, end: float = 0.5) -> mechlib.Solution:
    """Two 1 kg, 1 m links (uniform bars) hinged at the origin and at x = 1 m about +z,
    horizontal and at rest under gravity -y; each joint's friction a preload only (N*m),
    `end` s dynamic."""
    mech = mechlib.Mechanism(name="arm", gravity=(0.0, -G, 0.0))
    inertia = [1e-3, 1.0 / 12.0, 1.0 / 12.0]
    mech.add_body("upper", mass=1.0, cm=(0.5, 0.0, 0.0), inertia=inertia)
    mech.add_body("lower", mass=1.0, cm=(1.5, 0.0, 0.0), inertia=inertia)
    z = (0.0, 0.0, 1.0)
    mech.add_joint("shoulder", "revolute", bodies=("upper", "ground"), at=(0, 0, 0), axis=z)
    mech.add_joint("elbow", "revolute", bodies=("lower", "upper"), at=(1, 0, 0), axis=z)
    mech.add_force(mechlib.JointFriction("f_shoulder", "shoulder", 0.0, preload=shoulder_hold))
    mech.add_force(mechlib.JointFriction("f_elbow", "elbow", 0.0, preload=elbow_hold))
    coordinates = [mechlib.JointCoordinate(j, j, "angle") for j in ("shoulder", "elbow")]
    sol = mechlib.solve(mech, mechlib.Dynamic(end=end, step=0.01), requests=coordinates)
    assert sol.ok, sol.message
    return sol


@pytest.mark.parametrize(
    ("holds", "moving"),
    [((30.0, 10.0), None), ((30.0, 2.0), "elbow"), ((10.0, 10.0), "shoulder")],
)
def test_two_joint_frictions_hold_or_slip_each_by_its_own_moment(holds, moving) -> None:
    """Two frictions in one chain (the stick switching re-solves the multipliers after one
    joint changes state, before the next is tested). Gravity moments at rest: shoulder
    m g (0.5 + 1.5) = 19.62 N*m, elbow m g 0.5 = 4.905 N*m. A joint whose preload exceeds
    its moment stays exactly at rest (1e-12 rad); the one that cannot hold turns as the
    closed form of its link alone with a constant friction torque against the motion
    (the other joint held, so a fixed-axis pendulum: I theta'' = -m g d cos(theta) + T_f,
    scipy solve_ivp at 1e-10), within 3e-4 rad over the 0.5 s at the default tolerance
    (measured 1.6e-4 rad elbow, 3.5e-5 rad shoulder, of peaks 1.02 and 0.44 rad; 1.1e-5 and
    2.9e-6 at tolerance 1e-8: the integration error)."""
    from scipy.integrate import solve_ivp

    sol = _two_link_arm(*holds)
    for joint in ("shoulder", "elbow"):
        if joint != moving:
            assert np.abs(sol.channels[f"{joint}.value"]).max() < 1e-12, joint
    if moving is None:
        return
    # the links that turn about the moving joint: its inertia, mass and cm distance
    inertia, mass, arm, hold = {
        "elbow": (1.0 / 12.0 + 0.25, 1.0, 0.5, holds[1]),
        "shoulder": (2.0 / 12.0 + 0.25 + 2.25, 2.0, 1.0, holds[0]),
    }[moving]

    def pendulum(_t, y):
        return [y[1], (-mass * G * arm * np.cos(y[0]) + hold) / inertia]  # falling: w < 0

    t = np.asarray(sol.time)
    ref = solve_ivp(pendulum, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-12)
    assert np.all(ref.y[1][1:] < 0.0)  # still falling at the end: friction against it
    np.testing.assert_allclose(sol.channels[f"{moving}.value"], ref.y[0], atol=3e-4)


def test_a_joint_stopping_while_the_next_is_held_sticks_both() -> None:
    """Issue 13: the shoulder (friction 10 N*m < its gravity moment 19.62 N*m) swings the
    arm down, the elbow held (30 N*m) throughout, and the shoulder stops at its turnaround
    past the vertical, where it sticks while the elbow is held: one switch in which the
    shoulder's new stick equation shifts the elbow's multiplier (an IndexError before
    4fbde85, which re-solves the multipliers before testing the next joint). Closed form
    (energy, the arm rigid: friction work = the cm's drop): the shoulder stops at
    phi = -theta with m g d sin(phi) = T phi (m g d = 19.62 N*m), phi = 1.8731 rad (at
    1.4 s), and holds there (gravity moment 19.62 |cos phi| = 5.9 < 10 N*m): the last
    0.3 s within 1e-4 rad of it (measured 3.4e-5 rad at the default tolerance), exactly
    still; the elbow at rest."""
    from scipy.optimize import brentq

    sol = _two_link_arm(10.0, 30.0, end=1.8)
    stop = brentq(lambda phi: 2.0 * G * math.sin(phi) - 10.0 * phi, 1.0, 3.0, xtol=1e-14)
    shoulder = sol.channels["shoulder.value"]
    assert np.abs(sol.channels["elbow.value"]).max() < 1e-12
    held = np.asarray(sol.time) > 1.5
    assert np.abs(shoulder[held] + stop).max() < 1e-4
    assert np.ptp(shoulder[held]) < 1e-12


def _bar_with_friction(preload: float) -> mechlib.Mechanism:
    mech = hinged_bar(BAR)
    mech.add_force(mechlib.JointFriction("rub", "hinge", MU, RADIUS, preload))
    return mech


_LOCK_REQUESTS = [
    mechlib.JointCoordinate("a", "hinge"),
    mechlib.JointReaction("r", "hinge"),
    mechlib.ElementOutput("rub", "rub"),
]


def _solve_with(mech, analysis, events=()) -> mechlib.Solution:
    sol = mechlib.solve(mech, analysis, events=list(events), requests=_LOCK_REQUESTS)
    assert sol.ok, sol.message
    return sol


def test_a_lock_holds_a_sliding_friction_joint_alone() -> None:
    """The bar falls from horizontal against a 3 N*m friction preload (< its weight moment
    9.81 N*m: it slides) and a latch locks the hinge at -30 deg. A locked joint cannot
    slip: the friction neither sticks nor acts while the lock holds (before, its stick
    equation duplicated the lock's and took 3.04 N*m of the 8.50 N*m hold). Up to the
    lock the rows are those of the same fall without the latch (identical); after it the
    angle stays at -30 deg (1e-9), the friction reports 0 and the lock alone carries the
    weight moment m g L/2 cos(30 deg) = 8.4957 N*m (hand statics, 1e-6)."""
    lock_at = -math.pi / 6
    analysis = mechlib.Dynamic(end=0.6, step=0.01, tolerance=1e-10)
    latch = mechlib.Event(
        "latch",
        lambda t, view: lock_at - view.angle("hinge"),
        (mechlib.Action("lock", "hinge"),),
    )
    sol = _solve_with(_bar_with_friction(3.0), analysis, [latch])
    # the same path as the run with an event (steps from Python; a compiled whole run's
    # iteration matrices differ, its rows by Newton's tolerance)
    free = _solve_with(_bar_with_friction(3.0), dataclasses.replace(analysis, compiled="steps"))
    assert [e.name for e in sol.events] == ["latch"]
    t_lock, time = sol.events[0].time, np.asarray(sol.time)
    before, after = time < t_lock - 1e-9, time > t_lock + 1e-9
    assert before.sum() > 10 and after.sum() > 10
    np.testing.assert_array_equal(time[before], np.asarray(free.time)[: before.sum()])
    for channel in ("a.value", "r.tz", "rub.value"):
        np.testing.assert_array_equal(
            sol.channels[channel][before], free.channels[channel][: before.sum()]
        )
    assert np.abs(sol.channels["a.value"][after] - lock_at).max() < 1e-9
    hold = BAR.weight_moment * math.cos(lock_at)
    np.testing.assert_allclose(sol.channels["r.tz"][after], hold, atol=1e-6)
    assert np.all(sol.channels["rub.value"][after] == 0.0)


def test_a_lock_on_a_stuck_friction_joint_replaces_its_stick() -> None:
    """The bar held horizontal by its friction (20 N*m preload > 9.81 N*m) is locked at
    t = 0.1 s: the lock's equation replaces the stick's (before, the two made the system
    redundant: 'rub: stick: stuck angle, dependent on hinge'). The hold moves from the
    friction to the lock, m g L/2 = 9.81 N*m (1e-6); the bar never moves (1e-9)."""
    lock = mechlib.Event("lock", lambda t, view: t - 0.1, (mechlib.Action("lock", "hinge"),))
    sol = _solve_with(
        _bar_with_friction(20.0), mechlib.Dynamic(end=0.3, step=0.01, tolerance=1e-10), [lock]
    )
    time = np.asarray(sol.time)
    assert abs(sol.events[0].time - 0.1) < 1e-9
    assert np.abs(sol.channels["a.value"]).max() < 1e-9
    after = time > 0.1 + 1e-9
    np.testing.assert_allclose(sol.channels["r.tz"][after], BAR.weight_moment, atol=1e-6)
    assert np.all(sol.channels["rub.value"][after] == 0.0)
    stuck = time < 0.1 - 1e-9
    np.testing.assert_allclose(sol.channels["rub.value"][stuck], -BAR.weight_moment, atol=1e-6)


def test_friction_resumes_from_the_actual_state_when_a_lock_is_released() -> None:
    """A phase locks the hinge (bar horizontal) for 0.2 s, the next lets it go: the friction
    (3 N*m preload) carries nothing while locked and then slides as in a fall from rest
    without the lock (the same rows 0.2 s later, 1e-9 rad, 3e-9 N*m: the two runs' steps
    differ at round-off, 1.6e-9 N*m measured since Newton's acceleration floor is 10 eps,
    5e-10 of the torque at tolerance 1e-10)."""
    step = {"step": 0.01, "tolerance": 1e-10}
    phases = mechlib.Phases(
        (
            mechlib.Phase(mechlib.Dynamic(start=0.0, end=0.2, **step), "held", ("hinge",)),
            mechlib.Phase(mechlib.Dynamic(start=0.2, end=0.5, **step), "free"),
        )
    )
    sol = _solve_with(_bar_with_friction(3.0), phases)
    free = _solve_with(_bar_with_friction(3.0), mechlib.Dynamic(end=0.3, **step))
    time = np.asarray(sol.time)
    held = time < 0.2 - 1e-9
    assert np.all(sol.channels["rub.value"][held] == 0.0)
    np.testing.assert_allclose(sol.channels["r.tz"][held], BAR.weight_moment, atol=1e-6)
    for t in (0.25, 0.3, 0.4, 0.5):
        i, j = np.argmin(abs(time - t)), np.argmin(abs(np.asarray(free.time) - (t - 0.2)))
        assert sol.channels["a.value"][i] == pytest.approx(free.channels["a.value"][j], abs=1e-9)
        assert sol.channels["rub.value"][i] == pytest.approx(
            free.channels["rub.value"][j], abs=3e-9
        )
