"""Modes about a static equilibrium. References: spring-mass f = sqrt(k/m)/(2 pi); compound
pendulum hanging f = sqrt(m g d / I_O)/(2 pi); double spring-mass chain: the eigenvalues of
[[2k, -k], [-k, k]] / m (closed form w^2 = k/m (3 -+ sqrt 5)/2). Tolerance 1e-6 relative
(the tangent stiffness is a forward difference)."""

from __future__ import annotations

import math

import pytest

import mechlib as ml


def _slider(m: ml.Mechanism, name: str, y: float) -> None:
    m.add_body(name, mass=2.0, cm=(0, y, 0), inertia=[1, 1, 1])
    m.add_point(name + "_c", body=name, at=(0, y, 0))
    m.add_joint(name + "_g", "prismatic", bodies=(name, "ground"), at=(0, y, 0), axis=(0, 1, 0))


def test_spring_mass_frequency_and_shape() -> None:
    m = ml.Mechanism(gravity=(0, -9.81, 0))
    _slider(m, "s", 0.0)
    m.add_force(ml.Spring("k", (("s", (0, 0, 0)), ("ground", (0, 1, 0))), stiffness=800.0))
    sol = ml.solve(m, ml.Modes(), requests=[ml.PointKinematics("c", "s_c")])
    assert sol.channels["mode.frequency"][0] == pytest.approx(
        math.sqrt(800 / 2) / (2 * math.pi), rel=1e-6
    )
    assert abs(sol.channels["c.y"][0]) == pytest.approx(
        1 / math.sqrt(2.0), rel=1e-6
    )  # mass-normalised


def test_hanging_pendulum_frequency() -> None:
    m = ml.Mechanism(gravity=(0, -9.81, 0))
    m.add_body("bar", mass=3.0, cm=(0, -0.5, 0), inertia=[0.25, 0.01, 0.25])
    m.add_joint("h", "revolute", bodies=("bar", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    sol = ml.solve(m, ml.Modes(), requests=[ml.JointCoordinate("a", "h", "angle")])
    inertia_o = 0.25 + 3.0 * 0.5**2
    assert sol.channels["mode.frequency"][0] == pytest.approx(
        math.sqrt(3.0 * 9.81 * 0.5 / inertia_o) / (2 * math.pi), rel=1e-6
    )


def test_two_mass_chain_frequencies() -> None:
    """Two 2 kg sliders, ground-k-s1-k-s2 along y, no gravity: two modes, lowest first."""
    k = 500.0
    m = ml.Mechanism()
    _slider(m, "s1", 0.0)
    _slider(m, "s2", 1.0)
    m.add_force(ml.Spring("k1", (("ground", (0, -1, 0)), ("s1", (0, 0, 0))), stiffness=k))
    m.add_force(ml.Spring("k2", (("s1", (0, 0, 0)), ("s2", (0, 1, 0))), stiffness=k))
    sol = ml.solve(m, ml.Modes())
    expected = sorted(
        math.sqrt(k / 2.0 * (3 + s * math.sqrt(5)) / 2) / (2 * math.pi) for s in (-1, 1)
    )
    assert list(sol.channels["mode.frequency"]) == pytest.approx(expected, rel=1e-6)
