"""The `valve` servo-actuator's states and loads in compiled kernels: the rates of its five
states, their trapezoidal advance over a step (the Newton of mechlib.elements.states, in one
call), the stroke line between its points and its wrench on the bodies (SI units).

States z = [controller integral (m s), spool opening x_v (1), its rate (1/s), p1, p2 (Pa)];
parameters `p`: mechlib.elements.hydraulics.laws.pack. The laws are those of
mechlib.elements.hydraulics.laws, which the element's Python evaluation calls too.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.differences import fd_step
from mechlib.core.jit import KERNEL, njit
from mechlib.elements.hydraulics import laws as lw
from mechlib.elements.states import NEWTON_ITERATIONS, residual_size
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
    states z0 with rates f0, solved in place in `z` (its start values in) by modified
    Newton with the rule of mechlib.elements.states.ElementStates.advance: the matrix
    I - h/2 df/dz (forward differences, the same difference step) factored at the first
    iterate and again only where the residual shrank less than 4x since the last
    iterate; the same convergence test. Returns the iterations taken."""
    n = z.shape[0]
    rates, shifted, res = np.empty(n), np.empty(n), np.empty(n)
    matrix, pivots = np.empty((n, n)), np.empty(n, dtype=np.int64)
    prev, have, fresh = np.inf, False, False
    for it in range(NEWTON_ITERATIONS):
        valve_rates(p, demand, x, xd, z, rates)
        for i in range(n):
            res[i] = z[i] - z0[i] - 0.5 * h * (f0[i] + rates[i])
        size = residual_size(res, z)
        if size <= 1.0:
            return it
        if not have or (size > _CONTRACTION * prev and not fresh):
            _newton_matrix(p, demand, x, xd, z, rates, h, shifted, matrix)
            _factor(matrix, pivots)
            have, fresh = True, True
        else:
            fresh = False
        _solve(matrix, pivots, res)
        for i in range(n):
            z[i] -= res[i]
        prev = size
    return NEWTON_ITERATIONS


_CONTRACTION = 0.25  # a kept matrix while the residual shrinks at least 4x an iteration


@njit(**KERNEL)
def _newton_matrix(p, demand, x, xd, z, rates, h, shifted, matrix):
    """matrix = I - h/2 df/dz at z (rates: f there), df/dz by forward differences of
    step FD_STEP max(1, |z_j|) (mechlib.core.differences.fd_step)."""
    n = z.shape[0]
    for j in range(n):
        dz = fd_step(z[j])
        keep = z[j]
        z[j] = keep + dz
        valve_rates(p, demand, x, xd, z, shifted)
        z[j] = keep
        for i in range(n):
            matrix[i, j] = -0.5 * h * (shifted[i] - rates[i]) / dz
        matrix[j, j] += 1.0


@njit(**KERNEL)
def _factor(a, pivots):
    """LU factors of the small square a in place, partial pivoting (row i swapped with
    pivots[i]); a zero pivot is left to give non-finite steps (never converged)."""
    n = a.shape[0]
    for k in range(n):
        best, row = abs(a[k, k]), k
        for i in range(k + 1, n):
            if abs(a[i, k]) > best:
                best, row = abs(a[i, k]), i
        pivots[k] = row
        if row != k:
            for j in range(n):
                a[k, j], a[row, j] = a[row, j], a[k, j]
        for i in range(k + 1, n):
            a[i, k] /= a[k, k]
            for j in range(k + 1, n):
                a[i, j] -= a[i, k] * a[k, j]


@njit(**KERNEL)
def _solve(lu, pivots, b):
    """b := A^-1 b in place with A's factors from `_factor`."""
    n = b.shape[0]
    for k in range(n):
        r = pivots[k]
        if r != k:
            b[k], b[r] = b[r], b[k]
    for i in range(n):
        for j in range(i):
            b[i] -= lu[i, j] * b[j]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            b[i] -= lu[i, j] * b[j]
        b[i] /= lu[i, i]


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
    f0, f1, f2 = force * line[2], force * line[3], force * line[4]
    kr.point_force3(x, b1, s1, f0, f1, f2, F, N)
    kr.point_force3(x, b2, s2, -f0, -f1, -f2, F, N)
    return force
