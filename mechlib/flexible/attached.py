"""Modal bodies inside a `System`: their mass and forces, and the welds of their nodes.

Every kept node of a flexible body is a massless rigid "node body" of the mechanism; joints,
springs, contacts, loads and requests attach to it as to any body. Six weld equations per
node tie it to the deformed flexible body (seed 003 eqs 1.9-1.21, linearised node rotation):
position r_n = x + A (s + Phi zeta), orientation A_n = A (I + theta~), theta = Phi* zeta, the
latter as three perpendicularity equations (A_n f) . (A (g + theta x g)) = 0 for the pairs
(f, g) = (y, z), (z, x), (x, y). A massless node adds no inertia: its loads reach the modal
body through the weld's multipliers, exactly the nodal loads of eqs 1.24-1.30.

Coordinates of a modal body in q: its frame [x, p] (7, as a rigid body) and its modal
coordinates zeta after all the bodies' (q[7 nb + offset]); velocities w = T qd with
T = diag(I, 2 G(p), I) (omega = 2 G pd), so M_q = T^T M_w T and Q_q = T^T f_w.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mechlib.core.rotation import cross3, g_matrix, omega_body, skew
from mechlib.kinematics.kernels import b_matrix as d_rotate
from mechlib.kinematics.kernels import rotation_matrix
from mechlib.kinematics.kin import Kin

if TYPE_CHECKING:
    from mechlib.flexible.modal_body import ModalBody

__all__ = ["Attached", "NodeWelds"]

_PAIRS = ((1, 2), (2, 0), (0, 1))  # (f, g) axes of the three orientation equations
_AXES = np.eye(3)


@dataclass
class Attached:
    """One modal body: frame body index, first modal coordinate (into zeta), node bodies."""

    name: str
    body: ModalBody
    frame: int
    offset: int
    nodes: list[int]  # body index of each kept node (rows of the component)

    @property
    def modes(self) -> slice:
        return slice(self.offset, self.offset + self.body.n)

    def velocity_map(self, k: Kin) -> np.ndarray:
        """T (6 + n, 7 + n): w = T [xd, pd, zeta_d]."""
        n = self.body.n
        t = np.zeros((6 + n, 7 + n))
        t[:3, :3] = np.eye(3)
        t[3:6, 3:7] = 2.0 * g_matrix(k.p[self.frame])
        t[6:, 7:] = np.eye(n)
        return t

    def columns(self, nb: int) -> np.ndarray:
        """Its coordinates' indices in q (7 + n,)."""
        o = 7 * self.frame
        return np.r_[o : o + 7, 7 * nb + self.offset + np.arange(self.body.n)]

    def mass(self, k: Kin) -> np.ndarray:
        """M_q (7 + n, 7 + n), with the rigid body's p p^T term fixing |p|."""
        p, zeta = k.p[self.frame], k.z[self.modes]
        t = self.velocity_map(k)
        out = t.T @ self.body.mass(rotation_matrix(p), zeta) @ t
        scale = 4.0 * np.trace(self.body.theta(zeta)) / 3.0
        out[3:7, 3:7] += scale * np.outer(p, p)
        return out

    def forces(
        self, k: Kin, gravity: np.ndarray, inertia: bool, node_loads: np.ndarray | None = None
    ) -> np.ndarray:
        """Q_q (7 + n): gravity, modal stiffness and damping, with `inertia` the quadratic
        velocity vector; with geometric stiffening, -K_G zeta of the spin and of the loads
        `node_loads` (k, 6) on the body at its kept nodes (body axes; None: unknown)."""
        p, zeta, zeta_d = k.p[self.frame], k.z[self.modes], k.zd[self.modes]
        A = rotation_matrix(p)
        f = self.body.applied(A, zeta, zeta_d, gravity)
        omega = omega_body(p, k.pd[self.frame])
        if inertia:
            f = f + self.body.quadratic(A, omega, zeta, zeta_d)
        geometric = self.body.component.geometric
        if geometric is not None:
            f[6:] -= geometric.stiffness(omega, node_loads) @ zeta
        return self.velocity_map(k).T @ f


class NodeWelds:
    """The six weld equations of every kept node of the modal bodies (a constraint group:
    phi, jacobian, gamma, rate as mechlib.kinematics.constraints)."""

    def __init__(self, bodies: list[Attached], nb: int):
        self.items = [(a, row, node) for a in bodies for row, node in enumerate(a.nodes)]
        self.size = 6 * len(self.items)
        self.z0 = 7 * (nb + 1)  # first modal column of a working Jacobian row

    def _parts(self, k: Kin, a: Attached, row: int):
        comp = a.body.component
        zeta, zeta_d = k.z[a.modes], k.zd[a.modes]
        phi, phis = comp.phi[row], comp.phi_star[row]
        return comp.positions[row] + phi @ zeta, phi @ zeta_d, phis @ zeta, phis @ zeta_d

    def phi(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        for i, (a, row, node) in enumerate(self.items):
            u, _, theta, _ = self._parts(k, a, row)
            A, An = rotation_matrix(k.p[a.frame]), rotation_matrix(k.p[node])
            out[6 * i : 6 * i + 3] = k.r[node] - k.r[a.frame] - A @ u
            for c, (f, g) in enumerate(_PAIRS):
                v = _AXES[g] + cross3(theta, _AXES[g])
                out[6 * i + 3 + c] = (An @ _AXES[f]) @ (A @ v)
        return out

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        """Add the rows into `out` (size, 7 (nb + 1) + nz)."""
        for i, (a, row, node) in enumerate(self.items):
            comp = a.body.component
            u, _, theta, _ = self._parts(k, a, row)
            p, pn = k.p[a.frame], k.p[node]
            A, An = rotation_matrix(p), rotation_matrix(pn)
            fb, nb_, zc = 7 * a.frame, 7 * node, self.z0 + a.offset + np.arange(a.body.n)
            rows = out[6 * i : 6 * i + 3]
            rows[:, nb_ : nb_ + 3] += np.eye(3)
            rows[:, fb : fb + 3] -= np.eye(3)
            rows[:, fb + 3 : fb + 7] -= d_rotate(p, u)
            rows[:, zc] -= A @ comp.phi[row]
            for c, (f, g) in enumerate(_PAIRS):
                v = _AXES[g] + cross3(theta, _AXES[g])
                an, b = An @ _AXES[f], A @ v
                r = out[6 * i + 3 + c]
                r[nb_ + 3 : nb_ + 7] += b @ d_rotate(pn, _AXES[f])
                r[fb + 3 : fb + 7] += an @ d_rotate(p, v)
                r[zc] += an @ A @ (-skew(_AXES[g]) @ comp.phi_star[row])

    def node_loads(self, k: Kin, lam: np.ndarray, body: Attached) -> np.ndarray:
        """(k, 6): force (N) and torque (N m) on `body` at each of its kept nodes, body
        axes, from the multipliers `lam` (size,) of these equations (M qdd + phi_q^T lam
        = Q): the position rows push the body with +lam, an orientation row
        (A_n f).(A v) = 0 turns it with lam (A_n f) x (A v)."""
        A = rotation_matrix(k.p[body.frame])
        out = []
        for i, (a, row, node) in enumerate(self.items):
            if a is not body:
                continue
            theta = a.body.component.phi_star[row] @ k.z[a.modes]
            turn, rows = A.T @ rotation_matrix(k.p[node]), lam[6 * i : 6 * i + 6]
            torque = np.zeros(3)  # body axes: (A^T A_n f) x v
            for c, (f, g) in enumerate(_PAIRS):
                torque += rows[3 + c] * cross3(turn[:, f], _AXES[g] + cross3(theta, _AXES[g]))
            out.append(np.r_[A.T @ rows[:3], torque])
        return np.array(out)

    def gamma(self, k: Kin) -> np.ndarray:
        """phi_q qdd = gamma: minus the terms of the second derivative without qdd."""
        out = np.empty(self.size)
        for i, (a, row, node) in enumerate(self.items):
            u, u_d, theta, theta_d = self._parts(k, a, row)
            p, pd, pn, pnd = k.p[a.frame], k.pd[a.frame], k.p[node], k.pd[node]
            A = rotation_matrix(p)
            out[6 * i : 6 * i + 3] = d_rotate(pd, u) @ pd + 2.0 * d_rotate(p, u_d) @ pd
            for c, (f, g) in enumerate(_PAIRS):
                v = _AXES[g] + cross3(theta, _AXES[g])
                v_d = cross3(theta_d, _AXES[g])
                an, b = rotation_matrix(pn) @ _AXES[f], A @ v
                an_d = d_rotate(pn, _AXES[f]) @ pnd
                b_d = d_rotate(p, v) @ pd + A @ v_d
                quad = (d_rotate(pnd, _AXES[f]) @ pnd) @ b + 2.0 * an_d @ b_d
                quad += an @ (d_rotate(pd, v) @ pd + 2.0 * d_rotate(p, v_d) @ pd)
                out[6 * i + 3 + c] = -quad
        return out

    def rate(self, k: Kin) -> np.ndarray:
        """d(phi)/dt (size,)."""
        out = np.empty(self.size)
        for i, (a, row, node) in enumerate(self.items):
            u, u_d, theta, theta_d = self._parts(k, a, row)
            p, pd, pn, pnd = k.p[a.frame], k.pd[a.frame], k.p[node], k.pd[node]
            A = rotation_matrix(p)
            out[6 * i : 6 * i + 3] = k.rd[node] - k.rd[a.frame] - d_rotate(p, u) @ pd - A @ u_d
            for c, (f, g) in enumerate(_PAIRS):
                v = _AXES[g] + cross3(theta, _AXES[g])
                an, b = rotation_matrix(pn) @ _AXES[f], A @ v
                b_d = d_rotate(p, v) @ pd + A @ cross3(theta_d, _AXES[g])
                out[6 * i + 3 + c] = (d_rotate(pn, _AXES[f]) @ pnd) @ b + an @ b_d
        return out


def attach_flexible(mechanism, index: dict[str, int]) -> list[Attached]:
    """The modal bodies of `mechanism` (body indices from `index`), modal coordinates in
    the order of `mechanism.flexible`."""
    out, offset = [], 0
    for name, flexible in mechanism.flexible.items():
        # imported here (scipy.sparse): a System without flexible bodies does not load it
        from mechlib.flexible.modal_body import ModalBody

        body = ModalBody(flexible.component)
        nodes = [index[flexible.node_bodies[int(i)]] for i in flexible.component.node_ids]
        out.append(Attached(name, body, index[name], offset, nodes))
        offset += body.n
    return out


_AT_NODE = 1e-6  # m: a point of a flexible body closer than this to a kept node is at it


def node_at(flexible, at) -> str:
    """The node body of the kept node of `flexible` at design point `at` (m, global)."""
    point = np.asarray(at, dtype=float)
    ids = [int(i) for i in flexible.component.node_ids]
    gaps = [float(np.linalg.norm(flexible.node_position(i) - point)) for i in ids]
    best = int(np.argmin(gaps))
    if gaps[best] > _AT_NODE:
        raise ValueError(
            f"flexible body {flexible.name}: point {tuple(point.round(6))} m is not at one of "
            f"its interface nodes (nearest: node {ids[best]}, {gaps[best]:.3g} m away); "
            "loads and attachments act at interface nodes only"
        )
    return flexible.node_bodies[ids[best]]


def weld_labels(welds: NodeWelds) -> list[str]:
    """Labels of the weld equations, six per node."""
    return [
        f"{a.name}: node {int(a.body.component.node_ids[row])} weld {c}"
        for a, row, _ in welds.items
        for c in ("x", "y", "z", "rx", "ry", "rz")
    ]
