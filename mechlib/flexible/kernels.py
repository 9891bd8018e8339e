"""Compiled terms of a modal body in the floating frame (SI): its mass matrix and forces in
velocities w = [xd, omega, zeta_d] and in coordinates q = [x, p, zeta], the geometric
stiffening of the spin and of the node loads, and the node loads' maps from the weld
multipliers. The formulas are those of mechlib.flexible.modal_body (its docstring derives
them); this module is their one definition, which ModalBody and Attached call.

Invariants as mechlib.flexible.invariants (I1 kg, I2 (3,), I3 (3, n), I4 (3, n),
I5 (n, 3, n), I6 (n, n), I7 (3, 3)), I8 and I9 symmetrised: I8s = I8 + I8^T (n, 3, 3) and
I9s = I9 + I9^T(jk) laid out (n, 9 n) (`symmetrised`), so that the terms quadratic in the
modes cost one matrix-vector product. The kernels write into
arrays given to them: a step allocates nothing per modal body but its scratch.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics.kernels import rotation_matrix

__all__ = [
    "body_forces",
    "body_mass",
    "coordinate_forces",
    "coordinate_mass",
    "first_moment",
    "load_maps",
    "quadratic",
    "symmetrised",
    "theta",
]

_PAIRS = np.array([[1, 2], [2, 0], [0, 1]])  # (f, g) axes of the weld orientation rows


@njit(**KERNEL)
def _skew_times(v, x, out):
    """out = v x x (3,)."""
    out[0] = v[1] * x[2] - v[2] * x[1]
    out[1] = v[2] * x[0] - v[0] * x[2]
    out[2] = v[0] * x[1] - v[1] * x[0]


def symmetrised(I8: np.ndarray, I9: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(I8s (n, 3, 3), I9s (n, 9 n)) of the invariants I8 (n, 3, 3) and I9 (n, n, 3, 3):
    I8s_j = I8_j + I8_j^T, I9s[k, (j, a, b)] = I9_kj[a, b] + I9_jk[a, b]."""
    n = I8.shape[0]
    i8s = I8 + I8.transpose(0, 2, 1)
    i9s = (I9 + I9.transpose(1, 0, 2, 3)).reshape(n, 9 * n)
    return np.ascontiguousarray(i8s, dtype=float), np.ascontiguousarray(i9s, dtype=float)


@njit(**KERNEL)
def _contracted(zeta, I9s):
    """S (n, 3, 3): S_j = sum_k zeta_k (I9_jk + I9_kj), from the symmetrised I9s (n, 9 n)
    (rows k, columns (j, a, b)); a loop, not numpy's product (module docstring)."""
    n = zeta.shape[0]
    S = np.zeros((n, 3, 3))
    for k in range(n):
        zk = zeta[k]
        for j in range(n):
            for a in range(3):
                for b in range(3):
                    S[j, a, b] += zk * I9s[k, 9 * j + 3 * a + b]
    return S


@njit(**KERNEL)
def _theta_of(zeta, I7, I8s, S, out):
    """Theta = I7 - sum_j zeta_j (I8s_j + S_j / 2) into `out` (S: `_contracted`)."""
    for a in range(3):
        for b in range(3):
            acc = 0.0
            for j in range(zeta.shape[0]):
                acc += zeta[j] * (I8s[j, a, b] + 0.5 * S[j, a, b])
            out[a, b] = I7[a, b] - acc


@njit(**KERNEL)
def theta(zeta, I7, I8s, I9s, out):
    """Inertia tensor (3, 3) about the frame origin, body axes (kg m^2): I7 - sum_j zeta_j
    (I8_j + I8_j^T) - sum_jk zeta_j zeta_k I9_jk, into `out`; I8s = I8 + I8^T (n, 3, 3),
    I9s (n, 9 n) as `_contracted`."""
    _theta_of(zeta, I7, I8s, _contracted(zeta, I9s), out)


@njit(**KERNEL)
def first_moment(zeta, I2, I3, out):
    """c = I2 + I3 zeta (3,) (kg m)."""
    for a in range(3):
        acc = I2[a]
        for j in range(zeta.shape[0]):
            acc += I3[a, j] * zeta[j]
        out[a] = acc


@njit(**KERNEL)
def _coupling(zeta, I4, I5, out):
    """Iwz = I4 + sum_j zeta_j I5_j (3, n)."""
    n = zeta.shape[0]
    for a in range(3):
        for k in range(n):
            acc = 0.0
            for j in range(n):
                acc += zeta[j] * I5[j, a, k]
            out[a, k] = I4[a, k] + acc


@njit(**KERNEL)
def body_mass(A, zeta, I1, I2, I3, I4, I5, I6, I7, I8s, I9s, out):
    """M (6 + n, 6 + n) in velocities w, into `out`:
    [[m I, -A c~, A I3], [., Theta, Iwz], [., ., I6]]."""
    n = zeta.shape[0]
    c = np.empty(3)
    first_moment(zeta, I2, I3, c)
    out[:, :] = 0.0
    for a in range(3):
        out[a, a] = I1
    for a in range(3):  # -(A c~), c~ the cross-product matrix of c; then A I3
        out[a, 3] = -(A[a, 1] * c[2] - A[a, 2] * c[1])
        out[a, 4] = -(A[a, 2] * c[0] - A[a, 0] * c[2])
        out[a, 5] = -(A[a, 0] * c[1] - A[a, 1] * c[0])
        for j in range(n):
            out[a, 6 + j] = A[a, 0] * I3[0, j] + A[a, 1] * I3[1, j] + A[a, 2] * I3[2, j]
    theta(zeta, I7, I8s, I9s, out[3:6, 3:6])
    _coupling(zeta, I4, I5, out[3:6, 6:])
    out[6:, 6:] = I6
    for i in range(3, 6 + n):
        for j in range(i if i < 6 else 6):
            out[i, j] = out[j, i]


@njit(**KERNEL)
def _stiffening(zeta, omega, spin, nodal, loads, out):
    """out -= K_G zeta: the spin cases (6, n, n) per omega_a omega_b (xx, yy, zz, xy, yz,
    zx) and the node cases (k, 6, n, n) per unit load `loads` (k, 6). Empty case arrays
    (length 0) leave that part out."""
    products = np.array(
        [
            omega[0] * omega[0],
            omega[1] * omega[1],
            omega[2] * omega[2],
            omega[0] * omega[1],
            omega[1] * omega[2],
            omega[2] * omega[0],
        ]
    )
    n = zeta.shape[0]
    for i in range(n):
        total = 0.0
        for c in range(spin.shape[0]):
            acc = 0.0
            for j in range(n):
                acc += spin[c, i, j] * zeta[j]
            total += products[c] * acc
        for node in range(loads.shape[0]):
            for c in range(6):
                acc = 0.0
                for j in range(n):
                    acc += nodal[node, c, i, j] * zeta[j]
                total += loads[node, c] * acc
        out[i] -= total


@njit(**KERNEL)
def body_forces(
    A, omega, zeta, zeta_d, gravity, inertia, I1, I2, I3, I4, I5, I7, I8s, I9s,
    stiffness, viscous, spin, nodal, loads, out,
):  # fmt: skip
    """Forces f (6 + n) in velocities w, into `out`: gravity `gravity` (3,) m/s^2 (global),
    modal stiffness and damping, with `inertia` the quadratic velocity vector, minus the
    geometric stiffening K_G zeta (`_stiffening`) of body angular velocity `omega` (rad/s)."""
    c, g_body, tmp = np.empty(3), np.empty(3), np.empty(3)
    first_moment(zeta, I2, I3, c)
    for a in range(3):
        g_body[a] = A[0, a] * gravity[0] + A[1, a] * gravity[1] + A[2, a] * gravity[2]
        out[a] = I1 * gravity[a]
    _skew_times(c, g_body, tmp)
    out[3:6] = tmp
    for j in range(zeta.shape[0]):
        weight = I3[0, j] * g_body[0] + I3[1, j] * g_body[1] + I3[2, j] * g_body[2]
        out[6 + j] = weight - stiffness[j] * zeta[j] - viscous[j] * zeta_d[j]
    if inertia:
        quadratic(A, omega, zeta, zeta_d, I2, I3, I4, I5, I7, I8s, I9s, out)
    if spin.shape[0] or loads.shape[0]:
        _stiffening(zeta, omega, spin, nodal, loads, out[6:])


@njit(**KERNEL)
def quadratic(A, omega, zeta, zeta_d, I2, I3, I4, I5, I7, I8s, I9s, out):
    """out += the quadratic velocity vector f_v (6 + n) at body angular velocity `omega`
    (rad/s) (mechlib.flexible.modal_body). Written as loops over the invariants, no
    matrix products (a Newton iteration calls it: each product of numpy's cost about as
    much as the whole loop at these sizes)."""
    n = zeta.shape[0]
    c = np.empty(3)
    first_moment(zeta, I2, I3, c)
    S = _contracted(zeta, I9s)
    th = np.empty((3, 3))
    _theta_of(zeta, I7, I8s, S, th)
    # dTheta/dzeta_j = -(I8s_j + S_j); th_d = sum_j zeta_d_j dTheta_j; rate = sum_j zeta_d_j I5_j
    th_d = np.zeros((3, 3))
    iwz_zd, rate_zd, i3_zd = np.zeros(3), np.zeros(3), np.zeros(3)
    rate_t_omega = np.zeros(n)
    for j in range(n):
        zdj = zeta_d[j]
        for a in range(3):
            for b in range(3):
                th_d[a, b] -= zdj * (I8s[j, a, b] + S[j, a, b])
    for a in range(3):
        for k in range(n):
            iwz = I4[a, k]
            rate = 0.0
            for j in range(n):
                iwz += zeta[j] * I5[j, a, k]
                rate += zeta_d[j] * I5[j, a, k]
            iwz_zd[a] += iwz * zeta_d[k]
            rate_zd[a] += rate * zeta_d[k]
            rate_t_omega[k] += rate * omega[a]
            i3_zd[a] += I3[a, k] * zeta_d[k]
    wc, v, w2 = np.empty(3), np.empty(3), np.empty(3)
    _skew_times(omega, c, wc)
    _skew_times(omega, wc, w2)  # w~ w~ c
    _skew_times(omega, i3_zd, v)
    for a in range(3):
        w2[a] += 2.0 * v[a]
    for a in range(3):
        out[a] -= A[a, 0] * w2[0] + A[a, 1] * w2[1] + A[a, 2] * w2[2]
    h = np.empty(3)
    for a in range(3):
        h[a] = th[a, 0] * omega[0] + th[a, 1] * omega[1] + th[a, 2] * omega[2] + iwz_zd[a]
    _skew_times(omega, h, v)
    for a in range(3):
        thd_w = th_d[a, 0] * omega[0] + th_d[a, 1] * omega[1] + th_d[a, 2] * omega[2]
        out[3 + a] -= v[a] + thd_w + rate_zd[a]
    for j in range(n):
        acc = 0.0
        for a in range(3):
            for b in range(3):
                acc -= 0.5 * (I8s[j, a, b] + S[j, a, b]) * omega[a] * omega[b]
            for k in range(n):
                acc += I5[j, a, k] * omega[a] * zeta_d[k]
        out[6 + j] += acc - rate_t_omega[j]


@njit(**KERNEL)
def _rate_map(p):
    """G(p) (3, 4): body-axes angular velocity omega = 2 G(p) pd."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    return np.array([[-e1, e0, e3, -e2], [-e2, -e3, e0, e1], [-e3, e2, -e1, e0]])


@njit(**KERNEL)
def coordinate_mass(p, zeta, I1, I2, I3, I4, I5, I6, I7, I8s, I9s, scratch, out):
    """M_q (7 + n, 7 + n) = T^T M_w T + (4 tr Theta / 3) p p^T (the term fixing |p|), with
    T = diag(I, 2 G(p), I), into `out`; `scratch` (6 + n, 6 + n) takes M_w."""
    n = zeta.shape[0]
    body_mass(rotation_matrix(p), zeta, I1, I2, I3, I4, I5, I6, I7, I8s, I9s, scratch)
    t = np.zeros((6 + n, 7 + n))
    for a in range(3):
        t[a, a] = 1.0
    t[3:6, 3:7] = 2.0 * _rate_map(p)
    for j in range(n):
        t[6 + j, 7 + j] = 1.0
    out[:, :] = t.T @ (scratch @ t)
    scale = 4.0 * (scratch[3, 3] + scratch[4, 4] + scratch[5, 5]) / 3.0
    for a in range(4):
        for b in range(4):
            out[3 + a, 3 + b] += scale * p[a] * p[b]


@njit(**KERNEL)
def coordinate_forces(
    p, pd, zeta, zeta_d, gravity, inertia, I1, I2, I3, I4, I5, I7, I8s, I9s,
    stiffness, viscous, spin, nodal, loads, scratch, out,
):  # fmt: skip
    """Q_q (7 + n) = T^T f_w (`body_forces` at omega = 2 G(p) pd), into `out`; `scratch`
    (6 + n,) takes f_w."""
    g = _rate_map(p)
    omega = np.empty(3)
    for a in range(3):
        omega[a] = 2.0 * (g[a, 0] * pd[0] + g[a, 1] * pd[1] + g[a, 2] * pd[2] + g[a, 3] * pd[3])
    body_forces(
        rotation_matrix(p), omega, zeta, zeta_d, gravity, inertia, I1, I2, I3, I4, I5, I7,
        I8s, I9s, stiffness, viscous, spin, nodal, loads, scratch,
    )  # fmt: skip
    out[:3] = scratch[:3]
    for c in range(4):
        out[3 + c] = 2.0 * (g[0, c] * scratch[3] + g[1, c] * scratch[4] + g[2, c] * scratch[5])
    out[7:] = scratch[6:]


@njit(**KERNEL)
def load_maps(p, p_nodes, phi_star, zeta, out):
    """d(node load)/d(weld multipliers) (k, 6, 6) of k kept nodes (orientations `p_nodes`
    (k, 4), rotations per modal coordinate `phi_star` (k, 3, n)) of the body at `p`, into
    `out`: the position rows push the body with +lam (A^T lam, body axes), an orientation
    row (A_n f).(A v) = 0, v = g + theta x g, turns it with lam (A^T A_n f) x v."""
    A = rotation_matrix(p)
    v, axis = np.empty(3), np.empty(3)
    for i in range(p_nodes.shape[0]):
        out[i, :, :] = 0.0
        out[i, :3, :3] = A.T
        turn = A.T @ rotation_matrix(p_nodes[i])
        th = phi_star[i] @ zeta
        for c in range(3):
            f, g = _PAIRS[c, 0], _PAIRS[c, 1]
            axis[:] = 0.0
            axis[g] = 1.0
            _skew_times(th, axis, v)
            v[g] += 1.0
            _skew_times(turn[:, f].copy(), v, axis)
            out[i, 3:, 3 + c] = axis


@njit(**KERNEL)
def weld_coupling(nodal, zeta, maps, out):
    """out (n, k, 6) += dQ_zeta/d(weld multipliers) of a stiffened body's geometric
    stiffening, Q_zeta = -K_G(node loads) zeta with the node loads linear in its weld
    multipliers through `maps` (`load_maps`'): out[i, node, j] -= sum_c (K_c zeta)_i
    maps[node, c, j], K_c = nodal[node, c] the stiffening per unit load c at the node
    (mechlib.flexible.stiffening, (k, 6, n, n)); zeta (n,)."""
    n = zeta.shape[0]
    for node in range(nodal.shape[0]):
        for c in range(6):
            for i in range(n):
                g = 0.0
                for j in range(n):
                    g += nodal[node, c, i, j] * zeta[j]
                for col in range(6):
                    out[i, node, col] -= g * maps[node, c, col]
