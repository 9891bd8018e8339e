"""Contact laws and friction coefficients against their defining equations (SI units)."""

from __future__ import annotations

import math

import pytest

import mechlib as ml
from mechlib.elements.contact import (
    CoulombFriction,
    HertzLaw,
    ImpactLaw,
    RestitutionLaw,
    StribeckFriction,
    hertz_stiffness,
    step,
)
from tests.mechlib.contact._contact_models import G, guided_ball


def test_step_function_of_seed_004_eq_3_10() -> None:
    """f0 below x0, f1 above x1, 3s^2 - 2s^3 between (exact)."""
    assert step(-1.0, 0.0, 2.0, 1.0, 5.0) == 2.0
    assert step(2.0, 0.0, 2.0, 1.0, 5.0) == 5.0
    assert step(0.5, 0.0, 2.0, 1.0, 5.0) == pytest.approx(3.5, abs=1e-15)
    assert step(0.25, 0.0, 0.0, 1.0, 1.0) == pytest.approx(3 / 16 - 2 / 64, abs=1e-15)


def test_impact_law_is_continuous_and_never_pulls() -> None:
    """No force apart; k x^e + full damping beyond `depth`; clamped at zero while
    separating fast (no adhesion)."""
    law = ImpactLaw(1e7, 1.5, damping=100.0, depth=1e-4)
    assert law.force(-1e-3, 1.0) == 0.0
    assert law.force(2e-4, 0.5) == pytest.approx(1e7 * 2e-4**1.5 + 50.0, rel=1e-12)
    assert law.force(1e-6, -100.0) == 0.0


def test_hertz_stiffness_of_seed_004_eqs_3_4_and_3_5() -> None:
    """K = 4/(3 pi (h1 + h2)) sqrt(R), h = (1 - nu^2)/(pi E): equal steels give
    (4/3) E/(2 (1 - nu^2)) sqrt(R) (exact)."""
    E, nu, R = 210e9, 0.3, 0.21
    expected = 4.0 / 3.0 * E / (2.0 * (1.0 - nu * nu)) * math.sqrt(R)
    assert hertz_stiffness(E, nu, E, nu, R) == pytest.approx(expected, rel=1e-12)


def test_ln_damping_factor() -> None:
    """F = K d^n (1 + 3 (1 - e^2)/4 * dd / dd(-)) (seed 004 eq. 3.6-3.8)."""
    law = HertzLaw(1e9, 1.5, 0.8)
    x, xd, v0 = 1e-5, 0.3, 0.6
    assert law.force(x, xd, v0) == pytest.approx(1e9 * x**1.5 * (1 + 0.75 * 0.36 * 0.5))
    assert HertzLaw(1e9).force(x, xd, v0) == pytest.approx(1e9 * x**1.5)
    assert RestitutionLaw(0.8, 1e9).force(x, 0.0, v0) == pytest.approx(1e9 * x**1.5)


def test_stribeck_coefficient_of_seed_004_eq_3_9() -> None:
    """0 at rest, mu_static at v_static, mu_dynamic from v_dynamic, continuous."""
    f = StribeckFriction(0.3, 0.2, 1e-3, 1e-2)
    assert f.coefficient(0.0) == pytest.approx(0.0, abs=1e-15)
    assert f.coefficient(1e-3) == pytest.approx(0.3)
    assert f.coefficient(1e-3 * (1 + 1e-9)) == pytest.approx(0.3, rel=1e-6)
    assert f.coefficient(0.5) == pytest.approx(0.2)
    assert CoulombFriction(0.25, 1e-3).coefficient(0.1) == pytest.approx(0.25)


@pytest.mark.parametrize(
    "law, exact",
    [
        (ImpactLaw(1.0e7, 1.5), lambda f: (f / 1.0e7) ** (1 / 1.5)),  # x = (F/k)^(1/e)
        (HertzLaw(5.0e9, 1.5, 0.8), lambda f: (f / 5.0e9) ** (1 / 1.5)),  # d = (F/K)^(1/n)
        (ImpactLaw(2.0e6, 1.0), lambda f: f / 2.0e6),
    ],
)
def test_static_penetration_under_a_known_load(law, exact) -> None:
    """A 1 kg ball on a vertical guide pressed onto a plane by 100 N + its weight: static
    analysis, penetration within 0.1 % of the law inverted, normal force = load."""
    load = 100.0 + 1.0 * G
    mech = guided_ball(law, load=100.0, overlap=1e-5)
    sol = ml.solve(mech, ml.Static(), requests=[ml.ElementOutput("c", "contact")])
    assert sol.channels["c.penetration"][0] == pytest.approx(exact(load), rel=1e-3)
    assert sol.channels["c.normal"][0] == pytest.approx(load, rel=1e-6)
