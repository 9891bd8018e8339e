"""Tension-only wire pendulum (slack and taut again) and tabulated laws (Akima = scipy)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import Akima1DInterpolator

import mechlib
from mechlib.model.tables import Table, TableRangeError

from .._models import G

L, MASS, K = 1.0, 1.0, 1.0e5  # wire length (m), bob mass (kg), wire stiffness (N/m)


def _wire_pendulum(v0: float):
    """A bob hanging on a wire from the origin, launched horizontally at v0 (m/s), the wire
    stretched by the tension of that state, m (g + v0^2/L) (no radial oscillation)."""
    y0 = -(L + MASS * (G + v0**2 / L) / K)
    mech = mechlib.Mechanism(name="wire", gravity=(0.0, -G, 0.0))
    mech.add_body("bob", mass=MASS, cm=(0.0, y0, 0.0), inertia=[1e-3] * 3)
    mech.add_point("bob_cm", body="bob", at=(0.0, y0, 0.0))
    mech.add_force(
        mechlib.Spring(
            "wire",
            (("bob", (0.0, y0, 0.0)), ("ground", (0.0, 0.0, 0.0))),
            stiffness=K,
            free_length=L,
            tension_only=True,
        )
    )
    init = [mechlib.InitialBodyVelocity("bob", velocity=(v0, 0.0, 0.0))]
    return mechlib.solve(
        mech,
        mechlib.Dynamic(end=1.6, step=0.002),
        initial=init,
        requests=[
            mechlib.ElementOutput("wire", "wire"),
            mechlib.PointKinematics("p", "bob_cm", "position"),
            mechlib.PointKinematics("v", "bob_cm", "velocity"),
        ],
        throw=False,
    ), mech


def test_wire_goes_slack_and_taut_again() -> None:
    """v0^2 = 3.5 g L: the bob rises above the hinge level and the wire goes slack where
    the tension of a rigid rope vanishes, cos(phi) = (2 - v0^2/(g L)) / 3 (phi from the
    bottom) = -0.5, phi = 120 deg; it then flies ballistically until the wire is taut again.
    Checks: tension >= 0 always, taut -> slack -> taut, slack angle within 1 deg of the
    rigid-rope value (the wire stretches m v^2/(k L) ~ 1e-4 m), total energy (kinetic +
    potential + wire) bounded: never above its start by more than 1e-3 relative, and
    not below by more than 1% (the snap when the wire is taut again excites its 50 Hz
    axial mode, which generalized-alpha damps numerically: 0.4% measured)."""
    v0 = math.sqrt(3.5 * G * L)
    sol, _ = _wire_pendulum(v0)
    assert sol.ok, sol.message
    tension = sol.channels["wire.value"]
    assert tension.min() >= 0.0
    taut = tension > 0.0
    changes = np.flatnonzero(np.diff(taut.astype(int)))
    assert taut[0] and len(changes) >= 2 and not taut[changes[0] + 1] and taut[changes[1] + 1]
    x, y = sol.channels["p.x"], sol.channels["p.y"]
    phi = math.degrees(math.atan2(x[changes[0]], -y[changes[0]]))
    assert phi == pytest.approx(120.0, abs=1.0)
    speed2 = sol.channels["v.x"] ** 2 + sol.channels["v.y"] ** 2
    stretch = np.maximum(np.hypot(x, y) - L, 0.0)
    energy = 0.5 * MASS * speed2 + MASS * G * y + 0.5 * K * stretch**2
    assert energy.max() <= energy[0] * (1.0 + 1e-3)
    assert energy.min() >= energy[0] * (1.0 - 1e-2)


def test_akima_table_equals_scipy() -> None:
    """The wind-moment table of SPEC 1.2.1 (and a longer, uneven one): Akima values equal
    scipy's Akima1DInterpolator to 1e-12 relative inside the data."""
    for x, y in (
        ([0, 30, 60, 90], [0, 120, 180, 90]),
        ([0.0, 0.1, 0.5, 0.6, 1.2, 2.0, 2.1], [1.0, 3.0, -2.0, 0.5, 0.5, 4.0, 1.0]),
    ):
        x = np.radians(x) if len(x) == 4 else np.asarray(x)
        table, ref = Table("t", x, y, "akima"), Akima1DInterpolator(x, y)
        for v in np.linspace(x[0], x[-1], 97):
            assert table(v) == pytest.approx(float(ref(v)), rel=1e-12, abs=1e-12)


def test_table_extrapolation_rules() -> None:
    """hold: the end value; linear: the end slope; error: a TableLaw names the element."""
    x, y = [0.0, 1.0, 2.0], [0.0, 2.0, 3.0]
    assert Table("t", x, y, "linear", "hold")(3.0) == 3.0
    assert Table("t", x, y, "linear", "linear")(3.0) == pytest.approx(4.0)
    law = mechlib.TableLaw(Table("t", x, y, "linear", "error"), "harness")
    with pytest.raises(mechlib.SolverFailure, match="harness"):
        law(2.5)


def test_torsion_spring_table_law_static_equilibrium() -> None:
    """A harness-like torque table (Akima, torque resisting the angle) holds a 2 kg, 1 m
    bar: equilibrium where table(theta) = -m g L/2 cos(theta), solved by brentq on scipy's
    Akima interpolant; tolerance 1e-8 rad."""
    from scipy.optimize import brentq

    from .._models import Bar, hinged_bar

    bar = Bar()
    angles = np.radians([-90.0, -60.0, -30.0, 0.0, 30.0])
    torques = np.array([-30.0, -20.0, -12.0, -4.0, 6.0])
    ref = Akima1DInterpolator(angles, torques)
    expected = brentq(
        lambda a: float(ref(a)) + bar.weight_moment * math.cos(a), angles[0], angles[-1], xtol=1e-14
    )
    mech = hinged_bar(bar)
    law = mechlib.TableLaw(Table("harness", angles, torques, "akima"), "harness")
    mech.add_force(mechlib.TorsionSpring("harness", "hinge", law=law))
    sol = mechlib.solve(mech, mechlib.Static(), requests=[mechlib.JointCoordinate("a", "hinge")])
    assert sol.ok, sol.message
    assert sol.channels["a.value"][0] == pytest.approx(expected, abs=1e-8)


@pytest.mark.parametrize("interpolation", ["linear", "cubic", "akima"])
@pytest.mark.parametrize("extrapolate", ["hold", "linear"])
def test_table_integral_is_exact(interpolation: str, extrapolate: str) -> None:
    """Table.integral (the potential of a table law) against scipy's adaptive quadrature of
    the table itself (quad, breakpoints at the data, tolerance 1e-13), inside, across and
    beyond the data and reversed: within 1e-13 J (measured 2e-15); outside the data of an
    `error` table it raises as the table does."""
    from scipy.integrate import quad

    x, y = [0.0, 0.1, 0.25, 0.5, 1.0], [0.0, 3.0, 4.0, 9.0, 10.0]
    table = Table("t", x, y, interpolation, extrapolate)
    for a, b in [(0.0, 0.3), (0.05, 0.9), (-0.2, 1.4), (1.2, 0.02)]:
        ref = quad(table, a, b, points=x, limit=200, epsabs=1e-13, epsrel=1e-13)[0]
        assert abs(table.integral(a, b) - ref) < 1e-13
    with pytest.raises(TableRangeError):
        Table("t", x, y, interpolation, "error").integral(0.0, 1.1)


@pytest.mark.parametrize(
    ("stiffness", "damping", "preload", "slack", "stretch"),
    [
        (2.0e5, 30.0, 5.0, False, -0.004),  # compressed: pushes
        (2.0e5, 30.0, 5.0, False, 0.004),
        (2.0e5, 30.0, 0.0, True, 0.003),  # a taut wire
        (2.0e5, 30.0, 0.0, True, -0.002),  # a slack wire: nothing
        (2.0e5, 4.0e5, 0.0, True, 1.0e-4),  # taut but closing fast: its damping would push
    ],
)
def test_compiled_linear_spring_against_its_definition(
    stiffness: float, damping: float, preload: float, slack: bool, stretch: float
) -> None:
    """The compiled linear spring-damper (kernels.spring_state and spring_wrench) between
    two turned, moving bodies: tension = k (L - L0) + c dL/dt + preload (none for a slack
    or pushing wire), L and dL/dt from the points' positions and velocities taken apart
    (dL/dt by a central difference of L over +-1e-6 s of the rigid motion), the forces
    -T u and +T u at the two points with their moments about the cms (1e-9 relative)."""
    m = mechlib.Mechanism(name="two")
    m.add_body("a", mass=1.0, cm=(0.0, 0.0, 0.0), inertia=[1, 1, 1])
    m.add_body("b", mass=1.0, cm=(0.3, 0.1, 0.0), inertia=[1, 1, 1])
    at_a, at_b = np.array([0.05, 0.02, 0.01]), np.array([0.32, 0.12, -0.02])
    free = float(np.linalg.norm(at_a - at_b)) - stretch  # so that L - L0 = stretch at design
    spring = mechlib.Spring(
        "s", (("a", at_a), ("b", at_b)), stiffness, damping, free, preload, slack
    )
    m.add_force(spring)
    system = mechlib.System(m)
    rng = np.random.default_rng(5)
    q, qd = system.design_q().copy(), np.zeros(system.nq)
    for b in range(2):
        qd[7 * b : 7 * b + 3] = rng.normal(scale=0.01, size=3)
        qd[7 * b + 4 : 7 * b + 7] = rng.normal(scale=0.02, size=3)  # about p = (1, 0, 0, 0)
    closing = (at_a - at_b) / np.linalg.norm(at_a - at_b) * 0.05  # m/s each: dL/dt < 0
    qd[0:3] -= closing
    qd[7:10] += closing

    def points(t: float) -> tuple[np.ndarray, np.ndarray]:
        view = system.view(system.kin(q + t * qd, qd, 0.0))  # Euler parameters to first order
        return tuple(view.point_position(b, s) for b, s in ((0, at_a), (1, at_b - (0.3, 0.1, 0))))

    p1, p2 = points(0.0)
    length = float(np.linalg.norm(p1 - p2))
    rate = (
        np.linalg.norm(np.subtract(*points(1e-6))) - np.linalg.norm(np.subtract(*points(-1e-6)))
    ) / 2e-6
    tension = stiffness * (length - free) + damping * rate + preload
    if slack and (length < free or tension < 0.0):
        tension = 0.0
    view = system.view(system.kin(q, qd, 0.0))
    assert spring.output(view)["value"] == pytest.approx(tension, rel=1e-6, abs=1e-9)
    assert spring.output(view)["length"] == pytest.approx(length, rel=1e-12)
    F, N = np.zeros((3, 3)), np.zeros((3, 3))
    spring.apply(view, F, N)
    u = (p1 - p2) / length
    force = spring.output(view)["value"] * u
    np.testing.assert_allclose(F[:2], [-force, force], atol=1e-9 * max(abs(tension), 1.0))
    moments = [np.cross(p1 - view.kin.r[0], -force), np.cross(p2 - view.kin.r[1], force)]
    np.testing.assert_allclose(N[:2], moments, atol=1e-9 * max(abs(tension), 1.0))
    assert rate < 0.0
    assert (tension == 0.0) == (slack and (stretch < 0.0 or damping > stiffness))


def _tilted_hinge(spring) -> tuple[mechlib.System, object]:
    """(system, the joint's angle measure) of two bodies on a revolute `h` with a tilted
    axis, held by `spring`."""
    m = mechlib.Mechanism(name="hinge")
    m.add_body("a", mass=1.0, cm=(0.0, 0.0, 0.0), inertia=[1, 1, 1])
    m.add_body("b", mass=1.0, cm=(0.2, 0.0, 0.0), inertia=[1, 1, 1])
    m.add_joint("h", "revolute", bodies=("a", "b"), at=(0.1, 0.0, 0.0), axis=(0.0, 0.6, 0.8))
    m.add_force(spring)
    system = mechlib.System(m)
    return system, system.measure("h", "angle")


def _turned_states(system, measure, seed: int):
    """(angle reference, q, qd, view) of both bodies turned at random and moving, the
    angle unwrapped near 0, 6 and -19 rad (three turns)."""
    rng = np.random.default_rng(seed)
    for reference in (0.0, 6.0, -19.0):
        q, qd = system.design_q().copy(), rng.normal(scale=0.5, size=system.nq)
        for b in range(2):
            p = rng.normal(size=4)
            q[7 * b + 3 : 7 * b + 7] = p / np.linalg.norm(p)
        measure.reference = reference
        yield reference, q, qd, system.view(system.kin(q, qd, 0.0))


def _assert_resists(spring, view, measure, moment: float) -> None:
    """`spring` applies -moment a on the angle's body 1 and +moment a on its body 2, a the
    joint axis (fixed in body 2), and no force (1e-12 relative)."""
    F, N = np.zeros((3, 3)), np.zeros((3, 3))
    spring.apply(view, F, N)
    axis = view.rotation(measure.bj) @ measure.axis_local
    np.testing.assert_allclose(N[measure.bi], -moment * axis, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(N[measure.bj], moment * axis, rtol=1e-12, atol=1e-12)
    assert not F.any()


def test_compiled_torsion_spring_against_the_joint_angle() -> None:
    """The compiled linear torsion spring (kernels.angle_state, torsion_wrench) on a
    revolute between two bodies turned and moving: its angle and rate equal the joint's
    angle measure (mechlib.kinematics.coordinates.AngleMeasure, constraint kernels) over three turns
    of unwrapping, its rate the central difference of that angle over +-1e-6 s (1e-6
    relative), its moments -M a on body 1 and +M a on body 2 about the joint axis a of
    body 2, M = k (angle - angle0) + c rate + preload (1e-12 relative)."""
    spring = mechlib.TorsionSpring("t", "h", stiffness=35.0, damping=2.5, angle0=0.3, preload=4)
    system, measure = _tilted_hinge(spring)
    for reference, q, qd, view in _turned_states(system, measure, seed=9):
        angle = measure.value(view.kin)
        assert abs(angle - reference) <= math.pi
        out = spring.output(view)
        assert out["angle"] == pytest.approx(angle, rel=1e-12, abs=1e-12)
        rate = measure.rate(view.kin)
        ahead, behind = (measure.value(system.kin(q + t * qd, qd, 0.0)) for t in (1e-6, -1e-6))
        assert rate == pytest.approx((ahead - behind) / 2e-6, rel=1e-6)
        moment = 35.0 * (angle - 0.3) + 2.5 * rate + 4.0
        assert out["value"] == pytest.approx(moment, rel=1e-12)
        _assert_resists(spring, view, measure, moment)


def test_named_points_found_once_and_read_only() -> None:
    """A named point's (body, body-fixed vector) is found once per system and cannot be
    changed through what it returns: the position it gives is the body point's, r + A s."""
    m = mechlib.Mechanism(name="p")
    m.add_body("a", mass=1.0, cm=(0.1, 0.2, 0.3), inertia=[1, 1, 1])
    m.add_point("tip", body="a", at=(0.5, 0.2, 0.3))
    system = mechlib.System(m)
    body, s = system.point("tip")
    assert system.point("tip")[1] is s and body == 0
    np.testing.assert_array_equal(s, [0.4, 0.0, 0.0])
    with pytest.raises(ValueError):
        s[0] = 1.0
    q = system.design_q().copy()
    q[3:7] = [math.cos(0.25), 0.0, 0.0, math.sin(0.25)]  # 0.5 rad about z
    q[:3] += (0.01, 0.02, 0.03)
    view = system.view(system.kin(q, None, 0.0))
    expected = q[:3] + 0.4 * np.array([math.cos(0.5), math.sin(0.5), 0.0])
    np.testing.assert_allclose(view.position("tip"), expected, rtol=0, atol=1e-15)


def test_compiled_table_torsion_spring_against_its_definition() -> None:
    """The compiled tabulated torsion spring (kernels.torsion_table_wrench) on a tilted
    revolute between two turned, moving bodies: moments -M a on body 1 and +M a on body 2
    about the joint axis a of body 2, M = table(angle - angle0) + c rate + preload with the
    angle and rate of the joint's measure and the table's own value (1e-12 relative),
    beyond the data too (extrapolate: linear); a table that does not extrapolate refuses
    a turn beyond its data with a solver failure naming the element."""
    angles, torques = np.array([-1.0, 0.0, 0.5, 1.5]), np.array([-8.0, 0.0, 3.0, 20.0])
    law = mechlib.TableLaw(Table("law", angles, torques, "akima", "linear"), "t")
    spring = mechlib.TorsionSpring("t", "h", damping=2.5, angle0=0.3, preload=4.0, law=law)
    system, measure = _tilted_hinge(spring)
    for _, _, _, view in _turned_states(system, measure, seed=11):
        angle, rate = measure.value(view.kin), measure.rate(view.kin)
        moment = law.table(angle - 0.3) + 2.5 * rate + 4.0
        _assert_resists(spring, view, measure, moment)
    strict = mechlib.TableLaw(Table("law", angles, torques, "akima", "error"), "t")
    system, _ = _tilted_hinge(mechlib.TorsionSpring("t", "h", law=strict))
    q = system.design_q()
    q[3:7] = [math.cos(1.0), 0.0, 0.6 * math.sin(1.0), 0.8 * math.sin(1.0)]  # a turned 2 rad
    with pytest.raises(mechlib.SolverFailure, match="force element 't'"):
        system.forces(system.kin(q, np.zeros(system.nq), 0.0))


def test_table_torsion_spring_swings_as_its_linear_twin() -> None:
    """A bar on a hinge without gravity held by a torsion spring whose table is the line
    k theta (extrapolate: linear), released at 0.4 rad: theta(t) = 0.4 cos(w t), w =
    sqrt(k / I_end), over two periods; to 1e-4 rad (generalized-alpha at tolerance 1e-8:
    the closed form, not another run of the code)."""
    from .._models import Bar, hinged_bar

    bar, k, theta0 = Bar(), 50.0, 0.4
    table = Table("line", [-0.2, 0.0, 0.2], [-0.2 * k, 0.0, 0.2 * k], "linear", "linear")
    mech = hinged_bar(bar, gravity=0.0)
    mech.add_force(mechlib.TorsionSpring("spring", "hinge", law=mechlib.TableLaw(table, "s")))
    w = math.sqrt(k / bar.i_end)
    end = 2 * 2 * math.pi / w
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=end, step=end / 200, tolerance=1e-8),
        requests=[mechlib.JointCoordinate("a", "hinge")],
        initial=[mechlib.InitialValue("hinge", value=theta0)],
    )
    assert sol.ok, sol.message
    assert np.abs(sol.channels["a.value"] - theta0 * np.cos(w * sol.time)).max() < 1e-4


@pytest.mark.parametrize("analysis", ["kinematic", "quasi-static"])
def test_table_torsion_spring_loads_the_motion_that_drives_it(analysis: str) -> None:
    """A 2 kg, 1 m bar driven at 0.5 rad/s from -60 to 55 deg against gravity and a
    harness-like Akima torque table (beyond its data from 30 deg on: extrapolate linear):
    the motion carries table(theta) + m g L/2 cos(theta) (constant rate: no angular
    acceleration), with scipy's Akima interpolant and its end slope as the table; to 1e-9
    N*m."""
    from .._models import Bar, Ramp, hinged_bar

    bar = Bar()
    angles = np.radians([-90.0, -60.0, -30.0, 0.0, 30.0])
    torques = np.array([-30.0, -20.0, -12.0, -4.0, 6.0])
    ref = Akima1DInterpolator(angles, torques)
    mech = hinged_bar(bar)
    law = mechlib.TableLaw(Table("harness", angles, torques, "akima", "linear"), "harness")
    mech.add_force(mechlib.TorsionSpring("harness", "hinge", law=law))
    mech.add_motion("drive", joint="hinge", function=Ramp(math.radians(-60.0), 0.5))
    spec = (mechlib.Kinematic if analysis == "kinematic" else mechlib.QuasiStatic)(
        end=4.0, step=0.25
    )
    sol = mechlib.solve(mech, spec, requests=[mechlib.MotionEffort("drive", "drive")])
    assert sol.ok, sol.message
    theta = math.radians(-60.0) + 0.5 * sol.time
    end, slope = angles[-1], float(ref.derivative()(angles[-1]))
    table = np.where(theta <= end, ref(np.minimum(theta, end)), ref(end) + slope * (theta - end))
    assert theta[-1] > end  # beyond the data at the end
    expected = table + bar.weight_moment * np.cos(theta)
    np.testing.assert_allclose(sol.channels["drive.value"], expected, rtol=0, atol=1e-9)
