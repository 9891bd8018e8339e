"""Compiled (numba) loads of a closed cable loop (mechlib.elements.cable_loop: the same
formulas, seed 003 eqs. 2.3-2.6; layout of mechlib.kinematics.kernels: `x`, `xd` (nb+1, 7) rows [r,
p] per body, ground last). This kernel only removes the Python overhead of the loop's many
small array operations: the two cable loops were a quarter of the solar array's deployment
run, evaluated at every Newton iterate and at every column of the differenced tangent.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics.kernels import _rot, angle_state, point_position

__all__ = ["FLOATS", "INTS", "cable_loop_wrench"]

INTS = 7
"""`ints`: pulley 1's body, pulley 2's body, joint 1's angle bodies (bi, bj), joint 2's
(bi, bj), the yoke."""
FLOATS = 32
"""`floats`: the hinge points A and B in their pulleys' bodies (2 x 3, m), joint 1's angle
triad f, g and axis h (3 x 3), joint 2's (3 x 3), the senses of phi1 and phi2 (2), r1, r2
(m), strand stiffness (N/m), pretension (N), g(D0) (m), guided (1.0: the strands guided
along the yoke, 0.0: free between the pulleys)."""


@njit(**KERNEL)
def cable_loop_wrench(x, xd, ints, floats, reference1, reference2, F, N):
    """Add the cable loop's loads to F and N (nb+1, 3); the joint angles unwrapped to the
    turns nearest `reference1`, `reference2` (rad). False, and nothing added, when the hinge
    distance is not above |r1 - r2| (the caller reports it)."""
    b1, b2, yoke = ints[0], ints[1], ints[6]
    a = point_position(x, b1, floats[0:3])
    b = point_position(x, b2, floats[3:6])
    u = np.empty(3)
    for c in range(3):
        u[c] = b[c] - a[c]
    d = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    r1, r2, stiffness, pretension, g0 = floats[26], floats[27], floats[28], floats[29], floats[30]
    dr = r1 - r2
    if not d > abs(dr):
        return False
    state = np.empty(2)
    angle_state(x, xd, ints[2], ints[3], floats[6:9], floats[9:12], reference1, state)
    phi1 = floats[24] * state[0]
    angle_state(x, xd, ints[4], ints[5], floats[15:18], floats[18:21], reference2, state)
    phi2 = floats[25] * state[0]
    guided = floats[31] != 0.0
    length = d if guided else math.sqrt(d * d - dr * dr)
    wrap = r1 * phi1 - r2 * phi2
    common = (d if guided else length + dr * math.asin(dr / d)) - g0
    fa = max(0.0, pretension + stiffness * (wrap + common))
    fb = max(0.0, pretension + stiffness * (-wrap + common))
    carrier, pair = np.zeros(3), np.empty(3)  # what the joint-pair torques put on the yoke
    for j in range(2):
        bi, bj = ints[2 + 2 * j], ints[3 + 2 * j]
        torque = r1 * (fb - fa) if j == 0 else r2 * (fa - fb)  # T1, T2 (eqs. 2.3, 2.4)
        _rot(x[bj, 3:], floats[12 + 9 * j : 15 + 9 * j], pair)
        scale = floats[24 + j] * torque
        for c in range(3):
            pair[c] *= scale
            N[bi, c] += pair[c]
            N[bj, c] -= pair[c]
            carrier[c] += pair[c] if bi == yoke else -pair[c]
    for c in range(3):
        u[c] /= d
    # free strands: the yoke's share moved to the pulleys as a couple of forces at A and B
    # (its part along AB stays on the yoke); guided strands: the yoke keeps it (fig. 2.2.5-4)
    rest = np.zeros(3)
    if not guided:
        along = carrier[0] * u[0] + carrier[1] * u[1] + carrier[2] * u[2]
        for c in range(3):
            rest[c] = carrier[c] - along * u[c]
            N[yoke, c] -= rest[c]
    axial = (fa + fb) * length / d  # eq. 2.5 (guided: L = D)
    on_b = np.empty(3)  # (B - A) x on_b = rest: a couple of forces at A and B
    on_b[0] = (rest[1] * u[2] - rest[2] * u[1]) / d
    on_b[1] = (rest[2] * u[0] - rest[0] * u[2]) / d
    on_b[2] = (rest[0] * u[1] - rest[1] * u[0]) / d
    force = np.empty(3)
    for body, at, sign in ((b1, a, 1.0), (b2, b, -1.0)):
        for c in range(3):
            force[c] = sign * (axial * u[c] - on_b[c])
            F[body, c] += force[c]
        arm0, arm1, arm2 = at[0] - x[body, 0], at[1] - x[body, 1], at[2] - x[body, 2]
        N[body, 0] += arm1 * force[2] - arm2 * force[1]
        N[body, 1] += arm2 * force[0] - arm0 * force[2]
        N[body, 2] += arm0 * force[1] - arm1 * force[0]
    return True
