"""Modal geometric stiffness of a flexible body (geometric stiffening), SI units.

A linear modal body in a floating frame knows the centrifugal load only through the frame's
inertia: its bending softens as it spins (a linear beam model in the hub frame spun past its
first bending frequency diverges: Kane, Ryan & Banerjee, J. Guid. Control Dyn. 10 (1987)
139). The stresses that the motion and the interface loads set up stiffen it. With the
modal geometric stiffness K_G,c = Psi^T K_G,FE(sigma_c) Psi of unit load cases c (the
"SID" approach: Wallrapp 1994; Schwertassek, Wallrapp & Shabana, Nonlinear Dyn. 20 (1999)
361), the modal equations gain -(sum_c lambda_c K_G,c) zeta. The unit load cases are
balanced by the rigid body's own inertia (inertia relief: the body is free-free in its
mean-axis frame):

- spin: the centrifugal load -M a, a_p = (W - tr(W) I) s_p with W = omega omega^T (body
  axes, s_p from the centre of mass), one case per product omega_a omega_b;
- nodal: a unit force (N) or torque (N m) at each DOF of each kept node (body axes): the
  loads of joints, springs and applied forces reach the body there (the node welds).

Gravity and the frame's acceleration load the body uniformly: rigid acceleration balances
them, without stress (a supported body is stressed by its support's load, a nodal case).
The body's own vibration loads are left out: they stiffen at second order in the
deformation. Beams only: K_G,FE is the consistent Euler-Bernoulli geometric stiffness of
each element's axial force N = EA/L (u_b - u_a).x (Przemieniecki, Theory of Matrix
Structural Analysis, 1968, section 15.2), its lateral translations and bending rotations.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from mechlib.flexible.fe_model import FEModel

__all__ = ["ModalGeometric", "modal_geometric", "spin_products"]

_PRODUCTS = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0))  # omega_a omega_b of the cases


def spin_products(omega: np.ndarray) -> np.ndarray:
    """The six products omega_a omega_b (rad^2/s^2) in the order of the spin cases."""
    return np.array([omega[a] * omega[b] for a, b in _PRODUCTS])


@dataclass(frozen=True)
class ModalGeometric:
    """Modal geometric stiffness (n, n) per unit load: `spin` (6, n, n) per product
    omega_a omega_b (rad^2/s^2, body axes; order xx, yy, zz, xy, yz, zx), `nodal`
    (k, 6, n, n) per unit force (N) and torque (N m) at each kept node (body axes)."""

    spin: np.ndarray
    nodal: np.ndarray

    def stiffness(self, omega: np.ndarray, node_loads: np.ndarray | None) -> np.ndarray:
        """K_G (n, n) at body angular velocity `omega` (rad/s) and the loads (k, 6) on the
        body at its kept nodes (None: not known, left out)."""
        out = np.einsum("c,cij->ij", spin_products(omega), self.spin)
        if node_loads is not None:
            out += np.einsum("kc,kcij->ij", node_loads, self.nodal)
        return out


_PLANE = np.array(  # (v1, theta1, v2, theta2) of plane bending, times L^(r_i + r_j) / 30 L
    [
        [36.0, 3.0, -36.0, 3.0],
        [3.0, 4.0, -3.0, -1.0],
        [-36.0, -3.0, 36.0, -3.0],
        [3.0, -1.0, -3.0, 4.0],
    ]
)
_ROTATION = np.array([0, 1, 0, 1])


def _element_geometric(length: np.ndarray) -> np.ndarray:
    """K_G (e, 12, 12) per unit axial force (N, tension positive) in local axes."""
    L = length[:, None, None]
    block = _PLANE * L ** (_ROTATION[:, None] + _ROTATION[None, :]) / (30.0 * L)
    out = np.zeros((len(length), 12, 12))
    flip = np.array([1.0, -1.0, 1.0, -1.0])  # x-z bending: theta_y = -dw/dx
    for dofs, sign in (([1, 5, 7, 11], np.ones(4)), ([2, 4, 8, 10], flip)):
        out[:, np.array(dofs)[:, None], np.array(dofs)[None, :]] = block * np.outer(sign, sign)
    return out


def _element_dofs(model: FEModel) -> np.ndarray:
    """(e, 12) DOF rows of each beam's two nodes (a built-in model: 6 DOF per node)."""
    beams = model.beams
    assert beams is not None
    six = np.arange(6)
    return np.hstack([6 * beams.a[:, None] + six, 6 * beams.b[:, None] + six])


def _modal_elements(model: FEModel, psi: np.ndarray) -> np.ndarray:
    """(e, n, n): each element's geometric stiffness per unit axial force, on the modes."""
    beams = model.beams
    assert beams is not None
    turn = np.einsum("ab,eij->eaibj", np.eye(4), beams.axes).reshape(-1, 12, 12)
    local = np.einsum("eij,ejn->ein", turn, psi[_element_dofs(model)])
    return np.einsum(
        "ein,eij,ejm->enm", local, _element_geometric(beams.length), local, optimize=True
    )


def _axial_forces(model: FEModel, u: np.ndarray) -> np.ndarray:
    """(c, e) axial force (N, tension positive) of each element under displacements u
    (ndof, c)."""
    beams = model.beams
    assert beams is not None
    dofs = _element_dofs(model)
    stretch = u[dofs[:, 6:9]] - u[dofs[:, 0:3]]  # (e, 3, c)
    return (beams.EA / beams.length)[None, :] * np.einsum("ej,ejc->ce", beams.axes[:, 0], stretch)


def _relieved(model: FEModel, loads: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """Displacements (ndof, c) under `loads` (ndof, c) balanced by rigid-body inertia; the
    rigid part is arbitrary (one interface node held), which leaves the strains alone."""
    rigid = np.hstack(
        [model.translation_field(), model.skew_field(model.coordinates - origin, True)]
    )
    m_rigid = model.mass @ rigid
    balanced = loads - m_rigid @ np.linalg.solve(rigid.T @ m_rigid, rigid.T @ loads)
    free = np.flatnonzero(model.dof_map[:, 0] != model.interface[0])
    k = model.stiffness.tocsr()
    out = np.zeros_like(balanced)
    out[free] = spla.splu(k[free][:, free].tocsc()).solve(balanced[free])
    return out


def _spin_loads(model: FEModel, origin: np.ndarray) -> np.ndarray:
    """(ndof, 6): the centrifugal load -M a of each product omega_a omega_b."""
    s = model.coordinates - origin
    nodes, comps = model.dof_map[:, 0], model.dof_map[:, 1]
    trans = comps < 3
    field = np.zeros((len(model.dof_map), 6))
    for c, (a, b) in enumerate(_PRODUCTS):
        w = np.zeros((3, 3))
        w[a, b] = w[b, a] = 1.0
        accel = s @ (w - np.trace(w) * np.eye(3)).T  # (W - tr W I) s per node
        field[trans, c] = accel[nodes[trans], comps[trans]]
    return -(model.mass @ field)


def _nodal_loads(model: FEModel, nodes: Sequence[int]) -> np.ndarray:
    """(ndof, 6 k): a unit load at each DOF of each node (index into the model)."""
    out = np.zeros((len(model.dof_map), 6 * len(nodes)))
    for row, node in enumerate(nodes):
        for c in range(6):
            out[model.dof_index(node, c), 6 * row + c] = 1.0
    return out


def modal_geometric(
    model: FEModel, psi: np.ndarray, origin: np.ndarray, nodes: Sequence[int]
) -> ModalGeometric:
    """The modal geometric stiffness of `model` (with beams) on the modes `psi` (ndof, n),
    frame origin `origin` (3,) m (the centre of mass), per unit load at the kept `nodes`
    (indices into the model); ValueError for a model without beam elements."""
    if model.beams is None:
        raise ValueError(
            "geometric stiffening needs the elements of the model: a built-in beam or "
            "grillage (an imported model has matrices only, a plate no beam elements)"
        )
    loads = np.hstack([_spin_loads(model, origin), _nodal_loads(model, nodes)])
    forces = _axial_forces(model, _relieved(model, loads, origin))
    cases = np.einsum("ce,enm->cnm", forces, _modal_elements(model, psi))
    n = psi.shape[1]
    return ModalGeometric(cases[:6], cases[6:].reshape(len(nodes), 6, n, n))
