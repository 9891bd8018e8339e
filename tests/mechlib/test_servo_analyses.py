"""The servo-actuator in the analyses other than dynamic (issue 12): quasi-static and
kinematic runs of the single-DOF rig against closed forms.

References:
- lag, stroke: s = x_c (1 - exp(-K_v t)) (first-order lag, exact).
- lag at rest (quasi-static): the rod, without inertia, sits where the oil column carries
  the load: k_h (s - x) = L, so x = s - L / k_h; the column's damping carries nothing.
- lag, prescribed rod x = v t (kinematic): F = k_h (s - v t) + c (K_v (x_c - s) - v).
- valve, closed (demand = prescribed rod position: no error, no current, spool centred),
  no leakage: p1' = -beta A1 x' / V1(x), p2' = beta A2 x' / V2(x), so
  p1 = p1(0) - beta ln(V1(x) / V1(0)) and p2 = p2(0) - beta ln(V2(x) / V2(0)).
"""

from __future__ import annotations

import math

import numpy as np

import mechlib as ml
from mechlib.elements.hydraulics import Cylinder
from tests.mechlib._models import Ramp
from tests.mechlib.hydraulic_rig import REQUESTS, rig

X_C = 1e-3  # m: the stroke demand
V = 2e-3  # m/s: the prescribed rod speed


def _lag_closed_form(t: np.ndarray, gain: float) -> np.ndarray:
    return X_C * (1.0 - np.exp(-gain * t))


def test_lag_quasi_static_follows_the_first_order_closed_form() -> None:
    """Stroke within 1e-7 m of the closed form (measured 2.5e-8 m, trapezoidal states at
    1 ms); the rod where the oil column carries the 2 kN load, within 1e-12 m."""
    load = 2000.0
    sol = ml.solve(
        rig(lambda t: X_C, fidelity="lag", load=load),
        ml.QuasiStatic(end=0.2, step=1e-3),
        requests=REQUESTS,
    )
    assert sol.ok, sol.message
    actuator = rig().forces["act"]
    s = sol.channels["act.servo_stroke"]
    assert np.abs(s - _lag_closed_form(sol.time, actuator.loop_gain())).max() < 1e-7
    k_h = Cylinder().hydraulic_stiffness(0.0)
    assert np.abs(sol.channels["x.value"] - (s - load / k_h)).max() < 1e-12
    assert np.abs(sol.channels["act.force"] - load).max() < 1e-4


def _prescribed(**actuator) -> ml.Mechanism:
    m = rig(fidelity=actuator.pop("fidelity"), **actuator)
    m.add_motion("push", joint="slide", function=Ramp(0.0, V))
    return m


def test_lag_kinematic_force_follows_the_closed_form() -> None:
    """Rod driven at 2 mm/s: the stroke within 1e-7 m of the closed form (measured
    2.5e-8 m) and the force within 1 N of k_h (s - v t) + c (K_v (x_c - s) - v) with the
    closed-form s (a 17 kN force; measured 0.55 N, the stroke's error times k_h)."""
    sol = ml.solve(
        _prescribed(fidelity="lag", command=lambda t: X_C),
        ml.Kinematic(end=0.2, step=1e-3),
        requests=REQUESTS,
    )
    assert sol.ok, sol.message
    actuator = rig().forces["act"]
    gain, k_h, c = actuator.loop_gain(), Cylinder().hydraulic_stiffness(0.0), actuator.lag_damping
    s = _lag_closed_form(sol.time, gain)
    assert np.abs(sol.channels["act.servo_stroke"] - s).max() < 1e-7
    assert np.abs(sol.channels["x.value"] - V * sol.time).max() < 1e-12
    expected = k_h * (s - V * sol.time) + c * (gain * (X_C - s) - V)
    assert np.abs(sol.channels["act.force"] - expected).max() < 1.0


def test_valve_kinematic_closed_chambers_follow_the_volume_law() -> None:
    """Rod driven at 2 mm/s with the demand on it (closed valve, no leakage): chamber
    pressures within 0.2 Pa of the logarithmic volume law over 0.2 s (a 4.6 MPa change,
    above the vapour floor; measured 0.06 Pa), the force p1 A1 - p2 A2 - gamma v within
    1 mN (measured 0.12 mN)."""
    cylinder = Cylinder(leakage=0.0)
    sol = ml.solve(
        _prescribed(fidelity="valve", command=lambda t: V * t, cylinder=cylinder),
        ml.Kinematic(end=0.2, step=1e-2),
        requests=REQUESTS,
    )
    assert sol.ok, sol.message
    ch = sol.channels
    x = V * sol.time
    v1, v2 = np.array([cylinder.volumes(xi) for xi in x]).T
    beta = cylinder.bulk_modulus
    p1 = ch["act.p1"][0] - beta * np.log(v1 / v1[0])
    p2 = ch["act.p2"][0] - beta * np.log(v2 / v2[0])
    assert abs(p1[-1] - p1[0]) > 1e6  # the law is exercised, not only its start
    assert np.abs(ch["act.p1"] - p1).max() < 0.2
    assert np.abs(ch["act.p2"] - p2).max() < 0.2
    force = p1 * cylinder.area_1 - p2 * cylinder.area_2 - cylinder.viscous_friction * V
    assert np.abs(ch["act.force"] - force).max() < 1e-3
    assert math.isclose(ch["act.current"].max(initial=0.0), 0.0, abs_tol=1e-12)
