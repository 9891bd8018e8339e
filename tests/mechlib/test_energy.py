"""The energy request (`mechlib.EnergyBalance`, case key `quantity: energy`) against
closed forms. Its work and dissipation columns are trapezoid sums over the output rows
(second order in the output interval); the bounds below are the measured values x about 3.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib
from mechlib.solvers.assembly import InitialValue

from ._models import Bar, G, Ramp, hinged_bar


def _energy(sol: mechlib.Solution, name: str = "e") -> dict[str, np.ndarray]:
    return {c.split(".", 1)[1]: v for c, v in sol.channels.items() if c.startswith(name + ".")}


def test_pendulum_exchanges_kinetic_and_gravitational_energy() -> None:
    """A bar (2 kg, 1 m) hinged at one end, released horizontal: kinetic = I_end omega^2 / 2
    and gravitational = m g (L/2) sin(angle) (the cm's height) at every row, from the
    run's own angle and rate; no drive, load or dissipation; the balance stays within
    1e-4 J of the 9.81 J exchanged (generalized-alpha's numerical damping, rho_inf 0.9,
    tolerance 1e-8)."""
    bar = Bar(2.0, 1.0)
    sol = mechlib.solve(
        hinged_bar(bar),
        mechlib.Dynamic(end=2.0, step=0.005, tolerance=1e-8),
        requests=[
            mechlib.EnergyBalance("e"),
            mechlib.JointCoordinate("a", "hinge", "angle"),
            mechlib.JointCoordinate("w", "hinge", "omega"),
        ],
    )
    e = _energy(sol)
    angle, omega = sol.channels["a.value"], sol.channels["w.value"]
    assert np.abs(e["kinetic"] - 0.5 * bar.i_end * omega**2).max() < 1e-6
    assert np.abs(e["gravitational"] - bar.mass * G * 0.5 * np.sin(angle)).max() < 1e-9
    assert e["kinetic"].max() > 9.8  # the bar swung through its lowest position
    for quiet in ("elastic", "drive_work", "load_work", "dissipated"):
        assert np.abs(e[quiet]).max() == 0.0
    assert np.abs(e["balance"]).max() < 4e-4


def _oscillator(damping: float) -> mechlib.Mechanism:
    """A 2 kg block on a prismatic joint along x, tied to ground by a spring of 800 N/m and
    a damper of `damping` N*s/m (no gravity)."""
    mech = mechlib.Mechanism(name="oscillator")
    mech.add_body("block", mass=2.0, cm=(1.0, 0.0, 0.0), inertia=[1e-2] * 3)
    mech.add_joint("slide", "prismatic", bodies=("block", "ground"), at=(1, 0, 0), axis=(1, 0, 0))
    mech.add_force(
        mechlib.Spring(
            "spring",
            points=(("block", (1.0, 0.0, 0.0)), ("ground", (0.0, 0.0, 0.0))),
            stiffness=800.0,
            damping=damping,
        )
    )
    return mech


def test_damped_oscillator_dissipates_its_energy() -> None:
    """Free decay from x0 = 0.05 m (m = 2 kg, k = 800 N/m, c = 8 N*s/m: zeta = 0.1):
    x(t) = x0 e^(-zeta wn t) (cos wd t + zeta/sqrt(1-zeta^2) sin wd t); the elastic column is
    k x^2 / 2, dissipated = E0 - (m v^2 + k x^2)/2 (the closed form of the integral of
    c v^2), balance ~0; no drive and no load work (the spring's own work is its potential)."""
    m, k, c, x0 = 2.0, 800.0, 8.0, 0.05
    sol = mechlib.solve(
        _oscillator(c),
        mechlib.Dynamic(end=1.0, step=0.002, tolerance=1e-9),
        requests=[mechlib.EnergyBalance("e")],
        initial=[InitialValue("slide", value=x0)],
    )
    wn = math.sqrt(k / m)
    zeta = c / (2 * math.sqrt(k * m))
    wd = wn * math.sqrt(1 - zeta**2)
    t = sol.time
    decay = np.exp(-zeta * wn * t)
    x = x0 * decay * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta**2) * np.sin(wd * t))
    v = -x0 * wn / math.sqrt(1 - zeta**2) * decay * np.sin(wd * t)
    e0 = 0.5 * k * x0**2
    e = _energy(sol)
    assert np.abs(e["elastic"] - 0.5 * k * x**2).max() < 6e-5 * e0
    assert np.abs(e["kinetic"] - 0.5 * m * v**2).max() < 6e-5 * e0
    lost = e0 - 0.5 * (m * v**2 + k * x**2)
    assert lost[-1] > 0.7 * e0
    assert np.abs(e["dissipated"] - lost).max() < 2e-4 * e0
    assert np.abs(e["load_work"]).max() < 1e-12 and np.abs(e["drive_work"]).max() == 0.0
    assert np.abs(e["balance"]).max() < 2e-4 * e0


def test_coulomb_friction_dissipates_mu_n_times_the_distance() -> None:
    """A 3 kg block on a horizontal prismatic joint (mu = 0.3, gravity -y: normal force
    m g) launched at 2 m/s slides d = v0^2 / (2 mu g) = 0.680 m and stops: dissipated =
    mu m g * distance along the way (the block's travel), = m v0^2 / 2 = 6 J at the end."""
    m, mu, v0 = 3.0, 0.3, 2.0
    mech = mechlib.Mechanism(name="block", gravity=(0.0, -G, 0.0))
    mech.add_body("block", mass=m, cm=(0.0, 0.0, 0.0), inertia=[1e-2] * 3)
    mech.add_joint("slide", "prismatic", bodies=("block", "ground"), at=(0, 0, 0), axis=(1, 0, 0))
    mech.add_force(mechlib.JointFriction("friction", joint="slide", mu=mu))
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=1.0, step=0.002, tolerance=1e-8),
        requests=[mechlib.EnergyBalance("e"), mechlib.JointCoordinate("x", "slide", "travel")],
        initial=[InitialValue("slide", rate=v0)],
    )
    e, x = _energy(sol), sol.channels["x.value"]
    assert x[-1] == pytest.approx(v0**2 / (2 * mu * G), rel=1e-3)
    assert np.abs(e["dissipated"] - mu * m * G * x).max() < 2e-3 * 0.5 * m * v0**2
    assert e["dissipated"][-1] == pytest.approx(0.5 * m * v0**2, rel=2e-3)
    assert np.abs(e["balance"]).max() < 2e-3 * 0.5 * m * v0**2


@pytest.mark.parametrize("analysis", ["kinematic", "quasi-static", "dynamic"])
def test_driven_crank_work_lifts_the_bar(analysis: str) -> None:
    """A bar (2 kg, 1 m) driven from horizontal at omega = 1 rad/s: at constant speed the
    kinetic energy is constant (I_end omega^2 / 2; 0 where inertia is ignored), so the
    drive work is the potential gained, m g (L/2) sin(omega t), the integral of torque x
    omega; balance ~0."""
    bar, omega = Bar(2.0, 1.0), 1.0
    mech = hinged_bar(bar)
    mech.add_motion("drive", joint="hinge", function=Ramp(0.0, omega))
    spec = {
        "kinematic": mechlib.Kinematic(end=1.2, step=0.01),
        "quasi-static": mechlib.QuasiStatic(end=1.2, step=0.01),
        "dynamic": mechlib.Dynamic(end=1.2, step=0.01),
    }[analysis]
    sol = mechlib.solve(mech, spec, requests=[mechlib.EnergyBalance("e")])
    e = _energy(sol)
    lift = bar.mass * G * 0.5 * np.sin(omega * sol.time)
    kinetic = 0.0 if analysis == "quasi-static" else 0.5 * bar.i_end * omega**2
    assert np.abs(e["kinetic"] - kinetic).max() < (1e-7 if analysis == "dynamic" else 1e-12)
    # trapezoid over rows 0.01 s apart: error h^2/12 * max|P''| * t ~ 1e-5 J
    assert np.abs(e["drive_work"] - lift).max() < 3e-5 * lift.max()
    assert np.abs(e["balance"]).max() < 3e-5 * lift.max()
