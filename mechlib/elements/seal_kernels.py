"""Compiled parts of the distributed seal (mechlib.elements.seal): the stations' geometry,
their friction and the wrench on both bodies, for the state arrays `x`, `xd` (nb+1, 7) of
mechlib.kinematics.kernels (rows [r, p], ground last). Units: m, m/s, N.

The seal's force is evaluated in every column of a differenced tangent that moves one of
its two bodies; as a dozen small NumPy calls it cost about 0.3 ms, most of the door's
dynamic runs.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics.kernels import point_position, point_velocity, rotation_matrix

__all__ = ["seal_apply", "seal_friction", "seal_stations", "seal_wrench"]


@njit(**KERNEL)
def seal_stations(x, b1, b2, s1, s2, n_local, gap, p1, p2, n, pen):
    """Stations P_i of body 1 (body-fixed s1 (N, 3)) and their twins S_i of body 2 (s2) into
    p1, p2 (N, 3); the normal n (3,) of body 2 (n_local in its axes); penetrations
    x_i = -(P_i - S_i) . n - gap into pen (N,)."""
    rot = rotation_matrix(x[b2, 3:])
    for j in range(3):
        n[j] = rot[j, 0] * n_local[0] + rot[j, 1] * n_local[1] + rot[j, 2] * n_local[2]
    for i in range(s1.shape[0]):
        a = point_position(x, b1, s1[i])
        b = point_position(x, b2, s2[i])
        p1[i, :] = a
        p2[i, :] = b
        pen[i] = -((a[0] - b[0]) * n[0] + (a[1] - b[1]) * n[1] + (a[2] - b[2]) * n[2]) - gap


@njit(**KERNEL)
def seal_friction(x, xd, b1, b2, s1, p1, p2, n, normal, mu, anchor, rest, threshold, out):
    """Friction forces on body 1 (N, 3) into out: -mu F_i g(|w|/threshold) w/|w| with w the
    tangential slip of P_i on body 2 (at rest: its displacement since `anchor`, else its
    velocity relative to body 2's material point under it) and g the regularised Coulomb
    law of mechlib.elements.regularize."""
    rot = rotation_matrix(x[b2, 3:])
    w = np.empty(3)
    local = np.empty(3)
    for i in range(s1.shape[0]):
        if rest:
            for c in range(3):
                w[c] = p1[i, c] - p2[i, c] - anchor[i, c]
        else:
            v1 = point_velocity(x, xd, b1, s1[i])
            for c in range(3):
                local[c] = (
                    rot[0, c] * (p1[i, 0] - x[b2, 0])
                    + rot[1, c] * (p1[i, 1] - x[b2, 1])
                    + rot[2, c] * (p1[i, 2] - x[b2, 2])
                )
            v2 = point_velocity(x, xd, b2, local)
            for c in range(3):
                w[c] = v1[c] - v2[c]
        along = w[0] * n[0] + w[1] * n[1] + w[2] * n[2]
        for c in range(3):
            w[c] -= along * n[c]
        size = np.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
        s = size / threshold if threshold > 0.0 else np.inf  # no band: plain Coulomb
        if s < 1.0:
            factor = 0.5 * (3.0 - s * s) / threshold
        elif size > 0.0:
            factor = 1.0 / size
        else:
            factor = 0.0
        for c in range(3):
            out[i, c] = -mu * normal[i] * w[c] * factor


@njit(**KERNEL)
def seal_wrench(x, b1, b2, p1, n, normal, friction, F, N):
    """Add the stations' forces normal_i n + friction_i (on body 1 at P_i; the reverse on
    body 2) to F and their moments about each body's centre of mass to N."""
    for i in range(p1.shape[0]):
        f0 = normal[i] * n[0] + friction[i, 0]
        f1 = normal[i] * n[1] + friction[i, 1]
        f2 = normal[i] * n[2] + friction[i, 2]
        for body, sign in ((b1, 1.0), (b2, -1.0)):
            a0, a1, a2 = p1[i, 0] - x[body, 0], p1[i, 1] - x[body, 1], p1[i, 2] - x[body, 2]
            F[body, 0] += sign * f0
            F[body, 1] += sign * f1
            F[body, 2] += sign * f2
            N[body, 0] += sign * (a1 * f2 - a2 * f1)
            N[body, 1] += sign * (a2 * f0 - a0 * f2)
            N[body, 2] += sign * (a0 * f1 - a1 * f0)


@njit(**KERNEL)
def seal_apply(
    x, xd, b1, b2, s1, s2, n_local, gap, share, stiffness, exponent, mu, anchor, rest,
    threshold, F, N,
):  # fmt: skip
    """A seal of the power law w = stiffness x^exponent (N/m) in one call: its stations,
    normal forces share (m) x w(x_i), friction (mu > 0) and the wrench added to F and N
    (the three kernels above, as Seal.apply calls them)."""
    count = s1.shape[0]
    p1, p2 = np.empty((count, 3)), np.empty((count, 3))
    n, pen = np.empty(3), np.empty(count)
    seal_stations(x, b1, b2, s1, s2, n_local, gap, p1, p2, n, pen)
    normal = np.empty(count)
    for i in range(count):
        normal[i] = share * (stiffness * max(pen[i], 0.0) ** exponent)
    friction = np.zeros((count, 3))
    if mu != 0.0:
        start = anchor if rest else p1  # the static slip's start (unused moving)
        seal_friction(x, xd, b1, b2, s1, p1, p2, n, normal, mu, start, rest, threshold, friction)
    seal_wrench(x, b1, b2, p1, n, normal, friction, F, N)
