"""Joint library: mobility of every joint type, joint-coordinate signs, angle unwrapping.

Constraint counts are the textbook ones (Haug 1989, table 9.x; Nikravesh 1988, ch. 6):
fixed 6, revolute 5, spherical 3, cylindrical 4, prismatic 5, universal 4, planar 3,
screw 5 (cylindrical + travel = pitch * angle / 2 pi), inline 2, inplane 1, parallel 2,
perpendicular 1, orientation 3; a coupler or gear adds one equation between two joint
coordinates.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib
from mechlib.core.rotation import quaternion_from_rotvec, rotate
from mechlib.model.mechanism import JOINT_TYPES
from mechlib.system.system import System

from ._models import Ramp

AXIS = np.array([1.0, 2.0, 2.0]) / 3.0  # a skew unit axis: no global-axis luck
OTHER = np.cross(AXIS, [0.0, 0.0, 1.0])
OTHER /= np.linalg.norm(OTHER)  # perpendicular to AXIS
CM = (0.3, -0.2, 0.5)  # body centre of mass (m)
AT = (0.1, 0.4, -0.2)  # joint point (m)
PITCH = 0.01  # screw lead (m per revolution)

CONSTRAINTS = {
    "fixed": 6,
    "revolute": 5,
    "spherical": 3,
    "cylindrical": 4,
    "prismatic": 5,
    "universal": 4,
    "planar": 3,
    "screw": 5,
    "inline": 2,
    "inplane": 1,
    "parallel": 2,
    "perpendicular": 1,
    "orientation": 3,
    "point_on_curve": 2,
}
BEND = np.cross(AXIS, OTHER)  # the curve of point_on_curve bends this way
CURVE_RADIUS = 0.5  # m


def _arc(angle: float) -> np.ndarray:
    """Point of the circular arc through AT (tangent OTHER, centre AT + R BEND) at angle."""
    return (
        np.asarray(AT)
        + CURVE_RADIUS * math.sin(angle) * OTHER
        + CURVE_RADIUS * (1.0 - math.cos(angle)) * BEND
    )


KEYS = {
    "fixed": {},
    "spherical": {},
    "orientation": {"axis": AXIS},
    "revolute": {"axis": AXIS},
    "cylindrical": {"axis": AXIS},
    "prismatic": {"axis": AXIS},
    "screw": {"axis": AXIS, "pitch": PITCH},
    "inline": {"axis": AXIS},
    "parallel": {"axis": AXIS},
    "planar": {"normal": AXIS},
    "inplane": {"normal": AXIS},
    "universal": {"axes": (AXIS, OTHER)},
    "perpendicular": {"axes": (AXIS, OTHER)},
    "point_on_curve": {"curve": [_arc(a) for a in np.linspace(-1.0, 1.0, 21)]},
}


def _one_body(
    joint_type: str, *, body1: str = "body", body2: str = "ground", extra_body: str | None = None
) -> mechlib.Mechanism:
    """One body (plus optionally a second, `extra_body`) joined by `joint_type` joint `J`."""
    mech = mechlib.Mechanism()
    mech.add_body("body", mass=1.0, cm=CM, inertia=[0.1, 0.2, 0.3])
    if extra_body:
        mech.add_body(extra_body, mass=1.0, cm=(0.0, 0.0, 1.0), inertia=[0.1, 0.2, 0.3])
    mech.add_joint("J", joint_type, bodies=(body1, body2), at=AT, **KEYS[joint_type])
    return mech


def _two_cranks(joint_type: str) -> mechlib.Mechanism:
    """Two bodies on revolutes R1, R2 to ground, coupled by `joint_type` (ratio 2)."""
    mech = mechlib.Mechanism()
    for i, z in ((1, 0.0), (2, 1.0)):
        mech.add_body(f"b{i}", mass=1.0, cm=(0.5, 0.0, z), inertia=[0.1, 0.2, 0.3])
        mech.add_joint(
            f"R{i}", "revolute", bodies=(f"b{i}", "ground"), at=(0.0, 0.0, z), axis=(0.0, 0.0, 1.0)
        )
    mech.add_joint("K", joint_type, bodies=("b1", "b2"), joints=("R1", "R2"), ratio=2.0)
    return mech


def test_every_joint_type_is_covered() -> None:
    """The tables of this module list every type mechlib knows."""
    assert set(CONSTRAINTS) | {"coupler", "gear"} == set(JOINT_TYPES)


@pytest.mark.parametrize("joint_type", sorted(CONSTRAINTS))
def test_degrees_of_freedom_of_one_body_on_ground(joint_type: str) -> None:
    """6 - (textbook constraint count) degrees of freedom, exact integer; no redundant
    equation, and the design position is assembled."""
    check = mechlib.inspect_mechanism(_one_body(joint_type))
    assert check.degrees_of_freedom == 6 - CONSTRAINTS[joint_type]
    assert check.redundant == ()
    assert check.assembled


@pytest.mark.parametrize("joint_type", ["coupler", "gear"])
def test_coupler_and_gear_remove_one_freedom(joint_type: str) -> None:
    """Two cranks (1 freedom each) coupled: 12 - 2 x 5 - 1 = 1 degree of freedom."""
    check = mechlib.inspect_mechanism(_two_cranks(joint_type))
    assert check.degrees_of_freedom == 1
    assert check.redundant == ()


@pytest.mark.parametrize("joint_type", ["revolute", "cylindrical", "screw"])
def test_degrees_of_freedom_between_two_moving_bodies(joint_type: str) -> None:
    """The same count holds between two moving bodies: 12 - 6 (fixed body) - n."""
    mech = _one_body(joint_type, body2="other", extra_body="other")
    mech.add_joint("hold", "fixed", bodies=("other", "ground"), at=(0.0, 0.0, 1.0))
    check = mechlib.inspect_mechanism(mech)
    assert check.degrees_of_freedom == 6 - CONSTRAINTS[joint_type]
    assert check.redundant == ()


def _rotated_state(system: System, body: str, angle: float, shift: float = 0.0) -> np.ndarray:
    """Design q with `body` turned by `angle` (rad) about AXIS through AT and moved `shift`
    (m) along AXIS: every joint of the tests stays assembled."""
    q = system.design_q().reshape(-1, 7)
    b = system.body_index(body)
    p = quaternion_from_rotvec(angle * AXIS)
    q[b, :3] = np.asarray(AT) + rotate(p, np.asarray(CM) - np.asarray(AT)) + shift * AXIS
    q[b, 3:] = p
    return q.ravel()


@pytest.mark.parametrize("joint_type", ["revolute", "cylindrical", "screw"])
def test_angle_sign_is_right_handed_body1_relative_to_body2(joint_type: str) -> None:
    """Turning body 1 by +0.3 rad about the axis reads +0.3 (right-hand rule); with the
    ground as body 1 the same motion reads -0.3. Exact geometry: 1e-12 rad."""
    for body1, body2, sign in (("body", "ground", 1.0), ("ground", "body", -1.0)):
        system = System(_one_body(joint_type, body1=body1, body2=body2))
        q = _rotated_state(system, "body", 0.3)
        value = system.measure("J", "angle").value(system.kin(q))
        assert value == pytest.approx(sign * 0.3, abs=1e-12)
        geometric = system.phi(system.kin(q))[: system.n_geometric]
        assert np.abs(geometric).max() < 1e-12, "the turned state must satisfy the joint"


def test_angle_is_relative_when_both_bodies_move() -> None:
    """Body 1 turned by 0.5 rad, body 2 by 0.2 rad about the same axis: angle 0.3 rad."""
    mech = _one_body("revolute", body2="other", extra_body="other")
    system = System(mech)
    q = _rotated_state(system, "body", 0.5).reshape(-1, 7)
    b2 = system.body_index("other")
    p2 = quaternion_from_rotvec(0.2 * AXIS)
    q[b2, :3] = np.asarray(AT) + rotate(p2, system.cm[b2] - np.asarray(AT))
    q[b2, 3:] = p2
    value = system.measure("J", "angle").value(system.kin(q.ravel()))
    assert value == pytest.approx(0.3, abs=1e-12)


@pytest.mark.parametrize("joint_type", ["prismatic", "cylindrical"])
def test_travel_sign_is_along_the_axis(joint_type: str) -> None:
    """Moving body 1 by +0.05 m along the axis reads +0.05 m (1e-14 m); with ground as
    body 1 it reads -0.05 m."""
    for body1, body2, sign in (("body", "ground", 1.0), ("ground", "body", -1.0)):
        system = System(_one_body(joint_type, body1=body1, body2=body2))
        q = _rotated_state(system, "body", 0.0, shift=0.05)
        value = system.measure("J", "travel").value(system.kin(q))
        assert value == pytest.approx(sign * 0.05, abs=1e-14)


def test_screw_advances_pitch_per_revolution() -> None:
    """A screw driven to +0.3 rad is assembled at travel pitch * 0.3 / (2 pi) (1e-12 m)."""
    mech = _one_body("screw")
    mech.add_motion("turn", joint="J", function=Ramp(0.3, 0.0), coordinate="angle")
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(0.0, 1.0),
        requests=[
            mechlib.JointCoordinate("s", "J", "travel"),
            mechlib.JointCoordinate("a", "J", "angle"),
        ],
    )
    assert sol.channels["a.value"][0] == pytest.approx(0.3, abs=1e-12)
    assert sol.channels["s.value"][0] == pytest.approx(PITCH * 0.3 / (2 * math.pi), abs=1e-12)


def test_gear_ratio_relates_the_coordinates() -> None:
    """R1 driven to 0.2 rad through a gear of ratio 2: R2 at 0.4 rad (1e-12)."""
    mech = _two_cranks("gear")
    mech.add_motion("drive", joint="R1", function=Ramp(0.2, 0.0))
    sol = mechlib.solve(
        mech, mechlib.Kinematic(0.0, 1.0), requests=[mechlib.JointCoordinate("a2", "R2")]
    )
    assert sol.channels["a2.value"][0] == pytest.approx(0.4, abs=1e-12)


def test_revolute_angle_unwraps_past_pi() -> None:
    """A crank driven at 2 rev/s for 1 s: the angle channel runs continuously to 4 pi
    (1e-9 rad, brief), increases monotonically and equals 4 pi t at every output
    (the driver equation is solved to 1e-10)."""
    mech = mechlib.Mechanism()
    mech.add_body("crank", mass=1.0, cm=(0.05, 0.0, 0.0), inertia=[1e-4, 1e-3, 1e-3])
    mech.add_joint("A", "revolute", bodies=("crank", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_motion("spin", joint="A", function=Ramp(0.0, 4.0 * math.pi))
    sol = mechlib.solve(
        mech, mechlib.Kinematic(1.0, 0.01), requests=[mechlib.JointCoordinate("angle", "A")]
    )
    angle = sol.channels["angle.value"]
    assert sol.ok
    assert angle[-1] == pytest.approx(4.0 * math.pi, abs=1e-9)
    assert np.all(np.diff(angle) > 0.0)
    assert np.abs(angle - 4.0 * math.pi * sol.time).max() < 1e-9


def test_large_initial_angle_assembles_without_wrapping() -> None:
    """An initial hinge angle of 170 deg (and -170 deg) is reached as given, not wrapped to
    the other side: assembly approaches it in stages (regression: it landed at -164.5 deg)."""
    import math

    for degrees in (170.0, -170.0, 300.0):
        mech = mechlib.Mechanism()
        mech.add_body("bar", mass=1.0, cm=(0.5, 0.0, 0.0), inertia=[0.01, 0.1, 0.1])
        mech.add_joint("hinge", "revolute", bodies=("bar", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
        value = math.radians(degrees)
        sol = mechlib.solve(
            mech,
            mechlib.Dynamic(end=0.01, step=0.01),
            initial=[mechlib.InitialValue("hinge", value)],
            requests=[mechlib.JointCoordinate("a", "hinge", "angle")],
        )
        assert not sol.warnings
        assert sol.channels["a.value"][0] == pytest.approx(value, abs=1e-9)


def test_hinge_line_of_spherical_and_inline_has_the_revolute_angle() -> None:
    """A bar hinged by a spherical joint at one end of its hinge line and an inline joint
    (axis along the line) at the other swings exactly as on one revolute: the inline's
    angle, omega and alpha equal the revolute's (1e-7 rad, rad/s, rad/s^2 over 1 s of a
    pendulum swing from 60 deg; same integrator, same tolerance), and its travel stays 0."""

    def bar(hinge: str) -> mechlib.Mechanism:
        mech = mechlib.Mechanism(gravity=(0.0, 0.0, -9.81))
        mech.add_body("bar", mass=2.0, cm=(0.0, 0.3, 0.0), inertia=[0.06, 0.01, 0.06])
        if hinge == "revolute":
            mech.add_joint(
                "H", "revolute", bodies=("bar", "ground"), at=(-0.2, 0, 0), axis=(1, 0, 0)
            )
        else:
            mech.add_joint("S", "spherical", bodies=("bar", "ground"), at=(0.2, 0, 0))
            mech.add_joint("H", "inline", bodies=("bar", "ground"), at=(-0.2, 0, 0), axis=(1, 0, 0))
        return mech

    requests = [mechlib.JointCoordinate(q, "H", q) for q in ("angle", "omega", "alpha")]
    runs = {}
    for hinge in ("revolute", "inline"):
        extra = [mechlib.JointCoordinate("travel", "H", "travel")] if hinge == "inline" else []
        runs[hinge] = mechlib.solve(
            bar(hinge),
            mechlib.Dynamic(end=1.0, step=0.01, tolerance=1e-8),
            initial=[mechlib.InitialValue("H", math.radians(60.0))],
            requests=requests + extra,
        )
    rev, inl = runs["revolute"], runs["inline"]
    assert rev.ok and inl.ok
    assert np.ptp(rev.channels["angle.value"]) > 1.0  # it does swing
    for q in ("angle", "omega", "alpha"):
        assert np.allclose(inl.channels[f"{q}.value"], rev.channels[f"{q}.value"], atol=1e-7)
    assert np.abs(inl.channels["travel.value"]).max() < 1e-12


def test_point_on_curve_gradient_is_exact_on_the_curve() -> None:
    """Body 1 turned by 0.4 rad about OTHER and moved so that its joint point sits on the
    arc at 0.3 rad: the two equations vanish (1e-9 m, the spline of the arc) and their
    gradient equals central differences of phi (1e-6 relative): holding the nearest-point
    parameter does not change the gradient on the curve."""
    system = System(_one_body("point_on_curve"))
    q = system.design_q().reshape(-1, 7)
    b = system.body_index("body")
    p = quaternion_from_rotvec(0.4 * OTHER)
    q[b, :3] = _arc(0.3) + rotate(p, np.asarray(CM) - np.asarray(AT))
    q[b, 3:] = p
    q = q.ravel()
    phi = system.phi(system.kin(q))
    assert np.abs(phi[-2:]).max() < 1e-9
    grad = system.phi_q(system.kin(q))[-2:]
    fd = np.empty_like(grad)
    for j in range(system.nq):
        dq = np.zeros(system.nq)
        dq[j] = 1e-6
        fd[:, j] = (
            system.phi(system.kin(q + dq))[-2:] - system.phi(system.kin(q - dq))[-2:]
        ) / 2e-6
    assert np.abs(grad - fd).max() < 1e-6 * np.abs(grad).max()


@pytest.mark.parametrize(
    "joint_type, key", [("universal", "axes"), ("perpendicular", "axes"), ("screw", "pitch")]
)
def test_a_joint_without_its_required_key_is_refused_by_name(joint_type: str, key: str) -> None:
    """mechlib used directly (no YAML schema in front): a joint missing the key its type
    needs is a ValueError naming the joint and the key (it was a bare TypeError on None)."""
    mech = mechlib.Mechanism()
    mech.add_body("body", mass=1.0, cm=CM, inertia=[0.1, 0.2, 0.3])
    keys = {k: v for k, v in KEYS[joint_type].items() if k != key}
    mech.add_joint("J", joint_type, bodies=("body", "ground"), at=AT, **keys)
    with pytest.raises(ValueError, match=f"joint J: a {joint_type} joint needs `{key}`"):
        System(mech)


@pytest.mark.parametrize("axis", [(0.0, 0.0, 0.0), (0.0, 1.34e154, 1.34e154), (math.nan, 0, 1)])
def test_joint_frame_refuses_an_axis_it_cannot_normalise(axis) -> None:
    """A zero, overflowing or NaN axis is a ValueError, never an unbound triad (fuzz find)."""
    from mechlib.model.joints import joint_frame

    with pytest.raises(ValueError, match="finite, non-zero"):
        joint_frame(axis)


def test_joint_frame_is_a_right_handed_triad_about_the_axis() -> None:
    from mechlib.model.joints import joint_frame

    triad = joint_frame(3.0 * AXIS)
    f, g, h = triad.f, triad.g, triad.h
    assert np.allclose(h, AXIS, atol=1e-15)
    assert np.allclose(np.cross(f, g), h, atol=1e-15)
    assert abs(f @ h) < 1e-15 and abs(np.linalg.norm(f) - 1.0) < 1e-15


def test_cross_is_numpy_s_to_the_last_bit() -> None:
    """`joints.cross` (a joint triad's g = h x f, the labels' rotation axes) against
    np.cross on 20 000 random float vectors of mixed scales and on integer axes: the same
    values bit for bit."""
    from mechlib.model.joints import cross

    rng = np.random.default_rng(11)
    u = rng.normal(size=(20_000, 3)) * 10.0 ** rng.integers(-8, 8, size=(20_000, 1))
    v = rng.normal(size=(20_000, 3)) * 10.0 ** rng.integers(-8, 8, size=(20_000, 1))
    ours = np.array([cross(a, b) for a, b in zip(u, v)])
    assert np.array_equal(ours.view(np.int64), np.cross(u, v).view(np.int64))
    assert cross((0, 0, 1), (1, 0, 0)).tolist() == np.cross((0, 0, 1), (1, 0, 0)).tolist()
