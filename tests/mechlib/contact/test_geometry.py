"""Contact geometries at known positions: penetration, normal, point, eccentricity (SI)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.contact import (
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
    """The compiled nearest point (mechlib.contact.curve_kernels) on a scipy CubicSpline
    through 6 points: the foot of the perpendicular, i.e. (c(u) - w) . c'(u) = 0 to 1e-12 m,
    and no sample of a 20001-point scan of the curve nearer than it (within 1e-12 m);
    point and tangent equal to scipy's evaluation at u within 1e-13."""
    from scipy.interpolate import CubicSpline

    from mechlib.contact.curve_kernels import nearest_on_cubic

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
