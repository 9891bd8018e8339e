"""The compiled contact tangent (stiffness -dQ/dq, damping -dQ/dqd) against central
differences of the system's generalized forces (SI units)."""

from __future__ import annotations

import numpy as np
import pytest

from mechlib.elements.contact import (
    Contact,
    HertzLaw,
    ImpactLaw,
    SpherePlane,
    revolute_clearance,
    spherical_clearance,
)
from tests.mechlib.contact._contact_models import FRICTION, K_STEEL, posed_pair


def _central(system, q, qd, t, which: int) -> np.ndarray:
    """-dQ/dq (which = 0) or -dQ/dqd (1) of the contact forces, central differences."""
    n = system.nq
    out = np.empty((n, n))
    for j in range(n):
        step = (1e-11 if j % 7 < 3 else 1e-9) if which == 0 else 1e-9
        d = np.zeros(n)
        d[j] = step
        args = [(q + d, qd), (q - d, qd)] if which == 0 else [(q, qd + d), (q, qd - d)]
        plus, minus = (system.forces(system.kin(a, b, t), inertia=False) for a, b in args)
        out[:, j] = -(plus - minus) / (2 * step)
    return out


@pytest.mark.parametrize(
    "element",
    [
        spherical_clearance(
            "c",
            ("ball", "socket"),
            center=(0, 0, 0),
            radius=0.01,
            clearance=5e-4,
            law=HertzLaw(K_STEEL, 1.5, 0.5),
            friction=FRICTION,
        ),
        revolute_clearance(
            "c",
            ("ball", "socket"),
            center=(0, 0, 0),
            axis=(0, 0, 1),
            radius=0.01,
            clearance=5e-4,
            law=HertzLaw(K_STEEL, 1.5, 0.5),
            friction=FRICTION,
        ),
        Contact(
            "c",
            ("ball", "socket"),
            SpherePlane((0, 0, 0), 0.01, (0, -0.01, 0), (0, 1, 0)),
            ImpactLaw(1e9, 1.5, damping=1e3, depth=1e-5),
            FRICTION,
        ),
    ],
)
def test_contact_tangent_matches_central_differences(element) -> None:
    """A steel ball 0.5 um into its socket (or a pin in its hole, a sphere on a plane),
    both bodies turned and moving, sliding in the Stribeck regime: K and C of
    `Contact.tangent` equal central differences of `System.forces` (increments 1e-11 m,
    1e-9 for Euler parameters and rates) within 1e-4 of their largest entry (the kernel's
    forward differences of about 1e-11 m over a 5e-7 m deflection: measured 1.2e-5)."""
    system, q, qd = posed_pair(element, gravity=0.0, seed=3)
    element.approach = 0.05
    k = system.kin(q, qd, 0.0)
    assert element.forces(system.view(k)).friction > 0.0
    stiffness, damping = np.zeros((14, 14)), np.zeros((14, 14))
    element.tangent(system.view(k), stiffness, damping)
    for mine, which in ((stiffness, 0), (damping, 1)):
        ref = _central(system, q, qd, 0.0, which)
        np.testing.assert_allclose(mine, ref, rtol=0, atol=1e-4 * np.abs(ref).max())
