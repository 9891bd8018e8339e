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
