"""The `lag` and `jet_pipe` fidelities of the servo-actuator, and its orifice laws.

References: the lag's closed form s = x_c (1 - exp(-K_v t)); the jet-pipe servovalve's
static balance (seed 004 eqs. 6.2-6.3 at rest, flow forces after Merritt) solved here with
scipy's fsolve, independently of the element; the orifice identities by algebra.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

import mechlib as ml
from mechlib.elements.hydraulics import (
    Cylinder,
    JetPipe,
    ServoValve,
    Supply,
    TorqueMotor,
    floored,
    spool_flows,
)
from mechlib.elements.hydraulics import regularised_root as sr
from tests.mechlib.hydraulic_rig import REQUESTS, rig


def test_lag_follows_the_first_order_closed_form() -> None:
    """Step of 1 mm: the servo stroke within 1e-4 of the step of x_c (1 - exp(-K_v t))
    (measured 6.4e-6, 1 ms outputs); the rod, tied to the servo stroke by the oil columns
    (k_h, w_h), within the bound K_v x_c / w_h of the transient a sudden speed demand K_v x_c
    excites (5.9e-5 m, measured 4.2e-5 m), and at the demand by 0.2 s."""
    sol = ml.solve(
        rig(lambda t: 1e-3, fidelity="lag"), ml.Dynamic(end=0.2, step=1e-3), requests=REQUESTS
    )
    gain = rig().forces["act"].loop_gain()
    expected = 1e-3 * (1.0 - np.exp(-gain * sol.time))
    assert np.abs(sol.channels["act.servo_stroke"] - expected).max() < 1e-7
    w_h = math.sqrt(Cylinder().hydraulic_stiffness(0.0) / 100.0)
    assert np.abs(sol.channels["x.value"] - expected).max() < gain * 1e-3 / w_h
    assert abs(sol.channels["x.value"][-1] - 1e-3) < 5e-6


def _jet_static_opening(current: float, valve_drop: float, motor=None) -> float:
    """Spool opening (m) of the jet-pipe valve at rest: F_tm = k_f x_j + k_W (x_j + x_s),
    F_tm = k_t i or, with `motor` (S, g, N, M0, r), the reluctance force of the push-pull
    pair r S (B1^2 - B2^2) / (2 mu0), B1,2 = mu0 (M0 +- N i) / (2 (g -+ r x_j)),
    A_s P tanh(K_jr x_j / P) = k_W (x_j + x_s) + 0.428 w x_s dp_v (Merritt's steady flow
    force, 2 C_d C_v cos 69 deg w with C_v = 0.98), w from the rated flow."""
    j, v = JetPipe(), ServoValve()
    k_t = j.wire_stiffness * j.rated_opening / v.rated_current
    w = v.rated_flow / math.sqrt(0.5 * v.rated_pressure_drop)
    w /= j.discharge * j.rated_opening * math.sqrt(2.0 / j.density)
    flow = 2 * j.discharge * 0.98 * math.cos(math.radians(69.0)) * w * valve_drop

    def motor_force(xj):
        if motor is None:
            return k_t * current
        area, gap, turns, mmf, ratio = motor
        mu0 = 4e-7 * math.pi
        b1 = mu0 * (mmf + turns * current) / (2 * (gap - ratio * xj))
        b2 = mu0 * (mmf - turns * current) / (2 * (gap + ratio * xj))
        return ratio * area * (b1 * b1 - b2 * b2) / (2 * mu0)

    def balance(x):
        xj, xs = x
        wire = j.wire_stiffness * (xj + xs)
        return [
            motor_force(xj) - j.hinge_stiffness * xj - wire,
            j.spool_area
            * j.receiver_pressure
            * math.tanh(j.receiver_gain * xj / j.receiver_pressure)
            - wire
            - flow * xs,
        ]

    return float(fsolve(balance, [0.0, j.rated_opening], xtol=1e-13)[1])


def test_jet_pipe_full_open_speed_follows_its_static_spool_balance() -> None:
    """Saturated current, no load, no friction: the spool settles at the opening of its
    static balance (within 3e-4, measured 9e-5; 0.983 of the rated opening) and the rod
    moves at that fraction of the no-load speed Q_R sqrt((p_s - p_r)/dp_R)/A (within 5e-4,
    measured -4e-5)."""
    cylinder = Cylinder(viscous_friction=0.0, leakage=0.0)
    sol = ml.solve(
        rig(lambda t: 0.045, fidelity="jet_pipe", cylinder=cylinder),
        ml.Dynamic(end=0.15, step=2e-3),
        requests=REQUESTS,
    )
    t, x = sol.time, sol.channels["x.value"]
    window = t >= 0.05
    supply, valve = Supply(), ServoValve()
    drop = supply.pressure - supply.return_pressure
    opening = _jet_static_opening(valve.rated_current, drop)
    spool = sol.channels["act.spool"][window]
    assert np.abs(spool / opening - 1.0).max() < 3e-4
    no_load = valve.rated_flow * math.sqrt(drop / valve.rated_pressure_drop) / cylinder.area_1
    speed = np.polyfit(t[window], x[window], 1)[0]
    assert abs(speed / (no_load * opening / JetPipe().rated_opening) - 1.0) < 5e-4


MOTOR = (4.0e-4, 5.0e-4, 20000.0, 250.0, 0.2)  # S m^2, g m, N, M0 A, r: the library's


def test_reluctance_torque_motor_static_balance() -> None:
    """Jet pipe with the torque motor's reluctance law (seed 004 eq. 6.1), saturated current:
    the spool settles at the opening of the static balance with that force law (fsolve
    here), within 3e-4 as the linear law's (measured 7e-5); that opening differs from the
    linear law's by more than 0.5 % (1.0 % measured: the magnetic spring of the displaced
    armature). About the centre the push-pull force is k_i i exactly (B1^2 - B2^2 =
    mu0^2 M0 N i / g^2)."""
    motor = TorqueMotor(*MOTOR)
    assert motor.force(3e-3, 0.0) == pytest.approx(motor.current_gain * 3e-3, rel=1e-12)
    slope = (motor.force(0.0, 1e-8) - motor.force(0.0, -1e-8)) / 2e-8
    assert slope == pytest.approx(motor.magnetic_stiffness, rel=1e-6)
    cylinder = Cylinder(viscous_friction=0.0, leakage=0.0)
    sol = ml.solve(
        rig(
            lambda t: 0.045,
            fidelity="jet_pipe",
            cylinder=cylinder,
            jet_pipe=JetPipe(torque_motor=motor),
        ),
        ml.Dynamic(end=0.1, step=2e-3),
        requests=REQUESTS,
    )
    valve, supply = ServoValve(), Supply()
    drop = supply.pressure - supply.return_pressure
    opening = _jet_static_opening(valve.rated_current, drop, MOTOR)
    spool = sol.channels["act.spool"][sol.time >= 0.05]
    assert np.abs(spool / opening - 1.0).max() < 3e-4
    assert abs(opening / _jet_static_opening(valve.rated_current, drop) - 1.0) > 0.005


def test_regularised_root_and_pressure_floor() -> None:
    """sr(dp) -> sign(dp) sqrt|dp| beyond the transition (1e-4 at 100 dp_tr), finite slope
    dp_tr^-1/2 at 0; the floor never goes below the vapour pressure and is p itself well
    above it."""
    tr = 1e5
    assert sr(1e7, tr) == pytest.approx(math.sqrt(1e7), rel=1e-4)
    assert sr(-1e7, tr) == pytest.approx(-math.sqrt(1e7), rel=1e-4)
    assert (sr(1.0, tr) - sr(-1.0, tr)) / 2.0 == pytest.approx(tr**-0.5, rel=1e-9)
    assert floored(-1e7, 2e3, 1e4) >= 2e3
    assert floored(5e6, 2e3, 1e4) == pytest.approx(5e6, rel=1e-12)


@pytest.mark.parametrize("opening", [0.7, -0.4])
def test_spool_flows_conserve_power(opening: float) -> None:
    """p_s q_s - p_r q_r = p1 q1 - p2 q2 + throttling (exact) in both directions, and the
    flow enters the chamber the spool opens to the supply."""
    supply = Supply()
    flows = spool_flows(opening, 1.2e7, 0.9e7, supply, ServoValve().flow_gain, 1e5)
    balance = supply.pressure * flows.q_supply - supply.return_pressure * flows.q_return
    assert balance == pytest.approx(1.2e7 * flows.q1 - 0.9e7 * flows.q2 + flows.throttling)
    assert flows.throttling > 0.0
    assert np.sign(flows.q1) == np.sign(opening) == np.sign(flows.q2)


def test_end_stop_holds_the_rod_against_an_overreaching_demand() -> None:
    """lag, demand 60 mm beyond the 50 mm limit: the rod rests where the oil columns and
    the stop balance, k (x_c - x) = k_s (x - x_hi), x = (k x_c + k_s x_hi)/(k + k_s) (within
    1e-7 m after 0.5 s; measured 7e-9 m)."""
    cylinder = Cylinder()
    sol = ml.solve(
        rig(lambda t: 0.06, fidelity="lag"), ml.Dynamic(end=0.5, step=1e-2), requests=REQUESTS
    )
    k, k_s = cylinder.hydraulic_stiffness(0.0), cylinder.stop_stiffness
    expected = (k * 0.06 + k_s * cylinder.stroke[1]) / (k + k_s)
    assert abs(sol.channels["x.value"][-1] - expected) < 1e-7
