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

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from mechlib.flexible import kernels
from mechlib.flexible.weld_kernels import weld_gamma, weld_jacobian, weld_phi, weld_rate
from mechlib.kinematics.kin import Kin

if TYPE_CHECKING:
    from mechlib.flexible.modal_body import ModalBody

__all__ = ["Attached", "NodeWelds"]

_NO_LOADS = np.zeros((0, 6))


@dataclass
class Attached:
    """One modal body: frame body index, first modal coordinate (into zeta), node bodies."""

    name: str
    body: ModalBody
    frame: int
    offset: int
    nodes: list[int]  # body index of each kept node (rows of the component)
    _columns: dict[int, np.ndarray] = field(default_factory=dict, repr=False)
    _blocks: dict[int, tuple[np.ndarray, ...]] = field(default_factory=dict, repr=False)

    @property
    def modes(self) -> slice:
        return slice(self.offset, self.offset + self.body.n)

    def columns(self, nb: int) -> np.ndarray:
        """Its coordinates' indices in q (7 + n,) of a system of nb bodies (found once)."""
        if nb not in self._columns:
            o = 7 * self.frame
            self._columns[nb] = np.r_[o : o + 7, 7 * nb + self.offset + np.arange(self.body.n)]
        return self._columns[nb]

    def block(self, nb: int) -> tuple[np.ndarray, ...]:
        """The open-mesh index (np.ix_) of its (7 + n, 7 + n) block in M of a system of nb
        bodies (found once: a mass matrix is formed at every Newton iteration)."""
        if nb not in self._blocks:
            cols = self.columns(nb)
            self._blocks[nb] = np.ix_(cols, cols)
        return self._blocks[nb]

    def mass(self, k: Kin) -> np.ndarray:
        """M_q (7 + n, 7 + n), with the rigid body's p p^T term fixing |p|."""
        body = self.body
        out = np.empty((7 + body.n, 7 + body.n))
        p, zeta = k.p[self.frame], k.z[self.modes]
        kernels.coordinate_mass(p, zeta, *body.arrays, body.scratch[0], out)
        return out

    def forces(
        self, k: Kin, gravity: np.ndarray, inertia: bool, node_loads: np.ndarray | None = None
    ) -> np.ndarray:
        """Q_q (7 + n): gravity, modal stiffness and damping, with `inertia` the quadratic
        velocity vector; with geometric stiffening, -K_G zeta of the spin and of the loads
        `node_loads` (k, 6) on the body at its kept nodes (body axes; None: unknown)."""
        body = self.body
        i1, i2, i3, i4, i5, _, i7, i8, i9 = body.arrays
        loads = _NO_LOADS if node_loads is None or not len(body.nodal) else node_loads
        out = np.empty(7 + body.n)
        kernels.coordinate_forces(
            k.p[self.frame], k.pd[self.frame], k.z[self.modes], k.zd[self.modes], gravity,
            inertia, i1, i2, i3, i4, i5, i7, i8, i9, body.stiffness, body.viscous, body.spin,
            body.nodal, loads, body.scratch[1], out,
        )  # fmt: skip
        return out


class NodeWelds:
    """The six weld equations of every kept node of the modal bodies (a constraint group:
    phi, jacobian, gamma, rate as mechlib.kinematics.constraints)."""

    def __init__(self, bodies: list[Attached], nb: int):
        self.items = [(a, row, node) for a in bodies for row, node in enumerate(a.nodes)]
        self.size = 6 * len(self.items)
        self.z0 = 7 * (nb + 1)  # first modal column of a working Jacobian row
        self.bodies: list[tuple[Attached, int, np.ndarray]] = []  # (body, first row, nodes)
        row = 0
        for a in bodies:
            self.bodies.append((a, row, np.array(a.nodes, dtype=np.int64)))
            row += 6 * len(a.nodes)

    def _shapes(self, a: Attached) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        body = a.body
        return body.positions, body.phi, body.phi_star

    def phi(self, k: Kin) -> np.ndarray:
        out = np.empty(self.size)
        for a, first, nodes in self.bodies:
            rows = out[first : first + 6 * len(nodes)]
            weld_phi(k.x, a.frame, nodes, *self._shapes(a), k.z[a.modes], rows)
        return out

    def jacobian(self, k: Kin, out: np.ndarray) -> None:
        """Add the rows into `out` (size, 7 (nb + 1) + nz)."""
        for a, first, nodes in self.bodies:
            rows = out[first : first + 6 * len(nodes)]
            z_col = self.z0 + a.offset
            weld_jacobian(k.x, a.frame, nodes, *self._shapes(a), k.z[a.modes], z_col, rows)

    def node_loads(self, k: Kin, lam: np.ndarray, body: Attached) -> np.ndarray:
        """(k, 6): force (N) and torque (N m) on `body` at each of its kept nodes, body
        axes, from the multipliers `lam` (size,) of these equations (M qdd + phi_q^T lam
        = Q): linear in them, `load_maps` @ the node's six multipliers."""
        first, nodes = self.rows_of(body)
        rows = lam[first : first + 6 * len(nodes)].reshape(-1, 6, 1)
        return np.matmul(self.load_maps(k, body), rows)[:, :, 0]

    def load_maps(self, k: Kin, body: Attached) -> np.ndarray:
        """(k, 6, 6): d(node load)/d(its weld multipliers) of each kept node of `body`
        (mechlib.flexible.kernels.load_maps)."""
        _, nodes = self.rows_of(body)
        out = np.empty((len(nodes), 6, 6))
        kernels.load_maps(k.p[body.frame], k.p[nodes], body.body.phi_star, k.z[body.modes], out)
        return out

    def rows_of(self, body: Attached) -> tuple[int, np.ndarray]:
        """(first weld row, node body indices (k,)) of `body`."""
        return next((first, nodes) for a, first, nodes in self.bodies if a is body)

    def gamma(self, k: Kin) -> np.ndarray:
        """phi_q qdd = gamma: minus the terms of the second derivative without qdd."""
        out = np.empty(self.size)
        for a, first, nodes in self.bodies:
            rows = out[first : first + 6 * len(nodes)]
            z, zd = k.z[a.modes], k.zd[a.modes]
            weld_gamma(k.x, k.xd, a.frame, nodes, *self._shapes(a), z, zd, rows)
        return out

    def rate(self, k: Kin) -> np.ndarray:
        """d(phi)/dt (size,)."""
        out = np.empty(self.size)
        for a, first, nodes in self.bodies:
            rows = out[first : first + 6 * len(nodes)]
            z, zd = k.z[a.modes], k.zd[a.modes]
            weld_rate(k.x, k.xd, a.frame, nodes, *self._shapes(a), z, zd, rows)
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
