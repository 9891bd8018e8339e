"""Energy balance of the servo-actuator (issue 12 item 2): the hydraulic energy delivered
by the supply equals the work on the mechanism plus the losses, within 1 %.

Balance over [0, T] (each term a time integral of the recorded channels, trapezoidal rule):
  int (p_s q_s - p_r q_r) dt                                  hydraulic energy in
  = int throttling dt                                         the two open spool lands
  + int C_ip (p1 - p2)^2 dt                                   leakage across the piston
  + int (gamma v^2 + F_c tanh(v/v_c) v) dt                    piston friction
  + sum p V dp / beta                                         oil compression (stored)
  + [M v^2 / 2] + int F_load v dt                             work on the rod (its motion)
The work on the rod is measured on the mechanism (its speed, from the joint), not from the
actuator's force: a force applied inconsistently with the states would break the balance.
"""

from __future__ import annotations

import math

import numpy as np

import mechlib as ml
from mechlib.elements.hydraulics import Cylinder
from tests.mechlib.hydraulic_rig import REQUESTS, rig

M, LOAD = 100.0, 3000.0
CYLINDER = Cylinder(coulomb_friction=200.0, coulomb_speed=5e-3)


def _integral(t: np.ndarray, y: np.ndarray) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)))


def test_hydraulic_energy_in_equals_work_plus_losses() -> None:
    """10 mm at 2 Hz against a 3 kN load, the first 0.15 s (extending), outputs
    every 0.2 ms: imbalance below 1 % of the energy in (the issue's limit), guarded at 1e-4
    (measured -2.3e-6: the trapezoidal sums of the channels). 190 J in: 157 J throttled,
    27 J of work on the rod, 4.6 J friction, 0.9 J leakage, 0.2 J compression."""
    sol = ml.solve(
        rig(lambda t: 0.01 * math.sin(2 * math.pi * 2.0 * t), load=LOAD, cylinder=CYLINDER),
        ml.Dynamic(end=0.15, step=2e-4, tolerance=1e-6),
        requests=REQUESTS,
    )
    t, ch = sol.time, sol.channels
    v, x = ch["v.value"], ch["x.value"]
    p1, p2 = ch["act.p1"], ch["act.p2"]
    c = CYLINDER
    energy_in = _integral(t, ch["act.power"])
    throttling = _integral(t, ch["act.throttling"])
    leakage = _integral(t, c.leakage * (p1 - p2) ** 2)
    friction = _integral(
        t, c.viscous_friction * v * v + c.coulomb_friction * np.tanh(v / c.coulomb_speed) * v
    )
    volumes = np.array([c.volumes(xi) for xi in x])
    mid = 0.5 * (volumes[1:] + volumes[:-1])
    compression = float(
        np.sum(
            0.5 * (p1[1:] + p1[:-1]) * mid[:, 0] * np.diff(p1)
            + 0.5 * (p2[1:] + p2[:-1]) * mid[:, 1] * np.diff(p2)
        )
        / c.bulk_modulus
    )
    work = 0.5 * M * (v[-1] ** 2 - v[0] ** 2) + _integral(t, LOAD * v)
    losses = throttling + leakage + friction + compression
    imbalance = (energy_in - losses - work) / energy_in
    print(
        f"in {energy_in:.3f} J, work {work:.3f}, throttling {throttling:.3f}, "
        f"leak {leakage:.4f}, friction {friction:.3f}, compression {compression:.4f}, "
        f"imbalance {imbalance:.2e}"
    )
    assert abs(imbalance) < 1e-4
