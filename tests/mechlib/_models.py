"""Small mechanisms and time functions shared by the mechlib tests (SI units throughout).

The models are planar where a hand calculation is the reference: gravity along -y, joint
axes along +z, so that a positive joint angle lifts a bar lying along +x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import mechlib

G = 9.81
"""Gravitational acceleration used by the models (m/s^2)."""


@dataclass(frozen=True)
class Ramp:
    """f(t) = start + slope * t (rad or m) with its exact rates."""

    start: float
    slope: float

    def value(self, t: float) -> float:
        return self.start + self.slope * t

    def rate(self, t: float) -> float:
        return self.slope

    def accel(self, t: float) -> float:
        return 0.0


@dataclass(frozen=True)
class Sine:
    """f(t) = mean + amplitude * sin(omega t) (rad or m) with its exact rates."""

    mean: float
    amplitude: float
    omega: float

    def value(self, t: float) -> float:
        return self.mean + self.amplitude * math.sin(self.omega * t)

    def rate(self, t: float) -> float:
        return self.amplitude * self.omega * math.cos(self.omega * t)

    def accel(self, t: float) -> float:
        return -self.amplitude * self.omega**2 * math.sin(self.omega * t)


@dataclass(frozen=True)
class Bar:
    """A uniform slender bar of `mass` (kg) and `length` (m) hinged at one end."""

    mass: float = 2.0
    length: float = 1.0

    @property
    def i_cm(self) -> float:
        """Moment of inertia about the centre of mass, perpendicular to the bar (kg*m^2)."""
        return self.mass * self.length**2 / 12.0

    @property
    def i_end(self) -> float:
        """Moment of inertia about the hinged end, m L^2 / 3 (kg*m^2)."""
        return self.mass * self.length**2 / 3.0

    @property
    def weight_moment(self) -> float:
        """m g L / 2 (N*m): the gravity moment about the hinge with the bar horizontal."""
        return self.mass * G * self.length / 2.0


def hinged_bar(
    bar: Bar = Bar(),
    *,
    hinge_at: tuple[float, float, float] = (0.0, 0.0, 0.0),
    joint_type: str = "revolute",
    reversed_bodies: bool = False,
    gravity: float = G,
) -> mechlib.Mechanism:
    """Bar `bar` lying along +x from `hinge_at`, joined to ground by `hinge` (axis +z).

    Gravity is (0, -gravity, 0). The bar's body axes are its principal axes: a small
    polar inertia about x keeps the mass matrix regular.
    """
    mech = mechlib.Mechanism(name="bar", gravity=(0.0, -gravity, 0.0))
    x0, y0, z0 = hinge_at
    mech.add_body(
        "bar", mass=bar.mass, cm=(x0 + bar.length / 2.0, y0, z0), inertia=[1e-4, bar.i_cm, bar.i_cm]
    )
    mech.add_point("tip", body="bar", at=(x0 + bar.length, y0, z0))
    bodies = ("ground", "bar") if reversed_bodies else ("bar", "ground")
    mech.add_joint("hinge", joint_type, bodies=bodies, at=hinge_at, axis=(0.0, 0.0, 1.0))
    return mech


def slider_crank(crank: float = 0.1, rod: float = 0.3) -> tuple[mechlib.Mechanism, float]:
    """A slider-crank at crank angle 90 deg: crank A (revolute, z) at the origin, rod from
    the crank pin (spherical B) to the slider (universal C), slider on prismatic D along x.

    Returns the mechanism (1 degree of freedom, no redundant equation) and the design
    slider position x_s = sqrt(rod^2 - crank^2) (m).
    """
    xs = math.sqrt(rod**2 - crank**2)
    mech = mechlib.Mechanism(name="slider_crank")
    mech.add_body("crank", mass=1.0, cm=(0.0, crank / 2, 0.0), inertia=[1e-3] * 3)
    mech.add_body("rod", mass=1.0, cm=(xs / 2, crank / 2, 0.0), inertia=[1e-2] * 3)
    mech.add_body("slider", mass=1.0, cm=(xs, 0.0, 0.0), inertia=[1e-3] * 3)
    mech.add_joint("A", "revolute", bodies=("crank", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_joint("B", "spherical", bodies=("rod", "crank"), at=(0.0, crank, 0.0))
    mech.add_joint(
        "C", "universal", bodies=("rod", "slider"), at=(xs, 0.0, 0.0), axes=((0, 0, 1), (0, 1, 0))
    )
    mech.add_joint("D", "prismatic", bodies=("slider", "ground"), at=(xs, 0.0, 0.0), axis=(1, 0, 0))
    return mech, xs


def sprung_slider(mass: float, stiffness: float, damping: float = 0.0) -> mechlib.Mechanism:
    """A mass (kg) on a prismatic joint `slide` along x, a spring `spring` of `stiffness`
    (N/m) and `damping` (N s/m) from its centre (0.5, 0, 0) m to the origin: a linear
    oscillator along the travel."""
    mech = mechlib.Mechanism()
    mech.add_body("mass", mass=mass, cm=(0.5, 0.0, 0.0), inertia=[1e-2] * 3)
    mech.add_joint(
        "slide", "prismatic", bodies=("mass", "ground"), at=(0.5, 0.0, 0.0), axis=(1.0, 0.0, 0.0)
    )
    mech.add_force(
        mechlib.Spring(
            "spring",
            points=(("mass", (0.5, 0.0, 0.0)), ("ground", (0.0, 0.0, 0.0))),
            stiffness=stiffness,
            damping=damping,
        )
    )
    return mech


def rz(angle: float) -> np.ndarray:
    """Rotation matrix about +z by `angle` (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def falling_chain(links: int = 12) -> mechlib.Mechanism:
    """`links` bars of 0.1 m joined by spherical joints, falling from a gentle horizontal
    arc (benchmarks.models' chain), a point `tip` at its free end: saddle matrices above
    100 rows, factored by band LU (mechlib.linalg.flat_lu)."""
    mech = mechlib.Mechanism(name="chain", gravity=(0.0, -G, 0.0))
    start, heading = np.zeros(3), 0.0
    for i in range(links):
        end = start + 0.1 * np.array([math.cos(heading), 0.0, math.sin(heading)])
        mech.add_body(f"l{i}", mass=0.1, cm=(start + end) / 2, inertia=[1.25e-6, 8.4e-5, 8.4e-5])
        other = "ground" if i == 0 else f"l{i - 1}"
        mech.add_joint(f"s{i}", "spherical", bodies=(f"l{i}", other), at=start)
        start, heading = end, heading + 0.02
    mech.add_point("tip", body=f"l{links - 1}", at=start)
    return mech


def falling_slider_crank(drive: float | None = None) -> mechlib.Mechanism:
    """`slider_crank` under gravity (-y), free, or with its crank A driven at `drive`
    (rad/s) from 0 by the motion `drive`."""
    mech, _ = slider_crank()
    mech.gravity = (0.0, -G, 0.0)
    if drive is not None:
        mech.add_motion("drive", joint="A", function=Ramp(0.0, drive))
    return mech


PENDULUM_REQUESTS = (
    mechlib.JointCoordinate("angle", "hinge"),
    mechlib.JointCoordinate("omega", "hinge", "omega"),
)
"""What `pendulum_errors` reads of a `hinged_bar` run."""


def pendulum_errors(sol: mechlib.Solution, bar: Bar) -> tuple[float, float]:
    """(period error, energy error) of the bar `bar` released from the horizontal
    (`hinged_bar`, requests PENDULUM_REQUESTS): the last return to the horizontal (the
    vertex of the parabola through the three rows around the angle's last maximum) against
    the nearest multiple of the period T = 4 sqrt(I_O / (m g L/2)) K(sin^2(pi/4))
    (elliptic integral, amplitude 90 deg about the hanging position), relative to it; and
    the largest |m g (L/2) sin(theta) + I_O omega^2 / 2| over m g L (zero exactly)."""
    from scipy.special import ellipk

    theta, omega, t = sol.channels["angle.value"], sol.channels["omega.value"], sol.time
    period = 4.0 * math.sqrt(bar.i_end / bar.weight_moment) * ellipk(0.5)
    tops = np.flatnonzero((theta[1:-1] > theta[:-2]) & (theta[1:-1] >= theta[2:])) + 1
    assert tops.size >= 1, "the bar swings back up at least once"
    i = tops[-1]
    a, b, _ = np.polyfit(t[i - 1 : i + 2] - t[i], theta[i - 1 : i + 2], 2)
    vertex = t[i] - b / (2.0 * a)
    cycles = round(vertex / period)
    assert cycles >= 1, "a whole period run"
    energy = bar.weight_moment * np.sin(theta) + 0.5 * bar.i_end * omega**2
    return (
        abs(vertex - cycles * period) / (cycles * period),
        float(np.abs(energy).max()) / (bar.mass * G * bar.length),
    )
