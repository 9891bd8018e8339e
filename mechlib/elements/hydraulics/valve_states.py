"""The `valve` servo-actuator's states and loads in compiled kernels: the rates of its five
states, their trapezoidal advance over a step (the Newton of mechlib.elements.states, in one
call), the stroke line between its points and its wrench on the bodies (SI units).

States z = [controller integral (m s), spool opening x_v (1), its rate (1/s), p1, p2 (Pa)];
parameters `p`: mechlib.elements.hydraulics.laws.pack. The laws are those of
mechlib.elements.hydraulics.laws, which the element's Python evaluation calls too.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.hydraulics import laws as lw
from mechlib.elements.states import FD_STEP, NEWTON_ITERATIONS, residual_size
from mechlib.kinematics import kernels as kr

__all__ = ["advance_valve", "chamber_wrench", "stroke_line", "valve_rates"]

N_VALVE = 5  # states of the valve fidelity


@njit(**KERNEL)
def valve_rates(p, demand, x, xd, z, out):
    """dz/dt (5,) into `out` at stroke x (m), rate xd (m/s), stroke demand `demand` (m):
    PI controller on e = demand - x, spool transfer function, orifice flows and chamber
    pressure rates of the floored pressures."""
    current, integral_rate = lw.saturated_current(
        p[lw.KP], p[lw.KI], p[lw.CURRENT_LIMIT], demand - x, z[0]
    )
    ratio = current / p[lw.RATED_CURRENT]
    pf1 = lw.floored(z[3], p[lw.VAPOUR], p[lw.FLOOR_WIDTH])
    pf2 = lw.floored(z[4], p[lw.VAPOUR], p[lw.FLOOR_WIDTH])
    q1, q2, _, _, _ = lw.orifice_flows(
        z[1], pf1, pf2, p[lw.SUPPLY], p[lw.RETURN], p[lw.GAIN], p[lw.TRANSITION]
    )
    r1, r2 = lw.chamber_rates(p, x, xd, pf1, pf2, q1, q2)
    out[0] = integral_rate
    out[1] = z[2]
    out[2] = lw.spool_acceleration(p[lw.OMEGA], p[lw.DAMPING], ratio, z[1], z[2])
    out[3] = r1
    out[4] = r2


@njit(**KERNEL)
def advance_valve(p, demand, x, xd, z0, f0, h, z):
    """The trapezoidal rule z = z0 + h/2 (f0 + f(z)) over a step h (s) from the accepted
    states z0 with rates f0, solved in place in `z` (its start values in) by Newton with
    the forward-differenced Jacobian at each iterate (mechlib.elements.states: the same
    difference step and convergence rule). Returns the iterations taken."""
    n = z.shape[0]
    rates, shifted, res = np.empty(n), np.empty(n), np.empty(n)
    matrix = np.empty((n, n))
    for it in range(NEWTON_ITERATIONS):
        valve_rates(p, demand, x, xd, z, rates)
        for i in range(n):
            res[i] = z[i] - z0[i] - 0.5 * h * (f0[i] + rates[i])
        if residual_size(res, z) <= 1.0:
            return it
        for j in range(n):
            dz = FD_STEP * max(1.0, abs(z[j]))
            keep = z[j]
            z[j] = keep + dz
            valve_rates(p, demand, x, xd, z, shifted)
            z[j] = keep
            for i in range(n):
                matrix[i, j] = -0.5 * h * (shifted[i] - rates[i]) / dz
            matrix[j, j] += 1.0
        step = np.linalg.solve(matrix, res)
        for i in range(n):
            z[i] -= step[i]
    return NEWTON_ITERATIONS


@njit(**KERNEL)
def stroke_line(x, xd, b1, s1, b2, s2, design_length, out):
    """out (5,) = [stroke (m) from the design length, its rate (m/s), unit vector (3) from
    point 2 to point 1] of the body-fixed points s1 of b1 and s2 of b2 (state arrays x,
    xd: mechlib.kinematics)."""
    length, rate = kr.point_pair(x, xd, b1, s1, b2, s2, out[2:5])
    out[0], out[1] = length - design_length, rate


@njit(**KERNEL)
def chamber_wrench(x, xd, b1, s1, b2, s2, design_length, p, p1, p2, F, N):
    """Add the piston force of chamber pressures p1, p2 (Pa, floored here: lw.floored)
    with friction and end stops (lw.piston_force), extending positive, to F and N (nb+1,
    3) at both points along their line (+ at point 1, - at point 2); returns it (N)."""
    line = np.empty(5)
    stroke_line(x, xd, b1, s1, b2, s2, design_length, line)
    pf1 = lw.floored(p1, p[lw.VAPOUR], p[lw.FLOOR_WIDTH])
    pf2 = lw.floored(p2, p[lw.VAPOUR], p[lw.FLOOR_WIDTH])
    force = lw.piston_force(p, line[0], line[1], pf1, pf2)
    push = force * line[2:5]
    kr.point_force(x, b1, s1, push, F, N)
    kr.point_force(x, b2, s2, -push, F, N)
    return force
