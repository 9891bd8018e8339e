"""The servo-actuator calibration study (seed 004 section 6.2; loadcases.studies.
servo_calibration and loadcases/library/rod_end/calibration.py) against closed forms.

- Transmission ratio and equivalent mass of the rod-end's rigid linkage (kinematic run of
  the library mechanism made rigid): dL/dtheta against the slider-crank's closed form
  L(theta) = sqrt(t^2 + s^2 - 2 s t cos(gamma0 + theta)), dL/dtheta = s t sin(gamma) / L
  (seed eq. 4.1), within 1e-9 relative (measured 9e-16); m_eq = 2 T / L'^2 against the
  kinetic energy summed here body by body from the same closed-form positions (central
  differences in theta, 1e-5 relative; measured 6e-8 over the stroke).
- Ziegler-Nichols search on the 100 kg rig of the servo tests (valve fidelity, valve at
  1 kHz): the ultimate gain within 10 % of Merritt's bound K_v = 2 zeta_h w_h (measured
  +6 %: the bound neglects the valve's lag; tests/mechlib/test_servo_actuator.py shows
  0.7 x decays, 1.3 x grows), the ultimate period within 3 % of 2 pi / w_h (measured
  +1.0 %), and the ZN PI rule applied to them.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

ROD_END = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "rod_end"
S, T, L0 = 0.11, 0.38, 0.37  # crank, frame, actuator length at design (m)


def _script():
    spec = importlib.util.spec_from_file_location("calibration", ROD_END / "calibration.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _kinetic_energy_per_rate(theta: float) -> float:
    """2 T / L'^2 (kg) of the rigid linkage at hinge angle theta (rad), from the bodies of
    rod_end.mech.yaml and closed-form positions (central differences, h = 1e-6 rad)."""
    mech = yaml.safe_load((ROD_END / "rod_end.mech.yaml").read_text())
    q = np.array([0.38, 0.0])
    p0 = np.array([354.2105263157895, -106.93410609852879]) * 1e-3
    phi0 = math.atan2(*(p0 - q)[::-1])

    def pose(th):
        p = q + S * np.array([math.cos(phi0 + th), math.sin(phi0 + th)])
        return p, math.atan2(p[1], p[0]), float(np.linalg.norm(p))  # P, actuator angle, L

    h = 1e-6
    (_, ya, la), (_, yb, lb) = pose(theta - h), pose(theta + h)
    _, psi, length = pose(theta)
    psi_rate, length_rate = (yb - ya) / (2 * h), (lb - la) / (2 * h)  # per unit theta'
    energy = 0.0
    for name, body in mech["bodies"].items():
        m, cm = body["mass"], np.array(body["cm"][:2], float) * 1e-3
        izz = float(body["inertia"][2])
        if name == "surface":  # turns about Q at theta'
            r = cm - q
            energy += izz + m * float(r @ r)
            continue
        if name == "ball":  # at P, turning with the surface
            energy += izz + m * S * S
            continue
        # cylinder, rod, socket: turn with the actuator about O; rod and socket slide along
        # it with the travel, their cm at a fixed distance from the eye P
        unit = np.array([math.cos(psi), math.sin(psi)])
        normal = np.array([-unit[1], unit[0]])
        r0 = float(np.linalg.norm(cm))
        if name == "cylinder":
            velocity = r0 * psi_rate * normal
        else:
            r = r0 + length - L0
            velocity = length_rate * unit + r * psi_rate * normal
        energy += izz * psi_rate**2 + m * float(velocity @ velocity)
    return energy / length_rate**2


@pytest.fixture(scope="module")
def transmission(tmp_path_factory: pytest.TempPathFactory):
    return _script().run_transmission(tmp_path_factory.mktemp("calibration"))


def test_transmission_ratio_against_the_slider_crank(transmission) -> None:
    travel, ratio, _ = transmission
    length = L0 + travel
    gamma = np.arccos((T * T + S * S - length**2) / (2 * S * T))
    expected = S * T * np.sin(gamma) / length
    assert ratio == pytest.approx(expected, rel=1e-9)
    assert ratio.min() > 0.09 and ratio.max() < 0.115  # m/rad: the nearly flat fig. 6.9


def test_equivalent_mass_against_the_kinetic_energy_by_hand(transmission) -> None:
    travel, _, mass = transmission
    length = L0 + travel
    gamma = np.arccos((T * T + S * S - length**2) / (2 * S * T))
    gamma0 = math.acos((T * T + S * S - L0 * L0) / (2 * S * T))
    for row in range(0, len(travel), 10):
        expected = _kinetic_energy_per_rate(float(gamma[row] - gamma0))
        assert mass[row] == pytest.approx(expected, rel=1e-5), travel[row]


def test_ziegler_nichols_finds_the_hydraulic_stability_bound() -> None:
    from loadcases.studies.servo_calibration import ziegler_nichols
    from mechlib.elements.hydraulics import Cylinder, ServoValve
    from tests.mechlib.hydraulic_rig import rig

    mass, cyl = 100.0, Cylinder()
    v1, v2 = cyl.volumes(0.0)
    total = v1 + v2
    w_h = math.sqrt(cyl.hydraulic_stiffness(0.0) / mass)
    zeta = cyl.leakage / cyl.area_1 * math.sqrt(cyl.bulk_modulus * mass / total) + (
        cyl.viscous_friction / (4 * cyl.area_1) * math.sqrt(total / (cyl.bulk_modulus * mass))
    )
    actuator = rig(valve=ServoValve(frequency=1000.0)).forces["act"]
    bound = 2 * zeta * w_h / actuator.loop_gain() * actuator.controller.kp  # A/m
    zn = ziegler_nichols(actuator, mass, rtol=0.02, end=0.2)
    assert zn.ultimate_gain == pytest.approx(bound, rel=0.10)
    assert zn.ultimate_period == pytest.approx(2 * math.pi / w_h, rel=0.03)
    assert zn.kp == pytest.approx(0.45 * zn.ultimate_gain, rel=1e-12)
    assert zn.ki == pytest.approx(zn.kp * 1.2 / zn.ultimate_period, rel=1e-12)
    stable = [e for e in zn.evaluations if e.kp <= zn.ultimate_gain / 1.02]
    assert stable and all(e.sigma < 0 for e in stable)
