"""Tension-only wire pendulum (slack and taut again) and tabulated laws (Akima = scipy)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import Akima1DInterpolator

import mechlib
from mechlib.tables import Table, TableRangeError

from .._models import G

L, MASS, K = 1.0, 1.0, 1.0e5  # wire length (m), bob mass (kg), wire stiffness (N/m)


def _wire_pendulum(v0: float):
    """A bob hanging on a wire from the origin, launched horizontally at v0 (m/s), the wire
    stretched by the tension of that state, m (g + v0^2/L) (no radial oscillation)."""
    y0 = -(L + MASS * (G + v0**2 / L) / K)
    mech = mechlib.Mechanism(name="wire", gravity=(0.0, -G, 0.0))
    mech.add_body("bob", mass=MASS, cm=(0.0, y0, 0.0), inertia=[1e-3] * 3)
    mech.add_point("bob_cm", body="bob", at=(0.0, y0, 0.0))
    mech.add_force(
        mechlib.Spring(
            "wire",
            (("bob", (0.0, y0, 0.0)), ("ground", (0.0, 0.0, 0.0))),
            stiffness=K,
            free_length=L,
            tension_only=True,
        )
    )
    init = [mechlib.InitialBodyVelocity("bob", velocity=(v0, 0.0, 0.0))]
    return mechlib.solve(
        mech,
        mechlib.Dynamic(end=1.6, step=0.002),
        initial=init,
        requests=[
            mechlib.ElementOutput("wire", "wire"),
            mechlib.PointKinematics("p", "bob_cm", "position"),
            mechlib.PointKinematics("v", "bob_cm", "velocity"),
        ],
        throw=False,
    ), mech


def test_wire_goes_slack_and_taut_again() -> None:
    """v0^2 = 3.5 g L: the bob rises above the hinge level and the wire goes slack where
    the tension of a rigid rope vanishes, cos(phi) = (2 - v0^2/(g L)) / 3 (phi from the
    bottom) = -0.5, phi = 120 deg; it then flies ballistically until the wire is taut again.
    Checks: tension >= 0 always, taut -> slack -> taut, slack angle within 1 deg of the
    rigid-rope value (the wire stretches m v^2/(k L) ~ 1e-4 m), total energy (kinetic +
    potential + wire) bounded: never above its start by more than 1e-3 relative, and
    not below by more than 1% (the snap when the wire is taut again excites its 50 Hz
    axial mode, which generalized-alpha damps numerically: 0.4% measured)."""
    v0 = math.sqrt(3.5 * G * L)
    sol, _ = _wire_pendulum(v0)
    assert sol.ok, sol.message
    tension = sol.channels["wire.value"]
    assert tension.min() >= 0.0
    taut = tension > 0.0
    changes = np.flatnonzero(np.diff(taut.astype(int)))
    assert taut[0] and len(changes) >= 2 and not taut[changes[0] + 1] and taut[changes[1] + 1]
    x, y = sol.channels["p.x"], sol.channels["p.y"]
    phi = math.degrees(math.atan2(x[changes[0]], -y[changes[0]]))
    assert phi == pytest.approx(120.0, abs=1.0)
    speed2 = sol.channels["v.x"] ** 2 + sol.channels["v.y"] ** 2
    stretch = np.maximum(np.hypot(x, y) - L, 0.0)
    energy = 0.5 * MASS * speed2 + MASS * G * y + 0.5 * K * stretch**2
    assert energy.max() <= energy[0] * (1.0 + 1e-3)
    assert energy.min() >= energy[0] * (1.0 - 1e-2)


def test_akima_table_equals_scipy() -> None:
    """The wind-moment table of SPEC 1.2.1 (and a longer, uneven one): Akima values equal
    scipy's Akima1DInterpolator to 1e-12 relative inside the data."""
    for x, y in (
        ([0, 30, 60, 90], [0, 120, 180, 90]),
        ([0.0, 0.1, 0.5, 0.6, 1.2, 2.0, 2.1], [1.0, 3.0, -2.0, 0.5, 0.5, 4.0, 1.0]),
    ):
        x = np.radians(x) if len(x) == 4 else np.asarray(x)
        table, ref = Table("t", x, y, "akima"), Akima1DInterpolator(x, y)
        for v in np.linspace(x[0], x[-1], 97):
            assert table(v) == pytest.approx(float(ref(v)), rel=1e-12, abs=1e-12)


def test_table_extrapolation_rules() -> None:
    """hold: the end value; linear: the end slope; error: a TableLaw names the element."""
    x, y = [0.0, 1.0, 2.0], [0.0, 2.0, 3.0]
    assert Table("t", x, y, "linear", "hold")(3.0) == 3.0
    assert Table("t", x, y, "linear", "linear")(3.0) == pytest.approx(4.0)
    law = mechlib.TableLaw(Table("t", x, y, "linear", "error"), "harness")
    with pytest.raises(mechlib.SolverFailure, match="harness"):
        law(2.5)


def test_torsion_spring_table_law_static_equilibrium() -> None:
    """A harness-like torque table (Akima, torque resisting the angle) holds a 2 kg, 1 m
    bar: equilibrium where table(theta) = -m g L/2 cos(theta), solved by brentq on scipy's
    Akima interpolant; tolerance 1e-8 rad."""
    from scipy.optimize import brentq

    from .._models import Bar, hinged_bar

    bar = Bar()
    angles = np.radians([-90.0, -60.0, -30.0, 0.0, 30.0])
    torques = np.array([-30.0, -20.0, -12.0, -4.0, 6.0])
    ref = Akima1DInterpolator(angles, torques)
    expected = brentq(
        lambda a: float(ref(a)) + bar.weight_moment * math.cos(a), angles[0], angles[-1], xtol=1e-14
    )
    mech = hinged_bar(bar)
    law = mechlib.TableLaw(Table("harness", angles, torques, "akima"), "harness")
    mech.add_force(mechlib.TorsionSpring("harness", "hinge", law=law))
    sol = mechlib.solve(mech, mechlib.Static(), requests=[mechlib.JointCoordinate("a", "hinge")])
    assert sol.ok, sol.message
    assert sol.channels["a.value"][0] == pytest.approx(expected, abs=1e-8)


@pytest.mark.parametrize("interpolation", ["linear", "cubic", "akima"])
@pytest.mark.parametrize("extrapolate", ["hold", "linear"])
def test_table_integral_is_exact(interpolation: str, extrapolate: str) -> None:
    """Table.integral (the potential of a table law) against scipy's adaptive quadrature of
    the table itself (quad, breakpoints at the data, tolerance 1e-13), inside, across and
    beyond the data and reversed: within 1e-13 J (measured 2e-15); outside the data of an
    `error` table it raises as the table does."""
    from scipy.integrate import quad

    x, y = [0.0, 0.1, 0.25, 0.5, 1.0], [0.0, 3.0, 4.0, 9.0, 10.0]
    table = Table("t", x, y, interpolation, extrapolate)
    for a, b in [(0.0, 0.3), (0.05, 0.9), (-0.2, 1.4), (1.2, 0.02)]:
        ref = quad(table, a, b, points=x, limit=200, epsabs=1e-13, epsrel=1e-13)[0]
        assert abs(table.integral(a, b) - ref) < 1e-13
    with pytest.raises(TableRangeError):
        Table("t", x, y, interpolation, "error").integral(0.0, 1.1)
