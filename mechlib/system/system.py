"""A mechanism compiled to arrays: constraint equations, mass matrix, applied forces.

Symbols (7 coordinates per moving body, ground excluded): ``phi`` (m,) residuals,
``phi_q`` (m, nq) Jacobian, ``nu`` right side of ``phi_q qd = nu``, ``gamma`` right side of
``phi_q qdd = gamma``, ``M`` (nq, nq), ``Q`` (nq,) generalised applied forces, and the
equations of motion ``M qdd + phi_q^T lam = Q``. Row `i` of every constraint array is
labelled ``labels[i]`` and belongs to joint or motion ``owners[i]``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mechlib.core import jit
from mechlib.core.rotation import e_matrix
from mechlib.elements.compiled_forces import CompiledForces
from mechlib.flexible.kernels import weld_coupling
from mechlib.kinematics import kernels
from mechlib.kinematics.constraint_arrays import ConstraintArrays
from mechlib.kinematics.kin import Kin
from mechlib.kinematics.view import StateView
from mechlib.model.mechanism import Mechanism

if TYPE_CHECKING:
    from mechlib.linalg.factor import SaddlePattern
    from mechlib.linalg.sparse_rows import SparseRows

from mechlib.system.known_patterns import known_pattern
from mechlib.system.topology import Topology

__all__ = ["System"]

_NO_GRAVITY = np.zeros(3)


class System(Topology):
    """The numerical form of a `Mechanism` evaluated at a state (module docstring has the
    symbols): constraints, mass, applied forces; its rows and elements are its `Topology`."""

    _pattern: SaddlePattern | None = None  # the saddle matrix's sparsity, found on first use

    def __init__(self, mechanism: Mechanism):
        self._arrays: ConstraintArrays | bool | None = False  # packed_constraints(), once
        self._forces: tuple = ((), None)  # (the elements' switches, compiled_forces())
        self._no_wrench = np.zeros((len(mechanism.bodies) + 1, 3))
        self._no_wrench.flags.writeable = False
        self.row_plans: dict[tuple[bytes, bytes], list] = {}  # mechlib.system.rows_jacobian
        super().__init__(mechanism)

    def frame_origin(self, name: str, k: Kin) -> np.ndarray:
        """Origin (m, global) of frame `name`: a named frame's `at`; a body's frame is the
        body-fixed point that was at the global origin at design (CAD axes moving along)."""
        body, _, at = self.mechanism.frames.get(name, (name, None, (0.0, 0.0, 0.0)))
        b, s = self.body_point(body, at)
        return self.view(k).point_position(b, s)

    # ---- evaluation ---------------------------------------------------------------------
    def kin(self, q: np.ndarray, qd: np.ndarray | None = None, t: float = 0.0) -> Kin:
        return Kin.from_state(q, qd, t, self.nz)

    def body_columns(self, rows: np.ndarray) -> np.ndarray:
        """Working Jacobian rows (..., 7 (nb + 1) + nz) without ground's columns (..., nq)."""
        if not self.nz:
            return rows[..., : self.nq]
        cut = 7 * self.nb
        return np.concatenate([rows[..., :cut], rows[..., cut + 7 :]], axis=-1)

    def coordinate_gradient(self, measure, k: Kin) -> np.ndarray:
        """d(measure)/dq (nq,) of a joint angle or travel (mechlib.kinematics.coordinates)."""
        return self.body_columns(measure.gradient(k))

    def body_rates(self, k: Kin, body: int) -> np.ndarray:
        """(6, nq): qd -> the velocity (m/s) and angular velocity (rad/s) of `body`, global."""
        block = np.zeros((6, self.nq))
        block[:3, 7 * body : 7 * body + 3] = np.eye(3)
        block[3:, 7 * body + 3 : 7 * body + 7] = 2.0 * e_matrix(k.p[body])
        return block

    def state_of(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(q, qd) (nq,) of state `k`: the inverse of `kin`."""
        return np.r_[k.x[:-1].ravel(), k.z], np.r_[k.xd[:-1].ravel(), k.zd]

    def body_weights(self, translation: float, rotation: float) -> np.ndarray:
        """Per-body weights (7,) of q's entries: `translation` for r, `rotation` (the size
        of one radian) for the Euler parameters, which change by half an angle."""
        return np.r_[np.full(3, translation), np.full(4, rotation)]

    def cm_positions(self, q: np.ndarray) -> np.ndarray:
        """Centres of mass (nb, 3), m, global, of the rigid coordinates of q."""
        return q[: 7 * self.nb].reshape(self.nb, 7)[:, :3].copy()

    def cm_forces(self, generalized: np.ndarray) -> np.ndarray:
        """The force parts (nb, 3), N, global, of generalised forces (nq,)."""
        return generalized[: 7 * self.nb].reshape(self.nb, 7)[:, :3]

    def reaction_coupling(self, coupling: np.ndarray, k: Kin) -> np.ndarray:
        """dQ/dlam (nq, m) of elements that wrote it in this system's coordinates."""
        return coupling

    def output_notes(self, reactions: bool) -> list[str]:
        """What the outputs asked for (`reactions`: joint reactions among them) leave out
        (mechlib.system.planar: out-of-plane reactions)."""
        return []

    def in_space(self, trajectory):
        """(the 3-D system, the trajectory in its coordinates) to evaluate outputs on: this
        system and `trajectory` (mechlib.system.planar lifts its own)."""
        return self, trajectory

    def view(
        self, k: Kin, lam: np.ndarray | None = None, jac: np.ndarray | None = None
    ) -> StateView:
        return StateView(self, k, lam, jac)

    def phi(self, k: Kin) -> np.ndarray:
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.phi(k)
        parts = [g.phi(k) for g in self.groups] + [self.coordinate_rows().phi(k)]
        return self._select(np.concatenate(parts))

    def packed_constraints(self) -> ConstraintArrays | None:
        """The constraint equations packed for one compiled call
        (mechlib.kinematics.constraint_arrays), once the kernels are compiled; None where the
        system needs the grouped path (flexible bodies, curve joints) or the kernels run
        as Python (`loads validate`)."""
        if not jit.compiled():
            return None
        if self._arrays is False:
            self._arrays = ConstraintArrays(self) if ConstraintArrays.eligible(self) else None
        return self._arrays  # type: ignore[return-value]

    def compiled_forces(self) -> CompiledForces | None:
        """The active force elements packed for the compiled kernels
        (mechlib.elements.compiled_forces; their moving values as last refreshed); None
        where one has no compiled form. Packed anew only when an element is switched,
        sticks or is locked, or the active equations change."""
        key = CompiledForces.switches(self)
        if key != self._forces[0]:
            self._forces = (key, CompiledForces.of(self))
        return self._forces[1]

    def phi_and_jacobian(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(phi, phi_q): one compiled call (`packed_constraints`) or one pass over the
        primitive groups."""
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.phi_and_jacobian(k)
        return self.grouped_phi_and_jacobian(k)

    def grouped_phi_and_jacobian(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(phi, phi_q) by one compiled call per primitive group and the coordinate block
        (the path of every system; the reference of the packed one)."""
        out = np.zeros((len(self._all_labels), k.ncol))
        parts, row = [], 0
        for g in self.groups:
            parts.append(g.phi(k))
            g.jacobian(k, out[row : row + g.size])
            row += g.size
        block = self.coordinate_rows()
        sines = block.sines(k)
        parts.append(block.phi(k, sines))
        block.jacobian(k, out[row:], sines)
        return self._select(np.concatenate(parts)), self.body_columns(self._select(out))

    def phi_q(self, k: Kin) -> np.ndarray:
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.phi_and_jacobian(k)[1]
        out = np.zeros((len(self._all_labels), k.ncol))
        row = 0
        for g in self.groups:
            g.jacobian(k, out[row : row + g.size])
            row += g.size
        self.coordinate_rows().jacobian(k, out[row:])
        return self.body_columns(self._select(out))

    def phi_q_rows(self, k: Kin, rows: np.ndarray) -> np.ndarray:
        """phi_q[rows] (len(rows), nq) of the active equations `rows`, without the
        others (mechlib.system.rows_jacobian)."""
        from mechlib.system.rows_jacobian import phi_q_rows

        return phi_q_rows(self, k, rows)

    def phi_q_sparse(self, k: Kin) -> SparseRows:
        """`phi_q(k)` as its non-zeros, never the dense matrix (the checks of a large model)."""
        from mechlib.system.sparse_jacobian import sparse_phi_q

        return sparse_phi_q(self, k)

    def nu(self, k: Kin) -> np.ndarray:
        out = np.zeros(len(self._all_labels))
        if self.coordinates:
            out[self.n_geometric :] = [c.nu(k.t) for c in self.coordinates]
        return self._select(out)

    def gamma(self, k: Kin) -> np.ndarray:
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.nu_and_gamma(k)[1]
        parts = [g.gamma(k) for g in self.groups]
        parts.append(self.coordinate_rows().gamma(k))
        return self._select(np.concatenate(parts))

    def commit(self, k: Kin) -> None:
        """Accept a state: joint angles unwrap against it from now on, and elements with a
        memory (`commit(view)`: a contact's approach speed, a stick point) update it."""
        arrays = self.packed_constraints()
        if arrays is not None:
            arrays.commit_angles(k)
        else:
            for m in self.angle_measures:
                m.commit(k)
        if self._remembering:
            view = self.view(k)
            for element in self._remembering:
                element.commit(view)

    def begin(self, k: Kin) -> None:
        """Start of an analysis at state `k`: elements with a memory of where they began
        (`begin(view)`: a joint friction's stick anchor) take it from there."""
        view = self.view(k)
        for element in self._remembering:
            if hasattr(element, "begin"):
                element.begin(view)

    def saddle_pattern(self):
        """Sparsity of [[M, phi_q^T], [phi_q, 0]], from a generic state (found once)."""
        if self._pattern is None:
            self._pattern = known_pattern(self)
        return self._pattern

    def mass(self, k: Kin) -> np.ndarray:
        """Mass matrix M (nq, nq): m I for r; 4 G^T J' G (+ a p p^T term fixing |p|) for p."""
        out = np.zeros((self.nq, self.nq))
        kernels.mass_matrix(k.x, self.masses, self.inertia, self.pscale, out)
        for a in self.flexible:
            out[a.block(self.nb)] += a.mass(k)
        return out

    def mass_times(self, k: Kin, x: np.ndarray) -> np.ndarray:
        """M(q) x without forming M (nq,)."""
        out = np.empty(self.nq)
        if self.nz:
            return self.mass(k) @ x
        kernels.mass_times(k.x, self.masses, self.inertia, self.pscale, x, out)
        return out

    def wrenches(
        self, k: Kin, lam: np.ndarray | None = None, skip=(), jac: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Forces F and torques N (nb+1, 3) of the active force elements (but those whose
        id is in `skip`), global axes, through the cm; `lam` (the multipliers of the
        iterate) for elements that depend on joint reactions (joint friction), `jac` its
        phi_q when known."""
        if not self.elements:
            return self._no_wrench, self._no_wrench
        F = np.zeros((self.nb + 1, 3))
        N = np.zeros((self.nb + 1, 3))
        for group in self._groups:  # one call per element type (mechlib.elements.groups)
            group.apply(k.x, k.xd, skip, F, N)
        view = StateView(self, k, lam, jac, memo=True)  # one state for all elements
        for element in self._singles:
            if element.active and not (skip and id(element) in skip):
                element.apply(view, F, N)
        return F, N

    def forces(
        self,
        k: Kin,
        *,
        inertia: bool = True,
        lam: np.ndarray | None = None,
        skip=(),
        jac: np.ndarray | None = None,
    ) -> np.ndarray:
        """Q (nq,): gravity, elements and modal bodies (but those whose id is in `skip`)
        and, with `inertia`, the quadratic velocity terms (`lam`, `jac`: see `wrenches`)."""
        F, N = self.wrenches(k, lam, skip, jac)
        out = np.zeros(self.nq)
        kernels.body_forces(k.x, k.xd, self.masses, self.inertia, self.gravity, F, N, inertia, out)
        for a in self.flexible:
            if skip and id(a) in skip:
                continue
            stiff = a.body.component.geometric is not None
            loads = self.node_loads(k, lam, a) if stiff else None
            out[a.columns(self.nb)] += a.forces(k, self.gravity, inertia, loads)
        return out

    def node_loads(self, k: Kin, lam: np.ndarray | None, a) -> np.ndarray | None:
        """The loads (k, 6) on modal body `a` at its kept nodes from the weld multipliers
        among `lam` (the active rows), None when no multipliers are known."""
        if lam is None or self._welds is None or len(lam) != self.active.size:
            return None
        welds, first = self._welds
        full = np.zeros(len(self._all_labels))
        full[self.active] = lam
        return welds.node_loads(k, full[first : first + welds.size], a)

    def stiffening_coupling(self, k: Kin, lam: np.ndarray) -> np.ndarray | None:
        """dQ/dlam (nq, m) of the geometric stiffening loaded by the node loads (the weld
        multipliers among `lam`, the active rows), None without such a body: Q_zeta =
        -K_G(node loads) zeta, the node loads linear in the multipliers."""
        if self._welds is None or len(lam) != self.active.size:
            return None
        welds, first = self._welds
        out: np.ndarray | None = None
        for a in self.flexible:
            geometric = a.body.component.geometric
            if geometric is None:
                continue
            if out is None:
                out = np.zeros((self.nq, len(lam)))
            block = np.zeros((a.body.n, len(a.nodes), 6))
            weld_coupling(a.body.nodal, k.z[a.modes], welds.load_maps(k, a), block)
            start, nodes = welds.rows_of(a)
            column = np.full(len(self._all_labels), -1)  # of each equation among lam
            column[self.active] = np.arange(self.active.size)
            at = column[first + start + np.arange(6 * len(nodes))]
            modal = 7 * self.nb + a.offset + np.arange(a.body.n)
            out[np.ix_(modal, at[at >= 0])] += block.reshape(a.body.n, -1)[:, at >= 0]
        return out

    def generalized(self, k: Kin, F: np.ndarray, N: np.ndarray) -> np.ndarray:
        """Q (nq,) of forces F and torques N (nb+1, 3) alone (no gravity, no inertia)."""
        out = np.zeros(self.nq)
        kernels.body_forces(k.x, k.xd, self.masses, self.inertia, _NO_GRAVITY, F, N, False, out)
        return out
