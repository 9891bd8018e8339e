"""The 3-D Timoshenko beam element against closed forms.

Sources: Euler-Bernoulli cantilever and free-free roots beta_n L (Blevins, Formulas for
Natural Frequency and Mode Shape, 1979, Table 8-1); the simply supported Timoshenko beam's
frequency equation (Timoshenko, Young & Weaver, Vibration Problems in Engineering, 5.13):
rho^2 I/(k G) w^4 - (rho A + (n pi/L)^2 rho I (1 + E/(k G))) w^2 + E I (n pi/L)^4 = 0;
cantilever tip deflection P L^3/(3 E I) + P L/(k G A) (exact for the IIE element).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from mechlib.flexible.beam import (
    Material,
    Section,
    assemble_beams,
    beam_matrices,
    section_axes,
)

STEEL = Material(E=210e9, nu=0.3, rho=7850.0)


def _line(L: float, n: int, section: Section, direction=(1.0, 0.0, 0.0)):
    xyz = np.outer(np.linspace(0.0, L, n + 1), np.asarray(direction) / np.linalg.norm(direction))
    hint = _hint(direction)
    return assemble_beams(xyz, [(i, i + 1, section, STEEL, hint) for i in range(n)])


def _hint(direction) -> np.ndarray:
    """A section y axis for a beam along `direction` (y for a beam along x)."""
    d = np.asarray(direction) / np.linalg.norm(direction)
    return np.cross(np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.9 else np.array([1.0, 0, 0]), d)


def _plane_frequencies(model, keep) -> np.ndarray:
    """Frequencies (rad/s) on the DOF kept (indices), ascending."""
    k = model.stiffness.toarray()[np.ix_(keep, keep)]
    m = model.mass.toarray()[np.ix_(keep, keep)]
    return np.sqrt(np.abs(sla.eigh(k, m, eigvals_only=True)))


def _vy_dofs(n_nodes: int, start: int = 0) -> np.ndarray:
    """uy and rz of every node from `start` (bending in the x-y plane)."""
    return np.array([6 * i + c for i in range(start, n_nodes) for c in (1, 5)])


def test_cantilever_euler_bernoulli_frequencies():
    """Slender steel cantilever (2 m, 10 x 10 mm, 40 elements): the first three bending
    frequencies within 0.1 % of Euler-Bernoulli (measured: 2e-5, 1.4e-4, 3.3e-4, below:
    shear and rotary inertia, (r/L)^2 small but not nil)."""
    L, s = 2.0, Section.rectangle(0.01, 0.01)
    model = _line(L, 40, s)
    w = _plane_frequencies(model, _vy_dofs(41, start=1))[:3]
    beta = np.array([1.875104068711961, 4.694091132974175, 7.854757438237613])
    exact = beta**2 / L**2 * np.sqrt(STEEL.E * s.Iz / (STEEL.rho * s.A))
    assert np.abs(w / exact - 1.0).max() < 1e-3
    assert np.all((w < exact) & (w > exact * (1.0 - 4e-4)))


def test_free_free_euler_bernoulli_frequencies():
    """Free-free slender beam: two rigid modes, then beta L = 4.730, 7.853 (0.1 %;
    measured 9e-5 and 2.6e-4 below: shear and rotary inertia)."""
    L, s = 2.0, Section.rectangle(0.01, 0.01)
    model = _line(L, 40, s)
    w = _plane_frequencies(model, _vy_dofs(41))
    assert w[:2].max() < 1e-3 * w[2]
    beta = np.array([4.730040744862704, 7.853204624095838])
    exact = beta**2 / L**2 * np.sqrt(STEEL.E * s.Iz / (STEEL.rho * s.A))
    assert np.abs(w[2:4] / exact - 1.0).max() < 1e-3  # measured 9e-5, 2.6e-4
    assert np.all((w[2:4] < exact) & (w[2:4] > exact * (1.0 - 3e-4)))


def test_simply_supported_timoshenko_frequencies():
    """A thick beam (L/h = 5) simply supported: the first three bending frequencies of
    the Timoshenko closed form within 0.1 % (shear and rotary inertia change them by
    5-30 % from Euler-Bernoulli, so both effects are exercised)."""
    L, h = 0.5, 0.1
    s = Section.rectangle(h, h)
    model = _line(L, 60, s)
    keep = [d for d in _vy_dofs(61) if d not in (1, 6 * 60 + 1)]
    w = _plane_frequencies(model, keep)[:3]
    G, kGA = STEEL.G, s.ky * STEEL.G * s.A
    exact = []
    for n in (1, 2, 3):
        kn = n * np.pi / L
        a = STEEL.rho**2 * s.Iz / (s.ky * G)
        b = STEEL.rho * s.A + kn**2 * STEEL.rho * s.Iz * (1.0 + STEEL.E / (s.ky * G))
        c = STEEL.E * s.Iz * kn**4
        exact.append(np.sqrt((b - np.sqrt(b * b - 4 * a * c)) / (2 * a)))
    euler = (np.arange(1, 4) * np.pi / L) ** 2 * np.sqrt(STEEL.E * s.Iz / (STEEL.rho * s.A))
    assert (1.0 - np.array(exact) / euler).min() > 0.04
    assert kGA > 0.0
    assert np.abs(w / np.array(exact) - 1.0).max() < 1e-3


@pytest.mark.parametrize("direction", [(1.0, 0.0, 0.0), (0.3, -0.5, 0.8)])
def test_cantilever_tip_deflection_with_shear(direction):
    """Short cantilever, tip force normal to it: P L^3/(3 E I) + P L/(k G A) to 1e-10
    with 3 elements, whatever the beam's direction in space."""
    L, s = 0.3, Section.rectangle(0.04, 0.06)
    model = _line(L, 3, s, direction)
    ez = section_axes(model.coordinates[0], model.coordinates[1], _hint(direction))[2]
    P = 1000.0
    free = np.arange(6, 24)
    f = np.zeros(24)
    f[18:21] = P * ez
    u = np.linalg.solve(model.stiffness.toarray()[np.ix_(free, free)], f[free])
    tip = u[12:15] @ ez
    # ez is the section's local z: bending about local y uses Iy
    exact = P * L**3 / (3 * STEEL.E * s.Iy) + P * L / (s.kz * STEEL.G * s.A)
    assert tip == pytest.approx(exact, rel=1e-10)


def test_element_rigid_motions_carry_mass_and_no_stress():
    """A rigid rotation about the element's end is stress-free; a rigid translation
    has kinetic energy of the element mass rho A L."""
    L, s = 0.4, Section.rectangle(0.02, 0.05)
    k, m = beam_matrices(L, s, STEEL)
    theta = np.array([0, 0, 0, 0, 0, 1.0, 0, L, 0, 0, 0, 1.0])  # small rotation about z
    assert np.abs(k @ theta).max() < 1e-6 * np.abs(k).max()
    for axis in range(3):
        u = np.zeros(12)
        u[[axis, 6 + axis]] = 1.0
        assert u @ m @ u == pytest.approx(STEEL.rho * s.A * L, rel=1e-12)
