"""Quasi-static runs in which a contact closes: a block lowered onto a pad, a load ramped up.

Both start at zero penetration (no contact stiffness: the first equilibrium needs the
pseudo-transient continuation of mechlib/solvers/static/continuation.py). References are force
balances along the vertical (no friction), solved to 1e-15 by brentq where two contacts share the
load. Tolerance asked: 1e-6 relative; measured (2026-11, this file): 4e-12 of the static
deflection x* (lowered block), 4e-11 relative (ramped load); guarded at 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import mechlib as ml
from mechlib.elements.contact import Contact, ImpactLaw, SpherePlane
from tests.mechlib._models import Ramp
from tests.mechlib.contact._contact_models import RADIUS, G, guided_ball

MASS, EXPONENT, DEFLECTION = 1.0, 1.5, 1.0e-4
"""kg, -, m: x* = (m g / k)^(1/e), the penetration of one contact carrying the block."""
STIFFNESS = MASS * G / DEFLECTION**EXPONENT
"""N/m^1.5."""
RAISED = 3.0 * DEFLECTION
"""m: the platform's height over the pad at t = 0 (the foot on it touching)."""
LOWERED = 6.0 * DEFLECTION
"""m: how far the platform goes down in 1 s."""
MEASURED = 1e-9
"""Error guarded, relative (measured at most 4e-11; brief: 1e-6)."""


def _lowered_block() -> ml.Mechanism:
    """A block on a vertical guide with two feet (spheres, radius RADIUS, 0.1 m apart):
    foot A on a platform lowered by a motion, foot B over the ground pad y = 0."""
    law = ImpactLaw(STIFFNESS, EXPONENT)
    m = ml.Mechanism(name="lowered-block", gravity=(0.0, -G, 0.0))
    centre = (0.0, RADIUS + RAISED, 0.0)
    m.add_body("block", mass=MASS, cm=centre, inertia=[1e-3] * 3)
    m.add_point("centre", body="block", at=centre)
    m.add_joint("guide", "prismatic", bodies=("block", ml.GROUND), at=centre, axis=(0, 1, 0))
    m.add_body("platform", mass=5.0, cm=(-0.05, RAISED - 0.01, 0.0), inertia=[1e-2] * 3)
    m.add_joint(
        "lift", "prismatic", bodies=("platform", ml.GROUND), at=(-0.05, 0.0, 0.0), axis=(0, 1, 0)
    )
    m.add_motion("lower", joint="lift", function=Ramp(0.0, -LOWERED))
    foot_a, foot_b = (-0.05, RADIUS + RAISED, 0.0), (0.05, RADIUS + RAISED, 0.0)
    m.add_force(
        Contact(
            "on_platform",
            ("block", "platform"),
            SpherePlane(foot_a, RADIUS, (-0.05, RAISED, 0.0), (0, 1, 0)),
            law,
        )
    )
    m.add_force(
        Contact(
            "on_pad",
            ("block", ml.GROUND),
            SpherePlane(foot_b, RADIUS, (0.05, 0.0, 0.0), (0, 1, 0)),
            law,
        )
    )
    return m


def _penetrations(t: float) -> tuple[float, float]:
    """(platform, pad) penetrations (m) at time t: k x_a^e + k x_b^e = m g with
    x_a = RADIUS - (y - y_platform), x_b = RADIUS - y (y: the feet's centres)."""
    platform = RAISED - LOWERED * t

    def pressed(y: float) -> tuple[float, float]:
        return max(RADIUS - (y - platform), 0.0), max(RADIUS - y, 0.0)

    def unbalanced(y: float) -> float:
        return sum(STIFFNESS * x**EXPONENT for x in pressed(y)) - MASS * G

    top = RADIUS + max(platform, 0.0)
    return pressed(brentq(unbalanced, top - 2 * DEFLECTION, top, xtol=1e-15))


def test_block_lowered_onto_the_pad() -> None:
    """The platform carries the block (x_a = x*) until t = 1/3, both share it until 2/3,
    the pad alone after (x_b = x*): each contact's penetration within MEASURED x* of the
    force balance at all 21 outputs; the two contact forces add up to the weight."""
    sol = ml.solve(
        _lowered_block(),
        ml.QuasiStatic(1.0, 0.05),
        requests=[ml.ElementOutput("a", "on_platform"), ml.ElementOutput("b", "on_pad")],
    )
    expected = np.array([_penetrations(t) for t in sol.time])
    assert len(sol.time) == 21
    assert expected[0, 1] == 0.0 and expected[-1, 0] == 0.0  # the load changes contact
    assert np.abs(sol.channels["a.penetration"] - expected[:, 0]).max() <= MEASURED * DEFLECTION
    assert np.abs(sol.channels["b.penetration"] - expected[:, 1]).max() <= MEASURED * DEFLECTION
    total = sol.channels["a.normal"] + sol.channels["b.normal"]
    assert np.abs(total - MASS * G).max() <= MEASURED * MASS * G


def test_load_ramped_onto_a_touching_pad() -> None:
    """No gravity; a ball touching the pad at zero penetration is pressed by F = 1 + 99 t
    N: penetration (F / k)^(1/e) at every output within MEASURED of its value."""
    mech = guided_ball(ImpactLaw(STIFFNESS, EXPONENT), gravity=False)
    mech.add_force(
        ml.PointForce(
            "press", "ball", (0.0, RADIUS, 0.0), lambda t, v: (0.0, -(1.0 + 99.0 * t), 0.0)
        )
    )
    sol = ml.solve(mech, ml.QuasiStatic(1.0, 0.1), requests=[ml.ElementOutput("pad", "contact")])
    expected = ((1.0 + 99.0 * sol.time) / STIFFNESS) ** (1.0 / EXPONENT)
    assert np.abs(sol.channels["pad.penetration"] / expected - 1.0).max() <= MEASURED


@pytest.mark.parametrize("analysis", [ml.Static(), ml.QuasiStatic(0.2, 0.1)])
def test_statistics_stay_small(analysis) -> None:
    """The continuation is entered once, at the first equilibrium, not at every output:
    measured 19 iterations for a static run, 27 for three quasi-static outputs."""
    sol = ml.solve(_lowered_block(), analysis, requests=[])
    assert sol.ok and sol.stats.newton_iterations <= 40
