"""M(zeta) and the quadratic velocity vector of a modal body against independent forms.

Oracle 1 (docs/flexible-bodies.md, the notes' nodal oracle): for particles m_p at
r_p = s_p + Phi_p zeta, global velocity L_p w with L_p = [I, -A r_p~, A Phi_p], and
acceleration L_p w_d + h_p with h_p = A (w~ w~ r_p + 2 w~ Phi_p zeta_d): M = sum m_p L_p^T L_p
and f_v = -sum m_p L_p^T h_p (Newton = Lagrange for particles). Signs are checked here, not
copied. Oracle 2 (any mass matrix, rotary inertia included): the power balance of free
motion, w^T f_v = -1/2 w^T (dM/dt) w, dM/dt by central differences along the motion.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from mechlib.core.rotation import rotation_matrix, skew
from mechlib.flexible.beam import Material, Section, assemble_beams
from mechlib.flexible.craig_bampton import craig_bampton
from mechlib.flexible.fe_model import FEModel
from mechlib.flexible.invariants import field_invariants
from mechlib.flexible.modal_body import ModalBody
from mechlib.flexible.modal_component import ModalComponent


def _particles(n_p: int = 7, n: int = 3):
    """Translation-only nodes with point masses and arbitrary (not mean-axis) modes, an
    origin away from the centre of mass: every invariant is non-zero."""
    rng = np.random.default_rng(11)
    xyz = rng.uniform(-1.0, 1.0, (n_p, 3))
    masses = rng.uniform(0.5, 2.0, n_p)
    dof_map = np.column_stack([np.repeat(np.arange(n_p), 3), np.tile(np.arange(3), n_p)])
    empty = sp.csr_matrix((3 * n_p, 3 * n_p))
    model = FEModel(
        np.arange(1, n_p + 1),
        xyz,
        dof_map,
        empty,
        sp.csr_matrix(sp.diags(np.repeat(masses, 3))),
        (),
    )
    psi = rng.standard_normal((3 * n_p, n))
    origin = np.array([0.1, -0.2, 0.05])
    comp = ModalComponent(
        mass=float(masses.sum()),
        origin=origin,
        invariants=field_invariants(model, psi, origin),
        node_ids=model.node_ids,
        positions=xyz - origin,
        phi=psi.reshape(n_p, 3, n),
        phi_star=np.zeros((n_p, 3, n)),
        frequencies=np.ones(n),
        damping=np.zeros(n),
    )
    return comp, masses


def _state(n: int, seed: int = 2):
    rng = np.random.default_rng(seed)
    p = rng.standard_normal(4)
    return (
        rotation_matrix(p / np.linalg.norm(p)),
        rng.standard_normal(3),
        0.3 * rng.standard_normal(n),
        rng.standard_normal(n),
    )


def test_mass_matrix_and_quadratic_velocity_vector_against_particles():
    """Both to 1e-13 relative (measured ~1e-15)."""
    comp, masses = _particles()
    body = ModalBody(comp)
    A, omega, zeta, zeta_d = _state(comp.count)
    w = np.concatenate([np.zeros(3), omega, zeta_d])
    m_ref = np.zeros((6 + comp.count, 6 + comp.count))
    f_ref = np.zeros(6 + comp.count)
    wx = skew(omega)
    for m_p, s_p, phi_p in zip(masses, comp.positions, comp.phi):
        r_p = s_p + phi_p @ zeta
        L = np.hstack([np.eye(3), -A @ skew(r_p), A @ phi_p])
        h = A @ (wx @ wx @ r_p + 2.0 * wx @ (phi_p @ zeta_d))
        m_ref += m_p * L.T @ L
        f_ref -= m_p * L.T @ h
    assert np.abs(body.mass(A, zeta) - m_ref).max() < 1e-13 * np.abs(m_ref).max()
    f = body.quadratic(A, omega, zeta, zeta_d)
    assert np.abs(f - f_ref).max() < 1e-13 * np.abs(f_ref).max()
    assert w.shape == f.shape


def test_power_balance_with_consistent_mass_and_rotary_inertia():
    """A Craig-Bampton beam component (consistent mass, rotational DOF): free motion keeps
    T constant, w^T f_v + 1/2 w^T dM/dt w = 0 (1e-7 relative: central differences)."""
    steel = Material(E=210e9, nu=0.3, rho=7850.0)
    xyz = np.outer(np.linspace(0.0, 1.0, 9), [1.0, 0.0, 0.0])
    xyz[:, 1] = 0.1 * xyz[:, 0] ** 2
    beams = [(i, i + 1, Section.rectangle(0.05, 0.08), steel, (0, 0.2, 1)) for i in range(8)]
    comp = craig_bampton(assemble_beams(xyz, beams, interface=(0, 8)), modes=4)
    body = ModalBody(comp)
    A, omega, zeta, zeta_d = _state(comp.count, seed=4)
    zeta *= 0.05
    w = np.concatenate([np.array([0.3, -0.1, 0.2]), omega, zeta_d])
    h = 1e-6

    def mass_at(tau: float) -> np.ndarray:
        rot = A @ _exp(tau * omega)  # body-axes angular velocity: A_d = A omega~
        return body.mass(rot, zeta + tau * zeta_d)

    m_dot = (mass_at(h) - mass_at(-h)) / (2 * h)
    power = w @ body.quadratic(A, omega, zeta, zeta_d)
    scale = abs(0.5 * w @ m_dot @ w) + abs(power)
    assert abs(power + 0.5 * w @ m_dot @ w) < 1e-7 * scale


def _exp(v: np.ndarray) -> np.ndarray:
    """Rotation matrix of the rotation vector v (Rodrigues)."""
    angle = np.linalg.norm(v)
    k = skew(v / angle)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k
