"""Rates of the control and valve stages of the servo-actuator (SI units).

Each stage maps (time t, stroke x, its states) to (their rates, normalised spool opening,
outputs). The chambers and piston are common to the `valve` and `jet_pipe` fidelities
(mechlib.elements.hydraulics.actuator).
"""

from __future__ import annotations

import math

from mechlib.elements.hydraulics.laws import saturated_current, spool_acceleration
from mechlib.elements.hydraulics.parameters import Controller, JetPipe, ServoValve

__all__ = ["controller_current", "jet_pipe_rates", "motor_force", "motor_gain", "valve_rates"]

_COS_JET = math.cos(math.radians(69.0))  # jet angle of a sharp-edged port (Merritt)
_VELOCITY_COEFFICIENT = 0.98


def controller_current(c: Controller, error: float, integral: float) -> tuple[float, float]:
    """(current i (A), d(integral)/dt (m)): i = sat(kp e + ki I, +-limit); anti-windup by
    conditional integration: I stands still while the demand is beyond the limit and the
    error would drive it further (Astrom & Hagglund, PID controllers, 1995, sec. 3.5;
    laws.saturated_current)."""
    return saturated_current(c.kp, c.ki, c.current_limit, error, integral)


def valve_rates(v: ServoValve, current: float, z) -> tuple[list[float], float]:
    """Spool of a servovalve as a second-order transfer function of the current:
    x'' + 2 zeta w x' + w^2 x = w^2 i / i_R, x the opening normalised by its rated value.
    z = [x, x'] -> ([x', x''], x) (laws.spool_acceleration)."""
    x, xd = z[0], z[1]
    w = 2.0 * math.pi * v.frequency
    return [xd, spool_acceleration(w, v.damping, current / v.rated_current, x, xd)], x


def motor_gain(j: JetPipe, v: ServoValve) -> float:
    """Torque-motor force gain (N/A): given, or the one that balances the feedback wire at
    the rated opening with rated current, k_t = k_W x_R / i_R."""
    if j.motor_gain is not None:
        return j.motor_gain
    return j.wire_stiffness * j.rated_opening / v.rated_current


def motor_force(j: JetPipe, v: ServoValve, current: float, jet: float) -> float:
    """Torque-motor force (N) on the jet tip: the reluctance law of `j.torque_motor`, or
    k_t i."""
    if j.torque_motor is not None:
        return j.torque_motor.force(current, jet)
    return motor_gain(j, v) * current


def port_width(j: JetPipe, v: ServoValve) -> float:
    """Port width w (m) that passes the rated flow at the rated opening:
    K = C_d w x_R sqrt(2/rho)."""
    return v.flow_gain / (j.discharge * j.rated_opening * math.sqrt(2.0 / j.density))


def jet_pipe_rates(
    j: JetPipe, v: ServoValve, current: float, z, valve_drop: float
) -> tuple[list[float], float, dict[str, float]]:
    """Torque motor, jet pipe and spool (seed 004 eqs. 6.1-6.3), z = [x_j, x_j', x_s, x_s']:

    m_j x_j'' = F_tm(i, x_j) - k_f x_j - b_f x_j' - k_W (x_j + x_s)                (6.2)
    m_s x_s'' = A_s dP_r(x_j) - k_W (x_j + x_s) - b_s x_s' + F_fl                   (6.3)
    dP_r = P_max tanh(K_jr x_j / P_max) (receiver), F_fl = -2 C_d C_v cos 69 deg w x_s dp_v
    (steady flow forces of both open lands, dp_v the drop across them), F_tm the torque
    motor's force (`motor_force`: k_t i, or the reluctance law of eq. 6.1).
    Returns (rates, opening x_s / x_R, outputs)."""
    xj, vj, xs, vs = z
    wire = j.wire_stiffness * (xj + xs)
    jet_acc = motor_force(j, v, current, xj) - j.hinge_stiffness * xj - j.hinge_damping * vj - wire
    receiver = j.receiver_pressure * math.tanh(j.receiver_gain * xj / j.receiver_pressure)
    flow_force = (
        -2.0 * j.discharge * _VELOCITY_COEFFICIENT * _COS_JET * port_width(j, v) * xs * valve_drop
    )
    spool_acc = j.spool_area * receiver - wire - j.spool_damping * vs + flow_force
    rates = [vj, jet_acc / j.jet_mass, vs, spool_acc / j.spool_mass]
    outputs = {"jet": xj, "receiver_pressure": receiver, "flow_force": flow_force}
    return rates, xs / j.rated_opening, outputs
