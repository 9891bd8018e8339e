"""The stiff-contact benchmark: a steel ball bouncing on a steel plane (Hertz contact).

A solid steel ball (radius 10 mm, density 7850 kg/m^3) is released at rest with its lowest
point 0.1 m above the plane y = 0 and bounces under gravity (-y) for 1 s: six impacts, each
lasting about 60 microseconds. The contact force is Hertz's K x^1.5 with K = 4/3 E* sqrt(R)
(steel on steel, E = 210 GPa, nu = 0.3: E* = 115 GPa, K = 1.54e10 N/m^1.5) and
Lankarani-Nikravesh damping of restitution 0.7 (the `hertz` law of `loads`); no friction, so
the ball moves only vertically.

`hertz_impact` gives the closed form of an undamped Hertz impact (maximum penetration and
contact time), which tests/benchmarks check the Exudyn model against. All SI.
"""

from __future__ import annotations

import math

import numpy as np

from benchmarks.models import GRAVITY, BodySpec, ContactSpec, ModelSpec, OutputSpec, PointSpec

__all__ = [
    "BALL_RADIUS",
    "DROP_HEIGHT",
    "STEEL",
    "ball_bounce",
    "ball_mass",
    "effective_modulus",
    "hertz_impact",
]

BALL_RADIUS = 0.01  # m
STEEL_DENSITY = 7850.0  # kg/m^3
STEEL = (210e9, 0.3)  # Young's modulus (Pa) and Poisson's ratio of ball and plane
DROP_HEIGHT = 0.1  # m, gap between the ball and the plane at release
RESTITUTION = 0.7  # Lankarani-Nikravesh coefficient of the `hertz` law
HERTZ_EXPONENT = 1.5


def ball_mass(radius: float = BALL_RADIUS) -> float:
    """Mass (kg) of a solid steel ball of `radius` (m)."""
    return STEEL_DENSITY * 4.0 / 3.0 * math.pi * radius**3


def effective_modulus(e1: float, nu1: float, e2: float, nu2: float) -> float:
    """E* (Pa) of two elastic bodies: 1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2."""
    return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)


def hertz_impact(mass: float, radius: float, modulus: float, speed: float) -> tuple[float, float]:
    """Closed form of an undamped Hertz impact of a sphere on a plane (Johnson, Contact
    Mechanics, 11.2): `(max_penetration, contact_time)` (m, s) for a sphere of `mass` (kg)
    and `radius` (m) arriving at `speed` (m/s), E* = `modulus` (Pa):
    ((15 m v^2) / (16 E* sqrt(R)))^(2/5) and 2.87 (m^2 / (R E*^2 v))^(1/5)."""
    penetration = (15.0 * mass * speed**2 / (16.0 * modulus * math.sqrt(radius))) ** 0.4
    duration = 2.87 * (mass**2 / (radius * modulus**2 * speed)) ** 0.2
    return penetration, duration


def ball_bounce(restitution: float = RESTITUTION, end: float = 1.0) -> ModelSpec:
    """The bouncing ball as a ModelSpec (`restitution` 1.0: an undamped contact)."""
    mass = ball_mass()
    centre = (0.0, DROP_HEIGHT + BALL_RADIUS, 0.0)
    inertia = 0.4 * mass * BALL_RADIUS**2
    modulus = effective_modulus(*STEEL, *STEEL)
    stiffness = 4.0 / 3.0 * modulus * math.sqrt(BALL_RADIUS)
    impact_speed = math.sqrt(2.0 * GRAVITY * DROP_HEIGHT)
    _, duration = hertz_impact(mass, BALL_RADIUS, modulus, impact_speed)
    contact = ContactSpec(
        name="floor",
        body="ball",
        center=centre,
        radius=BALL_RADIUS,
        plane_point=(0.0, 0.0, 0.0),
        normal=(0.0, 1.0, 0.0),
        stiffness=stiffness,
        exponent=HERTZ_EXPONENT,
        restitution=restitution,
    )
    diag = tuple(tuple(float(v) for v in row) for row in np.diag([inertia] * 3))
    return ModelSpec(
        name="ball_bounce",
        title=f"steel ball bouncing on a steel plane, Hertz contact, {end:g} s",
        bodies=(BodySpec("ball", mass, centre, diag),),
        joints=(),
        points=(PointSpec("centre", "ball", centre),),
        gravity=(0.0, -GRAVITY, 0.0),
        end=end,
        quick_end=0.3,
        output_step=1e-3,
        outputs=(OutputSpec("ball", "y", "point_position", "centre"),),
        main=("ball.y",),
        contacts=(contact,),
        notes=(
            f"1 body, 6 DOF, Hertz K = {stiffness:.4g} N/m^1.5, "
            f"Lankarani-Nikravesh restitution {restitution:g}",
            f"first impact at {impact_speed:.3g} m/s, contact time about {duration * 1e6:.0f} us",
        ),
    )
