"""The compiled terms of a modal body (mechlib.flexible.kernels, weld_kernels) against an
independent Python transcription of their formulas (the einsum path they replaced, written
out below as the oracle) and against themselves interpreted, at one random deformed, moving
state (issue 40: physics must not depend on whether a kernel is compiled).

The component is random (invariants I1..I9 without the symmetries of a beam, two kept nodes
with random shapes, spin and nodal geometric stiffness), so that a transposed block, a term
left out or counted twice shows: mass matrix, quadratic velocity, applied and stiffening
forces (in velocities and in coordinates), weld residual, Jacobian, rate and gamma, node
loads. Acceptance 1e-10 of each array's largest entry (measured at most 3e-16: round-off).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from mechlib.core.rotation import cross3, g_matrix, omega_body, skew
from mechlib.flexible import kernels, weld_kernels
from mechlib.flexible.attached import Attached, NodeWelds
from mechlib.flexible.modal_body import ModalBody
from mechlib.flexible.stiffening import ModalGeometric
from mechlib.kinematics.kernels import b_matrix, rotation_matrix
from mechlib.kinematics.kin import Kin

N_MODES, N_NODES = 5, 2
RELATIVE = 1e-10
State = tuple[Attached, NodeWelds, Kin, np.ndarray]
PAIRS = ((1, 2), (2, 0), (0, 1))
AXES = np.eye(3)


def _component(rng: np.random.Generator) -> SimpleNamespace:
    """A modal component with random invariants (with the symmetries of their definitions,
    mechlib.flexible.invariants: I6, I7 symmetric, I9_kj = I9_jk^T), shapes and geometric
    stiffness."""
    n, k = N_MODES, N_NODES
    sym = rng.normal(size=(n, n))
    rotations = rng.normal(scale=0.3, size=(3 * n, 3))  # R_j rows (3, 3) per mode
    i9 = -np.einsum("jab,kac->jkbc", rotations.reshape(n, 3, 3), rotations.reshape(n, 3, 3))
    i7 = rng.normal(scale=0.1, size=(3, 3))
    invariants = SimpleNamespace(
        I1=2.5,
        I2=rng.normal(scale=0.1, size=3),
        I3=rng.normal(size=(3, n)),
        I4=rng.normal(size=(3, n)),
        I5=rng.normal(size=(n, 3, n)),
        I6=sym @ sym.T + n * np.eye(n),
        I7=np.diag([0.4, 0.5, 0.6]) + i7 @ i7.T,
        I8=rng.normal(scale=0.1, size=(n, 3, 3)),
        I9=i9,
    )
    return SimpleNamespace(
        invariants=invariants,
        mass=invariants.I1,
        count=n,
        stiffness=rng.uniform(1e2, 1e4, size=n),
        viscous=rng.uniform(0.1, 1.0, size=n),
        geometric=ModalGeometric(
            spin=rng.normal(size=(6, n, n)), nodal=rng.normal(scale=1e-2, size=(k, 6, n, n))
        ),
        positions=rng.normal(size=(k, 3)),
        phi=rng.normal(scale=0.1, size=(k, 3, n)),
        phi_star=rng.normal(scale=0.1, size=(k, 3, n)),
        node_ids=np.arange(k),
    )


def _state(rng: np.random.Generator) -> State:
    """The modal body (frame row 0, nodes rows 1, 2) deformed and moving: random unit
    quaternions and rates, modes 0.05, mode rates 1 (modal units)."""
    body = ModalBody(_component(rng))  # type: ignore[arg-type]
    nb = 1 + N_NODES
    attached = Attached("flex", body, 0, 0, list(range(1, nb)))
    x, xd = np.zeros((nb + 1, 7)), np.zeros((nb + 1, 7))
    x[:nb] = rng.normal(size=(nb, 7))
    x[:nb, 3:] /= np.linalg.norm(x[:nb, 3:], axis=1)[:, None]
    x[nb, 3] = 1.0  # ground
    xd[:nb] = rng.normal(size=(nb, 7))
    z, zd = rng.normal(scale=0.05, size=N_MODES), rng.normal(size=N_MODES)
    k = Kin(x, xd, 0.3, z=z, zd=zd)
    loads = rng.normal(scale=100.0, size=(N_NODES, 6))
    return attached, NodeWelds([attached], nb), k, loads


def _python(kernel: Any) -> Any:
    """The kernel's Python function (numba's dispatcher and the mark both keep it)."""
    return kernel.py_func


def _close(actual: np.ndarray, reference: np.ndarray) -> None:
    scale = np.abs(reference).max()
    assert scale > 0.0
    assert np.abs(actual - reference).max() <= RELATIVE * scale


# --- the oracle: the formulas of mechlib.flexible.modal_body and attached in einsum form ---


def _theta(inv, zeta):
    out = inv.I7 - np.einsum("j,jab->ab", zeta, inv.I8 + inv.I8.transpose(0, 2, 1))
    return out - np.einsum("j,k,jkab->ab", zeta, zeta, inv.I9)


def _d_theta(inv, zeta):
    i9s = inv.I9 + inv.I9.transpose(1, 0, 2, 3)
    return -(inv.I8 + inv.I8.transpose(0, 2, 1)) - np.einsum("k,jkab->jab", zeta, i9s)


def _mass_w(comp, A, zeta):
    inv, n = comp.invariants, comp.count
    out = np.zeros((6 + n, 6 + n))
    out[:3, :3] = inv.I1 * np.eye(3)
    out[:3, 3:6] = -A @ skew(inv.I2 + inv.I3 @ zeta)
    out[:3, 6:] = A @ inv.I3
    out[3:6, 3:6] = _theta(inv, zeta)
    out[3:6, 6:] = inv.I4 + np.einsum("j,jan->an", zeta, inv.I5)
    out[6:, 6:] = inv.I6
    out[3:, :3] = out[:3, 3:].T
    out[6:, 3:6] = out[3:6, 6:].T
    return out


def _quadratic(comp, A, omega, zeta, zeta_d):
    inv = comp.invariants
    c, theta = inv.I2 + inv.I3 @ zeta, _theta(inv, zeta)
    iwz, dtheta = inv.I4 + np.einsum("j,jan->an", zeta, inv.I5), _d_theta(inv, zeta)
    i5_rate = np.einsum("j,jan->an", zeta_d, inv.I5)
    wx = skew(omega)
    f_t = -A @ (wx @ (wx @ c) + 2.0 * wx @ (inv.I3 @ zeta_d))
    f_w = -wx @ (theta @ omega + iwz @ zeta_d)
    f_w -= np.einsum("j,jab->ab", zeta_d, dtheta) @ omega + i5_rate @ zeta_d
    f_z = 0.5 * np.einsum("a,jab,b->j", omega, dtheta, omega)
    f_z += np.einsum("a,jan,n->j", omega, inv.I5, zeta_d) - i5_rate.T @ omega
    return np.concatenate([f_t, f_w, f_z])


def _applied(comp, A, zeta, zeta_d, gravity):
    inv, g_body = comp.invariants, A.T @ gravity
    elastic = inv.I3.T @ g_body - comp.stiffness * zeta - comp.viscous * zeta_d
    return np.concatenate([comp.mass * gravity, skew(inv.I2 + inv.I3 @ zeta) @ g_body, elastic])


def _velocity_map(p, n):
    t = np.zeros((6 + n, 7 + n))
    t[:3, :3] = np.eye(3)
    t[3:6, 3:7] = 2.0 * g_matrix(p)
    t[6:, 7:] = np.eye(n)
    return t


def _coordinate_forces(comp, p, pd, zeta, zeta_d, gravity, loads):
    A, omega = rotation_matrix(p), omega_body(p, pd)
    f = _applied(comp, A, zeta, zeta_d, gravity) + _quadratic(comp, A, omega, zeta, zeta_d)
    f[6:] -= comp.geometric.stiffness(omega, loads) @ zeta
    return _velocity_map(p, comp.count).T @ f


def _weld_node(comp, k, a, row, node):
    """(residual (6,), Jacobian rows (6, ncol), rate (6,), gamma (6,)) of one kept node."""
    zeta, zeta_d = k.z[a.modes], k.zd[a.modes]
    u = comp.positions[row] + comp.phi[row] @ zeta
    u_d, theta = comp.phi[row] @ zeta_d, comp.phi_star[row] @ zeta
    theta_d = comp.phi_star[row] @ zeta_d
    p, pd, pn, pnd = k.p[a.frame], k.pd[a.frame], k.p[node], k.pd[node]
    A, An = rotation_matrix(p), rotation_matrix(pn)
    fb, nb_, zc = 7 * a.frame, 7 * node, 7 * k.x.shape[0] + a.offset + np.arange(a.body.n)
    phi, jac, rate, gamma = np.empty(6), np.zeros((6, k.ncol)), np.empty(6), np.empty(6)
    phi[:3] = k.r[node] - k.r[a.frame] - A @ u
    jac[:3, nb_ : nb_ + 3] += np.eye(3)
    jac[:3, fb : fb + 3] -= np.eye(3)
    jac[:3, fb + 3 : fb + 7] -= b_matrix(p, u)
    jac[:3, zc] -= A @ comp.phi[row]
    rate[:3] = k.rd[node] - k.rd[a.frame] - b_matrix(p, u) @ pd - A @ u_d
    gamma[:3] = b_matrix(pd, u) @ pd + 2.0 * b_matrix(p, u_d) @ pd
    for c, (f, g) in enumerate(PAIRS):
        v, v_d = AXES[g] + cross3(theta, AXES[g]), cross3(theta_d, AXES[g])
        an, b = An @ AXES[f], A @ v
        an_d = b_matrix(pn, AXES[f]) @ pnd
        b_d = b_matrix(p, v) @ pd + A @ v_d
        phi[3 + c] = an @ b
        jac[3 + c, nb_ + 3 : nb_ + 7] += b @ b_matrix(pn, AXES[f])
        jac[3 + c, fb + 3 : fb + 7] += an @ b_matrix(p, v)
        jac[3 + c, zc] += an @ A @ (-skew(AXES[g]) @ comp.phi_star[row])
        rate[3 + c] = an_d @ b + an @ b_d
        quad = (b_matrix(pnd, AXES[f]) @ pnd) @ b + 2.0 * an_d @ b_d
        quad += an @ (b_matrix(pd, v) @ pd + 2.0 * b_matrix(p, v_d) @ pd)
        gamma[3 + c] = -quad
    return phi, jac, rate, gamma


def _node_loads(comp, k, a, lam):
    A = rotation_matrix(k.p[a.frame])
    out = []
    for row, node in enumerate(a.nodes):
        theta = comp.phi_star[row] @ k.z[a.modes]
        turn, rows = A.T @ rotation_matrix(k.p[node]), lam[6 * row : 6 * row + 6]
        torque = np.zeros(3)
        for c, (f, g) in enumerate(PAIRS):
            torque += rows[3 + c] * cross3(turn[:, f], AXES[g] + cross3(theta, AXES[g]))
        out.append(np.r_[A.T @ rows[:3], torque])
    return np.array(out)


# --- the tests ---


@pytest.fixture(scope="module")
def state() -> State:
    return _state(np.random.default_rng(40))


def test_body_terms_match_the_python_formulas(state: State) -> None:
    """M_w, f_v, the applied forces and Theta in velocities w."""
    a, _, k, _ = state
    comp, p, zeta, zeta_d = a.body.component, k.p[0], k.z, k.zd
    A, omega, gravity = rotation_matrix(p), omega_body(p, k.pd[0]), np.array([1.0, -9.8, 3.0])
    _close(a.body.mass(A, zeta), _mass_w(comp, A, zeta))
    _close(a.body.quadratic(A, omega, zeta, zeta_d), _quadratic(comp, A, omega, zeta, zeta_d))
    _close(a.body.applied(A, zeta, zeta_d, gravity), _applied(comp, A, zeta, zeta_d, gravity))
    _close(a.body.theta(zeta), _theta(comp.invariants, zeta))


def test_coordinate_terms_match_the_python_formulas(state: State) -> None:
    """M_q = T^T M_w T + (4 tr Theta / 3) p p^T and Q_q = T^T f_w, with the stiffening of
    the spin and of the node loads (and without the node loads: None)."""
    a, _, k, loads = state
    comp, p, pd = a.body.component, k.p[0], k.pd[0]
    t = _velocity_map(p, comp.count)
    mass = t.T @ _mass_w(comp, rotation_matrix(p), k.z) @ t
    mass[3:7, 3:7] += 4.0 * np.trace(_theta(comp.invariants, k.z)) / 3.0 * np.outer(p, p)
    _close(a.mass(k), mass)
    gravity = np.array([0.0, 0.0, -9.81])
    for node_loads in (loads, None):
        _close(
            a.forces(k, gravity, True, node_loads),
            _coordinate_forces(comp, p, pd, k.z, k.zd, gravity, node_loads),
        )


def test_weld_terms_match_the_python_formulas(state: State) -> None:
    """Residual, Jacobian rows, rate, gamma and the node loads of the multipliers."""
    a, welds, k, _ = state
    parts = [_weld_node(a.body.component, k, a, row, node) for row, node in enumerate(a.nodes)]
    phi, jac, rate, gamma = (np.concatenate([q[i] for q in parts]) for i in range(4))
    _close(welds.phi(k), phi)
    out = np.zeros((welds.size, k.ncol))
    welds.jacobian(k, out)
    _close(out, jac)
    _close(welds.rate(k), rate)
    _close(welds.gamma(k), gamma)
    lam = np.random.default_rng(1).normal(scale=50.0, size=welds.size)
    _close(welds.node_loads(k, lam, a), _node_loads(a.body.component, k, a, lam))


def test_compiled_and_interpreted_kernels_agree(state: State) -> None:
    """Each kernel compiled and run as Python (its py_func) gives the same numbers."""
    a, welds, k, loads = state
    body = a.body
    i1, i2, i3, i4, i5, _, i7, i8, i9 = body.arrays
    p, pd = k.p[0].copy(), k.pd[0].copy()
    compiled, interpreted = np.empty((7 + body.n, 7 + body.n)), np.empty((7 + body.n,) * 2)
    kernels.coordinate_mass(p, k.z, *body.arrays, np.empty((6 + body.n,) * 2), compiled)
    _python(kernels.coordinate_mass)(p, k.z, *body.arrays, np.empty((6 + body.n,) * 2), interpreted)
    _close(compiled, interpreted)
    args = (
        p, pd, k.z, k.zd, np.array([0.0, 0.0, -9.81]), True, i1, i2, i3, i4, i5, i7, i8, i9,
        body.stiffness, body.viscous, body.spin, body.nodal, loads, np.empty(6 + body.n),
    )  # fmt: skip
    forces, forces_py = np.empty(7 + body.n), np.empty(7 + body.n)
    kernels.coordinate_forces(*args, forces)
    _python(kernels.coordinate_forces)(*args, forces_py)
    _close(forces, forces_py)
    nodes = np.array(a.nodes, dtype=np.int64)
    shapes = (body.positions, body.phi, body.phi_star)
    jac, jac_py = np.zeros((welds.size, k.ncol)), np.zeros((welds.size, k.ncol))
    weld_kernels.weld_jacobian(k.x, 0, nodes, *shapes, k.z, welds.z0, jac)
    _python(weld_kernels.weld_jacobian)(k.x, 0, nodes, *shapes, k.z, welds.z0, jac_py)
    _close(jac, jac_py)
    gamma, gamma_py = np.empty(welds.size), np.empty(welds.size)
    weld_kernels.weld_gamma(k.x, k.xd, 0, nodes, *shapes, k.z, k.zd, gamma)
    _python(weld_kernels.weld_gamma)(k.x, k.xd, 0, nodes, *shapes, k.z, k.zd, gamma_py)
    _close(gamma, gamma_py)
