"""Small contact mechanisms shared by the contact tests (SI units, gravity along -y)."""

from __future__ import annotations

import numpy as np

import mechlib as ml
from mechlib.core.rotation import quaternion_from_rotvec
from mechlib.elements.contact import Contact, SpherePlane, StribeckFriction, hertz_stiffness

G = 9.81
"""m/s^2."""
RADIUS = 0.01
"""m, radius of the test spheres."""
K_STEEL = hertz_stiffness(210e9, 0.3, 210e9, 0.3, 0.01 * 0.0105 / 0.0005)
"""N/m^1.5, steel on steel for a 10 mm ball in a socket 0.5 mm larger."""
FRICTION = StribeckFriction(0.15, 0.1)


def posed_pair(element, *, gravity: float, seed: int, depth: float = 5e-7) -> tuple:
    """(system, q, qd) of a ball and a free socket body joined by the contact `element`
    (gravity m/s^2 along -y), both turned, moving at random 1-10 mm/s and rad/s (`seed`),
    the ball moved along the contact normal until it is `depth` (m) into the other surface."""
    m = ml.Mechanism(name="pair", gravity=(0, -gravity, 0))
    m.add_body("ball", mass=0.2, cm=(0.001, 0.002, 0.0), inertia=[8e-6] * 3)
    m.add_body("socket", mass=1.0, cm=(0.0, -0.01, 0.003), inertia=[1e-3, 2e-3, 3e-3])
    m.add_force(element)
    system = ml.System(m)
    q = system.design_q().reshape(-1, 7)
    for b, rotvec in enumerate(([0.3, -0.2, 0.5], [-0.1, 0.4, 0.2])):
        q[b, 3:] = quaternion_from_rotvec(np.array(rotvec))
    q[0, :3] += [2e-4, -4e-4, 1e-4]
    qd = np.random.default_rng(seed).uniform(-1.0, 1.0, q.shape) * np.r_[[1e-2] * 3, [1.0] * 4]
    for _ in range(20):
        gap = element.geometry.gap(system.view(system.kin(q.ravel(), qd.ravel(), 0.0)))
        q[0, :3] -= (depth - gap.penetration) * gap.normal
    return system, q.ravel(), qd.ravel()


def guided_ball(
    law,
    *,
    mass: float = 1.0,
    load: float = 0.0,
    gravity: bool = True,
    height: float = 0.0,
    overlap: float = 0.0,
) -> ml.Mechanism:
    """A ball (centre at y = RADIUS + height) on a vertical prismatic guide above the
    plane y = overlap of ground, pressed down by its weight and `load` (N): touching at
    design by default, apart by `height` or penetrating by `overlap` (m)."""
    m = ml.Mechanism(name="guided-ball", gravity=(0.0, -G if gravity else 0.0, 0.0))
    centre = (0.0, RADIUS + height, 0.0)
    m.add_body("ball", mass=mass, cm=centre, inertia=[4e-5] * 3)
    m.add_point("centre", body="ball", at=centre)
    m.add_joint("guide", "prismatic", bodies=("ball", ml.GROUND), at=centre, axis=(0, 1, 0))
    m.add_force(
        Contact(
            "contact",
            ("ball", ml.GROUND),
            SpherePlane(centre, RADIUS, (0, overlap, 0), (0, 1, 0)),
            law,
        )
    )
    if load:
        m.add_force(ml.PointForce("load", "ball", centre, lambda t, v: (0.0, -load, 0.0)))
    return m
