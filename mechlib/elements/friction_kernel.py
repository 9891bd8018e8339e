"""Compiled (numba) joint friction of a revolute or cylindrical joint in a moving state
(mechlib.elements.friction: the same formulas, seed 003 eq. 2.2; layout of
mechlib.kinematics.kernels:
`x`, `xd` (nb+1, 7) rows [r, p] per body, ground last). It removes the Python overhead of
the reaction, axis, capacity and regularised direction: the solar array's three hinge
frictions were a third of its deployment run, evaluated at every Newton iterate and every
column of the differenced tangent. States at rest (static, quasi-static) and prismatic and
spherical joints keep the Python path.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.regularize import coulomb_factor
from mechlib.kinematics.kernels import _rotated, angle_rate, body_forces

__all__ = ["FLOATS", "INTS", "VARYING", "rotation_friction_coupling", "rotation_friction_wrench"]

INTS = 5
"""`ints`: the joint's body 1 and body 2 (the torque pair), its angle's bodies (bi, bj),
the body whose force columns carry the joint's reaction."""
FLOATS = 11
"""`floats`: the angle's triad f, g and axis h (3 x 3, body-fixed), mu * pin radius (m),
preload (N*m)."""
VARYING = 4
"""`varying`: the sign of the reaction's rows, the angle's unwrapping reference (rad),
v_threshold (rad/s), the impending slip direction (+1, -1 or 0)."""


@njit(**KERNEL)
def _friction_state(x, xd, jac, lam, rows, ints, floats, varying):
    """(F_r, the reaction force (N, global) on body 1 normal to the axis; the axis (unit,
    global); the regularised fraction of the full friction, signed with the joint's rate)
    at the state (the arguments of rotation_friction_wrench); the vectors as tuples: no
    array made (the loads are evaluated at every Newton iteration)."""
    body = ints[4]
    f0 = f1 = f2 = 0.0
    for r in range(rows.size):
        row = rows[r]
        f0 += jac[row, 7 * body] * lam[row]
        f1 += jac[row, 7 * body + 1] * lam[row]
        f2 += jac[row, 7 * body + 2] * lam[row]
    axis = _rotated(x[ints[3], 3:], floats[6:9])
    f0, f1, f2 = f0 * -varying[0], f1 * -varying[0], f2 * -varying[0]
    along = 0.0
    along += f0 * axis[0]
    along += f1 * axis[1]
    along += f2 * axis[2]
    force = (f0 - along * axis[0], f1 - along * axis[1], f2 - along * axis[2])
    _, rate = angle_rate(x, xd, ints[2], ints[3], floats[0:3], floats[3:6], varying[1])
    return force, axis, coulomb_factor(rate / varying[2] + varying[3], 1.0)


@njit(**KERNEL)
def rotation_friction_wrench(x, xd, jac, lam, rows, ints, floats, varying, N):
    """Add the friction torque pair to N (nb+1, 3): capacity mu r |F_r| + preload (F_r the
    reaction force -sign jac[rows, force columns]^T lam[rows] normal to the axis), times
    the regularised direction of the joint's rate, opposing body 1's rotation against
    body 2 (+ on body 2). Returns the capacity (N*m)."""
    normal, axis, factor = _friction_state(x, xd, jac, lam, rows, ints, floats, varying)
    size = math.sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2])
    capacity = floats[9] * size + floats[10]
    for c in range(3):
        load = -capacity * factor * axis[c]  # on body 1, opposing its slip
        N[ints[0], c] += load
        N[ints[1], c] -= load
    return capacity


@njit(**KERNEL)
def rotation_friction_coupling(x, xd, jac, lam, rows, ints, floats, varying, masses, inertia, out):
    """Add dQ/dlam of the friction to out (nq, m): Q is linear in the capacity mu r |F_r| +
    preload and F_r = P (-sign B^T lam), B the joint's force block, so dQ/dlam = Q(capacity
    1) (x) mu r (-sign B u), u = F_r / |F_r|; nothing where F_r = 0 (its derivative is
    undefined). masses, inertia: the system's (kernels.body_forces)."""
    normal, axis, factor = _friction_state(x, xd, jac, lam, rows, ints, floats, varying)
    size = math.sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2])
    if size == 0.0:
        return
    F, N = np.zeros((x.shape[0], 3)), np.zeros((x.shape[0], 3))
    for c in range(3):
        N[ints[0], c] -= factor * axis[c]  # the pair at capacity 1
        N[ints[1], c] += factor * axis[c]
    unit = np.zeros(out.shape[0])
    body_forces(x, xd, masses, inertia, np.zeros(3), F, N, False, unit)
    body = ints[4]
    for r in range(rows.size):
        row = rows[r]
        along = 0.0
        for c in range(3):
            along += jac[row, 7 * body + c] * (normal[c] / size)
        weight = -varying[0] * floats[9] * along
        for i in range(unit.size):
            out[i, row] += unit[i] * weight
