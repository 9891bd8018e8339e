"""Block on an incline held by four sphere-plane contacts with Stribeck friction.

A 1 kg box rests on four spheres (R = 10 mm at its corners, 0.2 m apart) on the plane y = 0;
gravity is tilted by theta, so the plane is an incline. Friction: mu_static 0.3, mu_dynamic
0.25, v_static 1 mm/s, v_dynamic 10 mm/s (seed 004 eq. 3.9). References (Coulomb):
- tan(theta) = 0.2 < mu_static: the block sticks -- it creeps at below v_static (the
  regularised law has no true stiction) and does not accelerate;
- tan(theta) = 0.5 > mu_static: it slides with a = g (sin theta - mu_dynamic cos theta)
  once faster than v_dynamic, within 1 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.contact import Contact, ImpactLaw, SpherePlane, StribeckFriction

G, K, R = 9.81, 1.0e7, 0.01
FRICTION = StribeckFriction(0.3, 0.25, 1e-3, 1e-2)
CORNERS = [(-0.1, -0.1), (-0.1, 0.1), (0.1, -0.1), (0.1, 0.1)]


def block_on_incline(slope: float, end: float = 1.0) -> ml.Solution:
    """Box on four frictional sphere contacts; gravity tilted to tan(theta) = slope."""
    theta = math.atan(slope)
    m = ml.Mechanism(name="incline", gravity=(G * math.sin(theta), -G * math.cos(theta), 0))
    m.add_body("box", mass=1.0, cm=(0, 0.05, 0), inertia=[0.01, 0.01, 0.01])
    m.add_point("cm", body="box", at=(0, 0.05, 0))
    # each sphere carries a quarter of the weight's normal part: start at that penetration
    overlap = (G * math.cos(theta) / 4 / K) ** (1 / 1.5)
    law = ImpactLaw(K, 1.5, damping=2.0e3, depth=1e-5)
    for i, (x, z) in enumerate(CORNERS):
        m.add_force(
            Contact(
                f"c{i}",
                ("box", ml.GROUND),
                SpherePlane((x, R, z), R, (0, overlap, 0), (0, 1, 0)),
                law,
                FRICTION,
            )
        )
    return ml.solve(
        m,
        ml.Dynamic(end=end, step=0.01),
        requests=[ml.PointKinematics("v", "cm", "velocity"), ml.ElementOutput("c0", "c0")],
    )


def test_sticks_below_mu_static() -> None:
    sol = block_on_incline(0.2)
    v = np.asarray(sol.channels["v.x"])
    assert np.abs(v[len(v) // 2 :]).max() < FRICTION.v_static
    assert abs(v[-1] - v[len(v) // 2]) < 0.1 * FRICTION.v_static  # no acceleration


def test_slides_with_dynamic_friction_above_mu_static() -> None:
    sol = block_on_incline(0.5)
    t, v = np.asarray(sol.time), np.asarray(sol.channels["v.x"])
    fast = t >= 0.5
    assert v[fast].min() > FRICTION.v_dynamic
    a = np.polyfit(t[fast], v[fast], 1)[0]
    theta = math.atan(0.5)
    assert a == pytest.approx(G * (math.sin(theta) - 0.25 * math.cos(theta)), rel=0.01)
