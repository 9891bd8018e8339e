"""Compiled (numba) contact kernels: the gap of the primitive geometries, the contact force
from a gap, the wrench on both bodies and its tangent (stiffness K = -dQ/dq, damping
C = -dQ/dqd) for the integrator's iteration matrix.

Layout as in mechlib.kinematics.kernels: `x`, `xd` (nb+1, 7) rows [r, p] per body, ground last.
Geometry parameters `g` (11,): [s1 (3), s2 (3), direction (3), radius, extra] with s1, s2
body-fixed vectors from the centres of mass (m), direction the body-2-fixed plane normal or
hole axis, extra the clearance (m) or, for a sphere on a plane, the pad radius (m, < 0:
unbounded). A gap `out` (13,) holds [penetration, normal (3), point (3), velocity (3),
eccentricity (3)] (see mechlib.elements.contact.geometry for their meaning).

The tangent is a forward difference of the compiled generalized force over the two bodies'
coordinates, with increments sized for contact (1e-9 of the ball radius on positions, 1e-6
of the friction's static speed on rates): the integrator's global difference (1e-7 m, and
a rate increment of gamma' times that, mm/s) would step over a Hertz deflection of a
fraction of a micrometre and over the whole Stribeck regularisation.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.contact.curve_kernels import nearest_on_cubic
from mechlib.elements.contact.friction import COULOMB, STRIBECK, coulomb, stribeck
from mechlib.elements.contact.laws import (
    HERTZ,
    IMPACT,
    MIN_APPROACH_SPEED,
    hertz_force,
    impact_force,
    restitution_force,
)
from mechlib.kinematics.kernels import _brot, _gt_times, _rot, point_position

__all__ = [
    "CIRCLE_PROFILE",
    "CYLINDER_IN_CYLINDER",
    "GAP_SIZE",
    "PROFILE_HEAD",
    "PROFILE_ITERATIONS",
    "SPHERE_IN_SPHERE",
    "SPHERE_PLANE",
    "contact_force",
    "contact_tangent",
    "contact_wrench",
    "gap",
    "static_contact_force",
    "static_contact_wrench",
]

SPHERE_PLANE, SPHERE_IN_SPHERE, CYLINDER_IN_CYLINDER, CIRCLE_PROFILE = 0, 1, 2, 3
GAP_SIZE = 13
PROFILE_HEAD = 19  # parameters of a profile before its spline arrays (`_profile_gap`)
PROFILE_ITERATIONS = 6  # Newton refinements of the nearest point (quadratic convergence)
_TINY = 1.0e-15  # m, below this the eccentricity has no direction (the force is zero there)
_FD = 1.0e-9


@njit(**KERNEL)
def _body_vector(x, b, point, out):
    """out = A(p)^T (point - r): the global `point` (m) in body b's axes, from its cm (A(p)^T
    = A of the conjugate)."""
    d = np.empty(3)
    conj = np.empty(4)
    conj[0] = x[b, 3]
    for c in range(3):
        d[c] = point[c] - x[b, c]
        conj[1 + c] = -x[b, 4 + c]
    _rot(conj, d, out)


@njit(**KERNEL)
def _material_velocity(x, xd, b, point, out):
    """Velocity (m/s, global) of the material point of body b now at `point` (global, m):
    rd + B(p, s) pd with s = A(p)^T (point - r)."""
    s = np.empty(3)
    _body_vector(x, b, point, s)
    _brot(x[b, 3:], xd[b, 3:], s, out)
    for c in range(3):
        out[c] += xd[b, c]


@njit(**KERNEL)
def gap(kind, x, xd, b1, b2, g, out):
    """The gap (layout in the module docstring) of geometry `kind` between b1 and b2."""
    c1 = point_position(x, b1, g[0:3])
    c2 = point_position(x, b2, g[3:6])
    e = np.empty(3)
    point = np.empty(3)
    for c in range(3):
        e[c] = c1[c] - c2[c]
    if kind == CIRCLE_PROFILE:
        _profile_gap(x, b2, g, e, c2, point, out)
    elif kind == SPHERE_PLANE:
        _plane_gap(x, b2, g, e, c1, point, out)
    else:
        _round_gap(kind, x, b2, g, e, c1, c2, point, out)
    v1 = np.empty(3)
    v2 = np.empty(3)
    _material_velocity(x, xd, b1, point, v1)
    _material_velocity(x, xd, b2, point, v2)
    for c in range(3):
        out[4 + c] = point[c]
        out[7 + c] = v1[c] - v2[c]


@njit(**KERNEL)
def _plane_gap(x, b2, g, e, c1, point, out):
    """A sphere (centre c1, e = c1 less the plane origin) against a plane of body 2, or a pad
    of radius g[10] >= 0 on it: penetration, normal and eccentricity (zero) into `out`, the
    contact point into `point`."""
    radius, extra = g[9], g[10]
    u = np.empty(3)
    _rot(x[b2, 3:], g[6:9], u)  # the plane normal
    d = e[0] * u[0] + e[1] * u[1] + e[2] * u[2]  # centre height over the plane
    for c in range(3):
        point[c] = c1[c] - 0.5 * (radius + d) * u[c]
    if extra >= 0.0:
        across = 0.0
        for c in range(3):
            across += (e[c] - d * u[c]) ** 2
        if across > extra * extra:
            d = max(d, radius)  # off the pad: no penetration
    out[0] = radius - d
    for c in range(3):
        out[1 + c] = u[c]
        out[10 + c] = 0.0


@njit(**KERNEL)
def _round_gap(kind, x, b2, g, e, c1, c2, point, out):
    """A sphere in a sphere, or a cylinder in a cylinder (e less its part along body 2's
    axis g[6:9]), with clearance g[10]: penetration, normal and eccentricity into `out`, the
    contact point into `point`."""
    radius, extra = g[9], g[10]
    u = np.empty(3)
    if kind == CYLINDER_IN_CYLINDER:
        axis = np.empty(3)
        _rot(x[b2, 3:], g[6:9], axis)
        along = e[0] * axis[0] + e[1] * axis[1] + e[2] * axis[2]
        for c in range(3):
            e[c] -= along * axis[c]
    length = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    if length < _TINY:
        u[0], u[1], u[2] = 1.0, 0.0, 0.0
    else:
        for c in range(3):
            u[c] = e[c] / length
    half = radius + 0.5 * extra
    for c in range(3):
        if kind == CYLINDER_IN_CYLINDER:
            point[c] = c1[c] - 0.5 * e[c] + half * u[c]
        else:  # ball surface c1 + R u, socket wall c2 + (R + clearance) u: the midpoint
            point[c] = 0.5 * (c1[c] + c2[c]) + half * u[c]
    out[0] = length - extra
    for c in range(3):
        out[1 + c] = -u[c]
        out[10 + c] = e[c]


@njit(**KERNEL)
def _profile_gap(x, b2, g, e, origin, point, out):
    """A roller circle against a profile curve of body 2 (mechlib.elements.contact.profile): from
    e, the roller centre less the profile origin (global), put the penetration, normal
    and eccentricity (zero) into `out` and the contact point into `point`. Parameters g:
    [s1 (3), s0 (3), plane normal m (3), radius, side (+-1), in-plane basis (3 x 2, by
    rows), samples n, breakpoints k, the sample parameters (n), the samples (n x 2), the
    breakpoints (k), the coefficients (4 x (k - 1) x 2)], body-2 axes."""
    radius, side = g[9], g[10]
    n, k = int(g[17]), int(g[18])
    at = PROFILE_HEAD
    grid = g[at : at + n]
    samples = g[at + n : at + 3 * n].reshape((n, 2))
    breaks = g[at + 3 * n : at + 3 * n + k]
    coefs = g[at + 3 * n + k : at + 3 * n + k + 8 * (k - 1)].reshape((4, k - 1, 2))
    conj = np.empty(4)
    conj[0] = x[b2, 3]
    for c in range(3):
        conj[1 + c] = -x[b2, 4 + c]
    local = np.empty(3)
    _rot(conj, e, local)  # the roller centre in body-2 axes (from the origin, not the cm)
    w = np.empty(2)
    for j in range(2):
        w[j] = local[0] * g[11 + j] + local[1] * g[13 + j] + local[2] * g[15 + j]
    curve = np.empty((3, 2))
    nearest_on_cubic(w, grid, samples, breaks, coefs, PROFILE_ITERATIONS, curve)
    tangent, foot, normal = np.empty(3), np.empty(3), np.empty(3)
    for c in range(3):
        tangent[c] = g[11 + 2 * c] * curve[1, 0] + g[12 + 2 * c] * curve[1, 1]
        foot[c] = g[11 + 2 * c] * curve[0, 0] + g[12 + 2 * c] * curve[0, 1]
    normal[0] = g[7] * tangent[2] - g[8] * tangent[1]
    normal[1] = g[8] * tangent[0] - g[6] * tangent[2]
    normal[2] = g[6] * tangent[1] - g[7] * tangent[0]
    length = math.sqrt(normal[0] ** 2 + normal[1] ** 2 + normal[2] ** 2)
    d = 0.0
    for c in range(3):
        normal[c] *= side / length
        d += (local[c] - foot[c]) * normal[c]
    n_global, foot_global = np.empty(3), np.empty(3)
    _rot(x[b2, 3:], normal, n_global)
    _rot(x[b2, 3:], foot, foot_global)
    out[0] = radius - d
    for c in range(3):
        out[1 + c] = n_global[c]
        point[c] = origin[c] + foot_global[c] + 0.5 * (d - radius) * n_global[c]
        out[10 + c] = 0.0


@njit(**KERNEL)
def _normal_force(law, lp, x, xd, approach):
    if law == IMPACT:
        return impact_force(lp[0], lp[1], lp[2], lp[3], x, xd, lp[4])
    if law == HERTZ:
        return hertz_force(lp[0], lp[1], lp[2], x, xd, approach)
    return restitution_force(lp[0], lp[1], lp[2], x, xd, approach)


@njit(**KERNEL)
def _coefficient(friction, fp, v):
    if friction == STRIBECK:
        return stribeck(fp[0], fp[1], fp[2], fp[3], fp[4], v)
    if friction == COULOMB:
        return coulomb(fp[0], fp[1], v)
    return 0.0


@njit(**KERNEL)
def contact_force(law, lp, friction, fp, radius, gp, approach, out):
    """out (6,) = [normal force (N, >= 0), friction force magnitude (N), force on body 1
    (3, N, global), sliding speed (m/s)] from the gap `gp`: F_N n - mu(|v_t|) F_N v_t/|v_t|.
    Beyond the radius (no state a step accepts comes near) the force stops growing, so that
    a wild Newton iterate does not make the iteration matrix singular."""
    x = min(gp[0], radius)
    rate = -(gp[7] * gp[1] + gp[8] * gp[2] + gp[9] * gp[3])  # > 0 approaching
    normal = _normal_force(law, lp, x, rate, approach)
    vt = np.empty(3)
    for c in range(3):
        vt[c] = gp[7 + c] + rate * gp[1 + c]
        out[2 + c] = normal * gp[1 + c]
    speed = math.sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2])
    slip = 0.0
    if friction != 0 and normal > 0.0 and speed > 0.0:
        slip = _coefficient(friction, fp, speed) * normal
        for c in range(3):
            out[2 + c] -= slip / speed * vt[c]
    out[0] = normal
    out[1] = abs(slip)
    out[5] = speed


@njit(**KERNEL)
def _wrench(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, force, arm1, arm2):
    """Force on body 1 (N, global) and the arms (m) from each body's cm to the point."""
    gp = np.empty(GAP_SIZE)
    cf = np.empty(6)
    gap(kind, x, xd, b1, b2, g, gp)
    contact_force(law, lp, friction, fp, g[9], gp, approach, cf)
    for c in range(3):
        force[c] = cf[2 + c]
        arm1[c] = gp[4 + c] - x[b1, c]
        arm2[c] = gp[4 + c] - x[b2, c]


@njit(**KERNEL)
def _cross_add(a, f, sign, out):
    out[0] += sign * (a[1] * f[2] - a[2] * f[1])
    out[1] += sign * (a[2] * f[0] - a[0] * f[2])
    out[2] += sign * (a[0] * f[1] - a[1] * f[0])


@njit(**KERNEL)
def contact_wrench(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, F, N):
    """Add the contact force to F (nb+1, 3) and its moments about the cms to N: +force on
    body 1 at the contact point, -force on body 2 at the same point."""
    f, a1, a2 = np.empty(3), np.empty(3), np.empty(3)
    _wrench(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, f, a1, a2)
    _add_wrench(b1, b2, f, a1, a2, F, N)


@njit(**KERNEL)
def _add_wrench(b1, b2, f, a1, a2, F, N):
    """+f on body 1 and -f on body 2 (N, global) with arms a1, a2 (m) from their cms."""
    for c in range(3):
        F[b1, c] += f[c]
        F[b2, c] -= f[c]
    _cross_add(a1, f, 1.0, N[b1])
    _cross_add(a2, f, -1.0, N[b2])


@njit(**KERNEL)
def _static_force(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, mu, anchor,
                  threshold, gp, out):  # fmt: skip
    """The gap `gp` and forces `out` (6,) as contact_force gives them, of a contact with
    friction in a static evaluation (no velocities): the friction mu F_N opposes the
    tangential slip of body 1 on body 2 at the contact point since the accepted state
    whose poses `anchor` (2, 12) holds (per body: r (3), then its rotation matrix by rows;
    rows of NaN: none yet, no slip), regularised over `threshold` (m) as
    mechlib.elements.regularize.coulomb_vector."""
    gap(kind, x, xd, b1, b2, g, gp)
    contact_force(law, lp, friction, fp, g[9], gp, approach, out)
    normal = out[0]
    if normal <= 0.0:
        return
    slip = np.zeros(3)
    if not math.isnan(anchor[0, 0]):
        local = np.empty(3)
        for k in range(2):
            b, sign = (b1, -1.0) if k == 0 else (b2, 1.0)
            _body_vector(x, b, gp[4:7], local)  # the contact point in body b's axes
            for c in range(3):  # where it was at the anchor: r0 + R0 local
                then = anchor[k, c]
                for j in range(3):
                    then += anchor[k, 3 + 3 * c + j] * local[j]
                slip[c] += sign * then
        along = slip[0] * gp[1] + slip[1] * gp[2] + slip[2] * gp[3]
        for c in range(3):
            slip[c] -= along * gp[1 + c]
    size = math.sqrt(slip[0] ** 2 + slip[1] ** 2 + slip[2] ** 2)
    s = size / threshold
    if s < 1.0:
        scale = 0.5 * (3.0 - s * s) / threshold
    else:
        scale = 1.0 / size if size > 0.0 else 0.0
    magnitude = 0.0
    for c in range(3):
        tangential = mu * normal * (slip[c] * scale)
        out[2 + c] = normal * gp[1 + c] - tangential
        magnitude += tangential * tangential
    out[1] = math.sqrt(magnitude)
    out[5] = 0.0


@njit(**KERNEL)
def static_contact_force(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, mu, anchor,
                         threshold, out):  # fmt: skip
    """out (6,) = [normal force, friction magnitude, force on body 1 (3), sliding speed 0]
    of a contact with friction in a static evaluation (`_static_force`)."""
    gp = np.empty(GAP_SIZE)
    _static_force(
        kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, mu, anchor, threshold, gp, out
    )


@njit(**KERNEL)
def static_contact_wrench(
    kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, mu, anchor, threshold, F, N
):
    """Add the force of a contact with friction in a static evaluation (`_static_force`)
    to F and its moments about the cms to N, as contact_wrench does."""
    gp = np.empty(GAP_SIZE)
    out = np.empty(6)
    _static_force(
        kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, mu, anchor, threshold, gp, out
    )
    f, a1, a2 = out[2:5].copy(), np.empty(3), np.empty(3)
    for c in range(3):
        a1[c] = gp[4 + c] - x[b1, c]
        a2[c] = gp[4 + c] - x[b2, c]
    _add_wrench(b1, b2, f, a1, a2, F, N)


@njit(**KERNEL)
def _generalized(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, out):
    """out (14,): the contact's generalized force on body 1 [F, 2 E(p)^T N] then body 2."""
    f, a1, a2 = np.empty(3), np.empty(3), np.empty(3)
    torque = np.empty(3)
    g4 = np.empty(4)
    _wrench(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, f, a1, a2)
    for k in range(2):
        b, arm, sign = (b1, a1, 1.0) if k == 0 else (b2, a2, -1.0)
        torque[:] = 0.0
        _cross_add(arm, f, sign, torque)
        _gt_times(x[b, 3:], torque, -1.0, g4)
        for c in range(3):
            out[7 * k + c] = sign * f[c]
        for c in range(4):
            out[7 * k + 3 + c] = 2.0 * g4[c]


@njit(**KERNEL)
def contact_tangent(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, nb, K, C):
    """Add -dQ/dq to K and -dQ/dqd to C (nq, nq) for the contact's generalized force Q
    (forward differences, increments in the module docstring); ground (b = nb) has no
    columns."""
    v_ref = (
        fp[2] if friction == STRIBECK else (fp[1] if friction == COULOMB else MIN_APPROACH_SPEED)
    )
    radius = g[9]
    base = np.empty(14)
    moved = np.empty(14)
    _generalized(kind, b1, b2, g, law, lp, friction, fp, approach, x, xd, base)
    xw, xdw = x.copy(), xd.copy()
    bodies = (b1, b2)
    for level in range(2):
        out = K if level == 0 else C
        w = xw if level == 0 else xdw
        for bc in bodies:
            if bc >= nb:
                continue
            for j in range(7):
                old = w[bc, j]
                if level == 0:
                    h = _FD * (abs(old) + (radius if j < 3 else 1.0))
                else:
                    h = _FD * abs(old) + 1e-6 * (v_ref if j < 3 else v_ref / radius)
                w[bc, j] = old + h
                _generalized(kind, b1, b2, g, law, lp, friction, fp, approach, xw, xdw, moved)
                w[bc, j] = old
                col = 7 * bc + j
                for k in range(2):
                    br = bodies[k]
                    if br >= nb:
                        continue
                    for i in range(7):
                        out[7 * br + i, col] -= (moved[7 * k + i] - base[7 * k + i]) / h
