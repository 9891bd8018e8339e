"""Static equilibrium on contacts that start touching, apart or penetrating.

A contact k x^e has no stiffness at zero penetration or when open, so Newton's matrix is
singular there: the static analysis brings the body to rest by pseudo-transient continuation
first (mechlib/solvers/static/continuation.py, docs/analyses.md, Static). References (closed form,
force balance along the contact normal, no friction):
- a block on an impact pad: penetration x* = (m g / k)^(1/e);
- a ball in its socket (Hertz, elastic): eccentricity = clearance + (m g / K)^(1/n), K from
  `hertz_stiffness` with the internal radius R (R + c) / c, along gravity.
Tolerance asked: 1e-6 relative. Measured (2026-11, this file): penetration errors at most
4e-11 relative over every start below, 1.4e-11 of the deflection in the socket; Newton stops
at a force residual of 1e-10 of the weight, i.e. about 1e-10 / e of x*. Guarded at 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.contact import (
    Contact,
    HertzLaw,
    ImpactLaw,
    SpherePlane,
    hertz_stiffness,
    spherical_clearance,
)
from tests.mechlib.contact._contact_models import G, guided_ball

DEFLECTION = 1.0e-4
"""m: the static penetration x* every pad below is given (k = m g / x*^e, m = 1 kg)."""
MEASURED = 1e-9
"""Relative error guarded (measured at most 4e-11; brief: 1e-6)."""


def _pad_penetration(exponent: float, start: float) -> tuple[float, ml.Solution]:
    """Static penetration (m) of a 1 kg ball on a pad of stiffness m g / x*^e, the ball
    starting `start` x* apart (> 0), touching (0) or penetrating (< 0)."""
    law = ImpactLaw(G / DEFLECTION**exponent, exponent)
    mech = (
        guided_ball(law, height=start * DEFLECTION)
        if start >= 0.0
        else guided_ball(law, overlap=-start * DEFLECTION)
    )
    sol = ml.solve(mech, ml.Static(), requests=[ml.ElementOutput("pad", "contact")])
    return float(sol.channels["pad.penetration"][0]), sol


@pytest.mark.parametrize("exponent", [1.0, 1.5, 2.2])
@pytest.mark.parametrize("start", [0.0, 1e-3, 1.0, 10.0, 100.0, -2.0])
def test_pad_penetration_from_any_start(exponent: float, start: float) -> None:
    """x* = (m g / k)^(1/e) from touching (0), apart by 1e-3 to 100 x* and penetrating
    2 x*: within MEASURED relative (brief 1e-6); the contact carries the weight."""
    penetration, sol = _pad_penetration(exponent, start)
    assert abs(penetration - DEFLECTION) <= MEASURED * DEFLECTION
    assert sol.channels["pad.normal"][0] == pytest.approx(G, rel=MEASURED)
    assert sol.stats.newton_iterations <= 40  # measured 21-29: continuation + Newton


@pytest.mark.parametrize("gravity", [(0.0, -G, 0.0), (3.0, -9.0, 1.0)])
def test_ball_rests_in_its_socket_at_clearance_plus_hertz_deflection(gravity) -> None:
    """0.2 kg steel ball, R = 10 mm, c = 0.5 mm, E = 210 GPa, nu = 0.3 (K = 7.05e10
    N/m^1.5), its rotation held by an orientation joint, released centred (5400
    deflections from the wall): e = c + (m |g| / K)^(1/1.5) along g, the deflection within
    MEASURED of itself (measured 1.4e-11)."""
    radius, clearance, mass = 0.01, 5e-4, 0.2
    stiffness = hertz_stiffness(210e9, 0.3, 210e9, 0.3, radius * (radius + clearance) / clearance)
    m = ml.Mechanism(name="socket", gravity=gravity)
    m.add_body("ball", mass=mass, cm=(0, 0, 0), inertia=[8e-6] * 3)
    m.add_joint("keep", "orientation", bodies=("ball", ml.GROUND), at=(0, 0, 0), axis=(0, 0, 1))
    m.add_force(
        spherical_clearance(
            "socket",
            ("ball", ml.GROUND),
            center=(0, 0, 0),
            radius=radius,
            clearance=clearance,
            law=HertzLaw(stiffness, 1.5),
        )
    )
    sol = ml.solve(m, ml.Static(), requests=[ml.ElementOutput("s", "socket")])
    deflection = (mass * np.linalg.norm(gravity) / stiffness) ** (1 / 1.5)
    ecc = np.array([sol.channels[f"s.e{c}"][0] for c in "xyz"])
    expected = (clearance + deflection) * np.asarray(gravity) / np.linalg.norm(gravity)
    assert np.abs(ecc - expected).max() <= MEASURED * deflection


def test_pad_facing_away_names_body_and_contact() -> None:
    """A pad whose normal points down, away from the ball above it, pushes the ball down
    with gravity (through the pad and beyond): no equilibrium. The failure says when,
    which body is not held, along which direction, and what the contact does (check its
    normal)."""
    m = ml.Mechanism(name="upside-down", gravity=(0.0, -G, 0.0))
    m.add_body("ball", mass=1.0, cm=(0, 0.01, 0), inertia=[4e-5] * 3)
    m.add_joint("guide", "prismatic", bodies=("ball", ml.GROUND), at=(0, 0.01, 0), axis=(0, 1, 0))
    m.add_force(
        Contact(
            "pad",
            ("ball", ml.GROUND),
            SpherePlane((0, 0.01, 0), 0.01, (0, 0, 0), (0, -1, 0)),
            ImpactLaw(1e6, 1.5),
        )
    )
    with pytest.raises(ml.SolverFailure) as failure:
        ml.solve(m, ml.Static(time=0.25))
    message = str(failure.value)
    assert failure.value.time == 0.25 and failure.value.where == ("ball", "pad")
    assert message.startswith(
        "static equilibrium not found at t = 0.25 s: body 'ball' is not held along (0, -1, 0)"
    )
    assert "contact 'pad'" in message and "normal points from body 2" in message


def test_floating_body_without_load_stays_a_singular_failure() -> None:
    """Continuation only brings loaded bodies to rest: a ball apart from its pad with no
    gravity and no load has no isolated equilibrium, reported as singular (as before)."""
    mech = guided_ball(ImpactLaw(1e6, 1.5), gravity=False, height=1e-3)
    sol = ml.solve(mech, ml.Static(), throw=False)
    assert sol.status == "failed"
    assert "singular" in sol.message and "t = 0 s" in sol.message
