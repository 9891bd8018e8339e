"""Contact geometries at known positions: penetration, normal, point, eccentricity (SI)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.contact import (
    CircleProfile,
    CylinderInCylinder,
    HertzLaw,
    SphereInSphere,
    SpherePlane,
    revolute_clearance,
)


def _system_at(offset, velocity=(0.0, 0.0, 0.0)):
    """One body 'b' (cm at the origin) moved by `offset` (m) with `velocity` (m/s)."""
    m = ml.Mechanism(name="g")
    m.add_body("b", mass=1.0, cm=(0, 0, 0), inertia=[1, 1, 1])
    system = ml.System(m)
    q = system.design_q().copy()
    q[:3] += offset
    qd = np.zeros_like(q)
    qd[:3] = velocity
    return system, system.view(system.kin(q, qd, 0.0))


def test_sphere_plane() -> None:
    """Sphere R = 10 mm, centre 9 mm above the plane: penetration 1 mm, normal +y, the
    contact point midway in the overlap, approach rate = the falling speed."""
    system, view = _system_at((0.0, -0.001, 0.0), (0.0, -0.5, 0.0))
    g = SpherePlane((0, 0.01, 0), 0.01, (0, 0, 0), (0, 2, 0))
    g.bind(system, "b", ml.GROUND)
    gap = g.gap(view)
    assert gap.penetration == pytest.approx(0.001)
    np.testing.assert_allclose(gap.normal, [0, 1, 0])
    np.testing.assert_allclose(gap.point, [0, -0.0005, 0], atol=1e-15)
    assert gap.rate == pytest.approx(0.5)


def test_ball_in_socket_and_pin_in_hole() -> None:
    """Eccentricity 0.6 mm with 0.5 mm clearance: penetration 0.1 mm, normal back to the
    centre; the pin ignores the axial part of the eccentricity."""
    system, view = _system_at((0.0006, 0.0, 0.002))
    ball = SphereInSphere((0, 0, 0), 0.01, 0.0005)
    ball.bind(system, "b", ml.GROUND)
    gap = ball.gap(view)
    assert gap.penetration == pytest.approx(math.hypot(0.0006, 0.002) - 0.0005)
    pin = CylinderInCylinder((0, 0, 0), (0, 0, 1), 0.01, 0.0005)
    pin.bind(system, "b", ml.GROUND)
    gap = pin.gap(view)
    assert gap.penetration == pytest.approx(0.0001)
    np.testing.assert_allclose(gap.normal, [-1, 0, 0])


def test_clearance_joint_polar_angle() -> None:
    """Eccentricity along +y about the z axis of the hole: polar angle 90 deg."""
    system, view = _system_at((0.0, 0.0003, 0.0))
    joint = revolute_clearance(
        "j",
        ("b", ml.GROUND),
        center=(0, 0, 0),
        axis=(0, 0, 1),
        radius=0.01,
        clearance=0.0005,
        law=HertzLaw(1e9),
    )
    joint.bind(system)
    out = joint.output(view)
    assert out["angle"] == pytest.approx(math.pi / 2)
    assert out["eccentricity"] == pytest.approx(0.0003)
    assert out["normal"] == 0.0


def test_roller_on_a_circular_profile() -> None:
    """Profile: 41 points on a circle of radius 0.1 m about the origin (the roller outside);
    roller R = 10 mm with its centre 0.105 m from the origin: penetration 5 mm (within the
    spline's interpolation error, 1e-6 m), normal radial."""
    angles = np.linspace(0.0, np.pi, 41)
    points = np.column_stack((0.1 * np.cos(angles), 0.1 * np.sin(angles), 0 * angles))
    system, view = _system_at((0.0, 0.0, 0.0))
    c = 0.105 * np.array([math.cos(1.0), math.sin(1.0), 0.0])
    g = CircleProfile(c, 0.01, points, (0, 0, 1))
    g.bind(system, "b", ml.GROUND)
    gap = g.gap(view)
    assert gap.penetration == pytest.approx(0.005, abs=1e-6)
    np.testing.assert_allclose(gap.normal, c / np.linalg.norm(c), atol=1e-4)


def test_nearest_point_on_a_cubic_profile_against_scipy() -> None:
    """The compiled nearest point (mechlib.elements.contact.curve_kernels) on a scipy CubicSpline
    through 6 points: the foot of the perpendicular, i.e. (c(u) - w) . c'(u) = 0 to 1e-12 m,
    and no sample of a 20001-point scan of the curve nearer than it (within 1e-12 m);
    point and tangent equal to scipy's evaluation at u within 1e-13."""
    from scipy.interpolate import CubicSpline

    from mechlib.elements.contact.curve_kernels import nearest_on_cubic

    pts = np.array([[0, 0], [0.1, 0.02], [0.2, 0.05], [0.3, 0.04], [0.4, 0.0], [0.5, -0.03]])
    chord = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
    spline = CubicSpline(chord, pts, bc_type="natural")
    grid = np.linspace(0.0, chord[-1], 201)
    scan = np.linspace(0.0, chord[-1], 20001)
    curve = spline(scan)
    out = np.empty((3, 2))
    for w in ([0.15, 0.1], [0.33, -0.05], [0.05, 0.03]):
        w = np.array(w)
        u = nearest_on_cubic(w, grid, spline(grid), spline.x, spline.c, 6, out)
        assert abs((spline(u) - w) @ spline(u, 1)) <= 1e-12
        assert np.linalg.norm(out[0] - w) <= np.linalg.norm(curve - w, axis=1).min() + 1e-12
        assert np.abs(out[0] - spline(u)).max() <= 1e-13
        assert np.abs(out[1] - spline(u, 1)).max() <= 1e-13


def _two_moving_bodies():
    """Bodies 'r' (roller) and 'p' (profile), each translated, turned about a skew axis and
    moving (linear and angular rates); returns the system and its view."""
    m = ml.Mechanism(name="two")
    m.add_body("r", mass=1.0, cm=(0.02, 0.1, 0.0), inertia=[1, 1, 1])
    m.add_body("p", mass=1.0, cm=(0.0, 0.05, 0.01), inertia=[1, 1, 1])
    system = ml.System(m)
    q = system.design_q().copy()
    rng = np.random.default_rng(11)
    qd = np.zeros_like(q)
    for b, angle in ((0, 0.05), (1, 0.3)):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        q[7 * b : 7 * b + 3] += rng.normal(scale=0.002, size=3)
        q[7 * b + 3 : 7 * b + 7] = [math.cos(angle / 2), *(math.sin(angle / 2) * axis)]
        qd[7 * b : 7 * b + 3] = rng.normal(scale=0.3, size=3)
        omega = rng.normal(scale=2.0, size=3)  # rad/s: pd = 1/2 G^T omega' (body axes)
        p = q[7 * b + 3 : 7 * b + 7]
        g = np.array(
            [[-p[1], p[0], p[3], -p[2]], [-p[2], -p[3], p[0], p[1]], [-p[3], p[2], -p[1], p[0]]]
        )
        qd[7 * b + 3 : 7 * b + 7] = 0.5 * g.T @ omega
    return system, system.view(system.kin(q, qd, 0.0))


def test_compiled_profile_gap_against_a_scanned_spline() -> None:
    """The compiled profile gap (kernels.CIRCLE_PROFILE) with both bodies turned and
    moving, against an independent evaluation: the roller centre taken into the profile
    body's axes, the nearest point of scipy's spline found by a 400,001-sample scan refined
    by scipy's bounded scalar minimiser, the normal from scipy's derivative there, the
    relative velocity from the view's point velocities (mechlib.elements.contact.geometry).
    Penetration and point within 1e-12 m, normal within 1e-9."""
    from scipy.interpolate import CubicSpline
    from scipy.optimize import minimize_scalar

    from mechlib.elements.contact.geometry import relative_velocity

    system, view = _two_moving_bodies()
    angles = np.linspace(0.2, 2.6, 9)
    points = np.column_stack((0.08 * np.cos(angles), 0.05 + 0.08 * np.sin(angles), 0 * angles))
    center = np.array([0.0, 0.05 + 0.0905, 0.0])  # 0.5 mm inside a 10 mm roller's reach
    g = CircleProfile(center, 0.01, points, (0, 0, 1))
    b1, b2 = g.bind(system, "r", "p")
    gap = g.gap(view)

    rot1, rot2 = view.rotation(b1), view.rotation(b2)
    c = view.kin.r[b1] + rot1 @ (center - system.cm[b1])
    origin = view.kin.r[b2] + rot2 @ (points[0] - system.cm[b2])
    local = rot2.T @ (c - origin)
    e1 = (points[-1] - points[0]) / np.linalg.norm(points[-1] - points[0])
    e2 = np.cross([0, 0, 1.0], e1)
    uv = (points - points[0]) @ np.column_stack((e1, e2))
    chord = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(uv, axis=0), axis=1))]
    spline = CubicSpline(chord, uv, bc_type="natural")
    w = np.array([local @ e1, local @ e2])
    scan = np.linspace(0.0, chord[-1], 400_001)
    start = scan[np.argmin(np.linalg.norm(spline(scan) - w, axis=1))]
    step = scan[1]
    best = minimize_scalar(
        lambda u: float(np.sum((spline(u) - w) ** 2)),
        bounds=(max(start - step, 0.0), min(start + step, chord[-1])),
        method="bounded",
        options={"xatol": 1e-14},
    )
    foot = spline(best.x) @ np.vstack((e1, e2))
    tangent = spline(best.x, 1) @ np.vstack((e1, e2))
    normal = np.cross([0, 0, 1.0], tangent)
    normal /= np.linalg.norm(normal)
    if (foot - (np.array([0.0, 0.05, 0.0]) - points[0])) @ normal < 0:
        normal = -normal  # away from the arc's centre: the roller's side at design
    d = float((local - foot) @ normal)
    assert gap.penetration == pytest.approx(0.01 - d, abs=1e-12)
    assert 0.0 < gap.penetration < 0.01  # in contact
    np.testing.assert_allclose(gap.normal, rot2 @ normal, atol=1e-9)
    point = origin + rot2 @ foot + 0.5 * (d - 0.01) * (rot2 @ normal)
    np.testing.assert_allclose(gap.point, point, atol=1e-12)
    np.testing.assert_allclose(
        gap.velocity, relative_velocity(view, b1, b2, gap.point), rtol=0, atol=1e-12
    )


def test_profile_contact_wrench_compiled_equals_its_forces() -> None:
    """A moving profile contact's compiled wrench (Contact.apply) is its force (from
    Contact.forces) on body 1 at the contact point and the opposite on body 2, with their
    moments about each centre of mass (1e-9 relative)."""
    from mechlib.elements.contact import Contact, CoulombFriction, ImpactLaw

    system, view = _two_moving_bodies()
    angles = np.linspace(0.2, 2.6, 9)
    points = np.column_stack((0.08 * np.cos(angles), 0.05 + 0.08 * np.sin(angles), 0 * angles))
    geometry = CircleProfile((0.0, 0.1405, 0.0), 0.01, points, (0, 0, 1))
    law = ImpactLaw(1e7, 1.5, 1e3, 1e-4)
    contact = Contact("guide", ("r", "p"), geometry, law, CoulombFriction(0.2))
    contact.bind(system)
    F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
    contact.apply(view, F, N)
    f = contact.forces(view)
    assert f.normal > 0.0 and f.friction > 0.0
    b1, b2 = geometry.compiled()[:2]
    scale = np.abs(f.force).max()
    np.testing.assert_allclose(F[b1], f.force, atol=1e-9 * scale)
    np.testing.assert_allclose(F[b2], -f.force, atol=1e-9 * scale)
    for b, sign in ((b1, 1.0), (b2, -1.0)):
        moment = np.cross(f.gap.point - view.kin.r[b], sign * f.force)
        np.testing.assert_allclose(N[b], moment, atol=1e-9 * scale)


@pytest.mark.parametrize("geometry", ["sphere_plane", "profile"])
@pytest.mark.parametrize("slip", [0.0, 3e-7, 5e-6])
def test_static_friction_wrench_compiled_equals_its_forces(geometry: str, slip: float) -> None:
    """A contact with friction in a static evaluation (no velocities): its compiled wrench
    (kernels.static_contact_wrench) is its force from Contact.forces -- the normal force
    and mu F_N against the tangential slip of the contact point since the accepted state
    (committed here), regularised below slip_threshold 1e-6 m -- on body 1 at the contact
    point, the opposite on body 2, with their moments (1e-12 relative); none before the
    first accepted state."""
    from mechlib.elements.contact import Contact, CoulombFriction, ImpactLaw, SpherePlane

    m = ml.Mechanism(name="rest", gravity=(0.0, 0.0, 0.0))
    m.add_body("r", mass=1.0, cm=(0.02, 0.1, 0.0), inertia=[1, 1, 1])
    m.add_body("p", mass=1.0, cm=(0.0, 0.05, 0.01), inertia=[1, 1, 1])
    if geometry == "profile":
        angles = np.linspace(0.2, 2.6, 9)
        points = np.column_stack((0.08 * np.cos(angles), 0.05 + 0.08 * np.sin(angles), 0 * angles))
        shape = CircleProfile((0.0, 0.1395, 0.0), 0.01, points, (0, 0, 1))
    else:
        shape = SpherePlane((0.0, 0.1395, 0.0), 0.01, (0.0, 0.13, 0.0), (0.0, 1.0, 0.0))
    contact = Contact("c", ("r", "p"), shape, ImpactLaw(1e7, 1.5, 1e3, 1e-4), CoulombFriction(0.3))
    m.add_force(contact)
    system = ml.System(m)
    q = system.design_q().copy()
    q[3:7] = [math.cos(0.01), 0.0, 0.0, math.sin(0.01)]  # body r turned 20 mrad about z
    b1, b2 = system.body_index("r"), system.body_index("p")
    for anchored in (False, True):
        if anchored:
            contact.commit(system.view(system.kin(q, None, 0.0)))
            q = q.copy()
            q[0] += slip  # body r slides along x (tangential) since the accepted state
            q[1] -= 2e-5  # and presses in
        view = system.view(system.kin(q, None, 0.0))
        F, N = np.zeros((3, 3)), np.zeros((3, 3))
        contact.apply(view, F, N)
        f = contact.forces(view)
        assert f.normal > 0.0
        assert anchored or f.friction == 0.0  # no accepted state yet: no slip
        scale = np.abs(f.force).max()
        np.testing.assert_allclose(F[b1], f.force, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(F[b2], -f.force, rtol=0, atol=1e-12 * scale)
        for b, sign in ((b1, 1.0), (b2, -1.0)):
            moment = np.cross(f.gap.point - view.kin.r[b], sign * f.force)
            np.testing.assert_allclose(N[b], moment, rtol=0, atol=1e-12 * scale)
    if slip > 1e-6:  # beyond the threshold: the full mu F_N
        assert f.friction == pytest.approx(0.3 * f.normal, rel=1e-12)
