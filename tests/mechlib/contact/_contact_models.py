"""Small contact mechanisms shared by the contact tests (SI units, gravity along -y)."""

from __future__ import annotations

import mechlib as ml
from mechlib.elements.contact import Contact, SpherePlane

G = 9.81
"""m/s^2."""
RADIUS = 0.01
"""m, radius of the test spheres."""


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
