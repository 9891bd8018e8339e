"""The servo-actuator's laws, defined once as compiled scalar kernels (SI units): the
orifice root and pressure floor, the PI controller, the spool's transfer function, the
chambers' pressure rates, the piston force with its end stops. The element
(mechlib.elements.hydraulics.actuator) calls them from Python for every fidelity; the
compiled state Newton of the `valve` fidelity (mechlib.elements.hydraulics.valve_states)
calls the same kernels.

Regularised root sr(dp) = dp / (dp^2 + dp_tr^2)^(1/4): sign(dp) sqrt(|dp|) for
|dp| >> dp_tr, linear (laminar) below, with a finite derivative at dp = 0 where the plain
root's is infinite (a Newton iteration on the pressures would stall there).

The parameters travel as one float array (`pack`; slots below), so that a kernel takes the
actuator's data in one argument.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = [
    "N_PARAMS",
    "chamber_rates",
    "chamber_volumes",
    "floored",
    "orifice_flows",
    "pack",
    "piston_force",
    "regularised_root",
    "saturated_current",
    "spool_acceleration",
    "stop_force",
]

# slots of the packed parameters (`pack`)
A1, A2, LO, HI, DEAD1, DEAD2, BULK, LEAK = 0, 1, 2, 3, 4, 5, 6, 7
VISCOUS, COULOMB, COULOMB_SPEED, STOP_K, STOP_C = 8, 9, 10, 11, 12
SUPPLY, RETURN, VAPOUR, FLOOR_WIDTH = 13, 14, 15, 16
GAIN, TRANSITION, OMEGA, DAMPING, RATED_CURRENT = 17, 18, 19, 20, 21
KP, KI, CURRENT_LIMIT = 22, 23, 24
N_PARAMS = 25
_MIN_VOLUME = 0.1  # of the dead volume: an end stop overrun never empties a chamber


def pack(cylinder, supply, valve, controller) -> np.ndarray:
    """The actuator's parameters (N_PARAMS,) in the slots above, from its Cylinder, Supply,
    ServoValve and Controller (mechlib.elements.hydraulics.parameters)."""
    c, s, v, k = cylinder, supply, valve, controller
    return np.array(
        [
            c.area_1, c.area_2, c.stroke[0], c.stroke[1], c.dead_volume_1, c.dead_volume_2,
            c.bulk_modulus, c.leakage, c.viscous_friction, c.coulomb_friction,
            c.coulomb_speed, c.stop_stiffness, c.stop_damping,
            s.pressure, s.return_pressure, s.vapour_pressure, s.floor_width,
            v.flow_gain, v.transition_pressure, 2.0 * math.pi * v.frequency, v.damping,
            v.rated_current, k.kp, k.ki, k.current_limit,
        ],
        dtype=float,
    )  # fmt: skip


@njit(**KERNEL)
def regularised_root(dp, transition):
    """sr(dp) (Pa^0.5) with the laminar transition `transition` (Pa)."""
    return dp / (dp * dp + transition * transition) ** 0.25


@njit(**KERNEL)
def floored(p, floor, width):
    """p (Pa) floored smoothly at `floor`: floor + width * softplus((p - floor)/width)."""
    s = (p - floor) / width
    return floor + width * (s + math.log1p(math.exp(-s)) if s > 0.0 else math.log1p(math.exp(s)))


@njit(**KERNEL)
def orifice_flows(opening, p1, p2, ps, pr, gain, transition):
    """(q1, q2, q_supply, q_return (m^3/s), throttling (W)) of a critically centred spool
    at normalised `opening` between supply ps, return pr and chambers p1, p2 (Pa); K =
    `gain`. opening >= 0: supply -> 1 and 2 -> return, q1 = K x sr(p_s - p1), q2 = K x
    sr(p2 - p_r); opening < 0: 1 -> return and supply -> 2, q1 = K x sr(p1 - p_r),
    q2 = K x sr(p_s - p2)."""
    if opening >= 0.0:
        inlet, outlet = ps - p1, p2 - pr
    else:
        inlet, outlet = p1 - pr, ps - p2
    root_in = regularised_root(inlet, transition)
    root_out = regularised_root(outlet, transition)
    q_in, q_out = gain * opening * root_in, gain * opening * root_out
    throttling = abs(gain * opening) * (root_in * inlet + root_out * outlet)
    if opening >= 0.0:
        return q_in, q_out, q_in, q_out, throttling
    return q_in, q_out, -q_out, -q_in, throttling


@njit(**KERNEL)
def saturated_current(kp, ki, limit, error, integral):
    """(current i (A), d(integral)/dt (m)): i = sat(kp e + ki I, +-limit); anti-windup by
    conditional integration: I stands still while the demand is beyond the limit and the
    error would drive it further (Astrom & Hagglund, PID controllers, 1995, sec. 3.5)."""
    demand = kp * error + ki * integral
    current = min(max(demand, -limit), limit)
    winding = current != demand and error * demand > 0.0
    return current, 0.0 if winding or ki == 0.0 else error


@njit(**KERNEL)
def spool_acceleration(omega, damping, ratio, x, xd):
    """x'' (1/s^2) of a spool opening x (normalised) as a second-order transfer function
    of the current ratio i / i_R: x'' + 2 zeta w x' + w^2 x = w^2 i / i_R (w in rad/s)."""
    return omega * omega * (ratio - x) - 2.0 * damping * omega * xd


@njit(**KERNEL)
def chamber_volumes(x, lo, hi, area_1, area_2, dead_1, dead_2):
    """Chamber volumes (m^3) at stroke x (m) of a cylinder with stroke limits lo, hi (m),
    areas (m^2) and dead volumes (m^3), each at least a tenth of its dead volume (an end
    stop overrun never empties a chamber)."""
    v1 = dead_1 + area_1 * (x - lo)
    v2 = dead_2 + area_2 * (hi - x)
    return max(v1, _MIN_VOLUME * dead_1), max(v2, _MIN_VOLUME * dead_2)


@njit(**KERNEL)
def chamber_rates(p, x, xd, p1, p2, q1, q2):
    """(p1', p2') (Pa/s): p1' = beta/V1 (q1 - A1 x' - q_L), p2' = beta/V2 (-q2 + A2 x' +
    q_L), q_L the leakage C_ip (p1 - p2) across the piston (seed 004 eqs. 6.8-6.12)."""
    v1, v2 = chamber_volumes(x, p[LO], p[HI], p[A1], p[A2], p[DEAD1], p[DEAD2])
    leak = p[LEAK] * (p1 - p2)
    return (
        p[BULK] / v1 * (q1 - p[A1] * xd - leak),
        p[BULK] / v2 * (-q2 + p[A2] * xd + leak),
    )


@njit(**KERNEL)
def stop_force(p, x, xd):
    """End stops (N, extending positive): one-sided spring-damper beyond the stroke
    limits, pushing back only (no pull from the damper on the way out)."""
    if x < p[LO]:
        return max(p[STOP_K] * (p[LO] - x) - p[STOP_C] * xd, 0.0)
    if x > p[HI]:
        return min(-p[STOP_K] * (x - p[HI]) - p[STOP_C] * xd, 0.0)
    return 0.0


@njit(**KERNEL)
def piston_force(p, x, xd, p1, p2):
    """p1 A1 - p2 A2 - gamma x' - F_c tanh(x'/v_c) + end stops (N, seed 004 eq. 6.13)."""
    friction = p[VISCOUS] * xd + p[COULOMB] * math.tanh(xd / p[COULOMB_SPEED])
    return p1 * p[A1] - p2 * p[A2] - friction + stop_force(p, x, xd)
