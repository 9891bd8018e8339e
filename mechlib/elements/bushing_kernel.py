"""Compiled (numba) bushing state: the force and torque of a 6-DOF linear bushing from the
two bodies' coordinates and rates (layout of mechlib.kinematics.kernels: `x`, `xd` (nb+1, 7) rows
[r, p] per body, ground last). The formulas are those of mechlib.elements.bushing; this
kernel only removes the Python overhead of the many small array operations (the bushing
was most of the cost of a rod-end run, evaluated at every Newton iterate).
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics.kernels import _brot

__all__ = ["STATE_SIZE", "bushing_state"]

STATE_SIZE = 21
"""bushing_state's `out`: force (3), torque (3) on body 1 (global, N, N*m), d (3, m) and
theta (3, rad) in body 2's axes, body 1's point (3, global, m), d' (3, m/s) and omega (3,
rad/s) in body 2's axes."""


@njit(**KERNEL)
def _matrix(p, out):
    """Rotation matrix A(p) (3, 3) of the unit quaternion p."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    c = e0 * e0 - (e1 * e1 + e2 * e2 + e3 * e3)
    e = (e1, e2, e3)
    for i in range(3):
        for j in range(3):
            out[i, j] = 2.0 * e[i] * e[j] + (c if i == j else 0.0)
    out[0, 1] -= 2.0 * e0 * e3
    out[1, 0] += 2.0 * e0 * e3
    out[0, 2] += 2.0 * e0 * e2
    out[2, 0] -= 2.0 * e0 * e2
    out[1, 2] -= 2.0 * e0 * e1
    out[2, 1] += 2.0 * e0 * e1


@njit(**KERNEL)
def _omega(p, pd, out):
    """Global angular velocity 2 E(p) pd (rad/s)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    w0, f1, f2, f3 = pd[0], pd[1], pd[2], pd[3]
    out[0] = 2.0 * (-e1 * w0 + e0 * f1 + e2 * f3 - e3 * f2)
    out[1] = 2.0 * (-e2 * w0 + e0 * f2 + e3 * f1 - e1 * f3)
    out[2] = 2.0 * (-e3 * w0 + e0 * f3 + e1 * f2 - e2 * f1)


@njit(**KERNEL)
def _transposed_times(a, v, out):
    for i in range(3):
        out[i] = a[0, i] * v[0] + a[1, i] * v[1] + a[2, i] * v[2]


@njit(**KERNEL)
def _rotation_vector(r, out):
    """Axis times angle (rad) of the rotation matrix r (as bushing.rotation_vector)."""
    s0 = 0.5 * (r[2, 1] - r[1, 2])
    s1 = 0.5 * (r[0, 2] - r[2, 0])
    s2 = 0.5 * (r[1, 0] - r[0, 1])
    sin = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
    cos = 0.5 * (r[0, 0] + r[1, 1] + r[2, 2] - 1.0)
    scale = 1.0 if sin < 1e-12 else math.atan2(sin, cos) / sin
    out[0], out[1], out[2] = scale * s0, scale * s1, scale * s2


@njit(**KERNEL)
def bushing_state(x, xd, b1, s1, b2, s2, k, c, kr, cr, out):
    """out (STATE_SIZE,) of the bushing between b1 (point s1, body axes) and b2 (s2)."""
    a1, a2 = np.empty((3, 3)), np.empty((3, 3))
    _matrix(x[b1, 3:], a1)
    _matrix(x[b2, 3:], a2)
    p1, p2, v1, v2, w1, w2 = (
        np.empty(3),
        np.empty(3),
        np.empty(3),
        np.empty(3),
        np.empty(3),
        np.empty(3),
    )
    _brot(x[b1, 3:], xd[b1, 3:], s1, v1)
    _brot(x[b2, 3:], xd[b2, 3:], s2, v2)
    _omega(x[b1, 3:], xd[b1, 3:], w1)
    _omega(x[b2, 3:], xd[b2, 3:], w2)
    for i in range(3):
        p1[i] = x[b1, i] + a1[i, 0] * s1[0] + a1[i, 1] * s1[1] + a1[i, 2] * s1[2]
        p2[i] = x[b2, i] + a2[i, 0] * s2[0] + a2[i, 1] * s2[1] + a2[i, 2] * s2[2]
        v1[i] += xd[b1, i]
        v2[i] += xd[b2, i]
    gap, rel = p1 - p2, np.empty(3)
    rel[0] = v1[0] - v2[0] - (w2[1] * gap[2] - w2[2] * gap[1])
    rel[1] = v1[1] - v2[1] - (w2[2] * gap[0] - w2[0] * gap[2])
    rel[2] = v1[2] - v2[2] - (w2[0] * gap[1] - w2[1] * gap[0])
    d, d_rate, theta, omega = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    _transposed_times(a2, gap, d)
    _transposed_times(a2, rel, d_rate)
    _transposed_times(a2, w1 - w2, omega)
    _rotation_vector(a2.T @ a1, theta)
    force = -(k * d + c * d_rate)
    torque = -(kr * theta + cr * omega)
    for i in range(3):
        out[i] = a2[i, 0] * force[0] + a2[i, 1] * force[1] + a2[i, 2] * force[2]
        out[3 + i] = a2[i, 0] * torque[0] + a2[i, 1] * torque[1] + a2[i, 2] * torque[2]
        out[6 + i] = d[i]
        out[9 + i] = theta[i]
        out[12 + i] = p1[i]
        out[15 + i] = d_rate[i]
        out[18 + i] = omega[i]
