"""Planar mechanisms: 3 coordinates per body, the 3-D model reduced to its plane.

Body b moves in the plane spanned by (e1, e2) with normal n = e1 x e2; its planar
coordinates are ``q_b = (x, y, phi)``: the centre of mass at ``c_b + x e1 + y e2`` (c_b its
design offset along n, m) and the Euler parameters ``p = (cos(phi/2), sin(phi/2) n)`` (a
rotation by phi, rad, about n). The 3-D `System` (`space`) evaluates everything in its own
coordinates at the mapped state, and the planar system projects through the Jacobian
T = d(q3)/d(q): ``phi_q = phi_q3 T``, ``Q = T^T Q3``, ``M = T^T M3 T = diag(m, m, n.J n)``
(constant: the reference point is the centre of mass), ``gamma = gamma3 - phi_q3 Td qd``
with ``Td qd = (0, -p phi_d^2 / 4)``; ``T^T M3 Td qd`` vanishes (G(p) p = 0, p . dp/dphi = 0).
The equations identically satisfied in the plane (the normalisation, the out-of-plane
rows of the joints: their reduced Jacobian is zero) are left out, so a planar four-bar
has 8 equations on 9 coordinates and no redundant one (3-D: 20 joint equations and 3
normalisations on 21 coordinates, 3 of them redundant).
Nikravesh, Planar Multibody Dynamics, 2nd ed. (2018), body-coordinate formulation.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np

from mechlib.core.outcome import ModelError
from mechlib.kinematics.kin import GROUND_Q, Kin
from mechlib.linalg.sparse_rows import SparseRows
from mechlib.model.analysis import Trajectory
from mechlib.model.mechanism import Mechanism
from mechlib.model.plane import contact_problem, joint_problem, normal_name, plane_axes
from mechlib.system.known_patterns import known_pattern
from mechlib.system.planar_kernels import planar_reduce, planar_state
from mechlib.system.sparse_jacobian import planar_reduced
from mechlib.system.system import System

if TYPE_CHECKING:
    from mechlib.linalg.factor import SaddlePattern

__all__ = ["PlanarSystem", "joint_problems", "make_system", "out_of_plane_rows"]

_IN_PLANE = 1e-10  # |reduced Jacobian row| below this (relative): identically satisfied


def make_system(mechanism: Mechanism) -> System:
    """The numerical form of `mechanism`: planar when it has a `plane`, else 3-D. A
    `PlanarSystem` offers the `System` interface in planar coordinates (see there). A
    planar mechanism with flexible bodies is the 3-D `System` itself (the planar reduction
    has no modal coordinates), after the same checks that it stays in its plane; the
    redundant equations the plane avoids are left to `out_of_plane_rows`."""
    space = System(mechanism)
    if mechanism.plane is None:
        return space
    if space.flexible:
        problems = _plane_problems(space, mechanism.plane)
        problems += [
            (e.name, f"contact {e.name}: {p[1]}")
            for e in space.elements
            if hasattr(e, "geometry")
            and (p := contact_problem(e.geometry, mechanism.plane)) is not None
        ]
        if problems:
            raise ModelError(problems)
        return space
    return cast(System, PlanarSystem(space, mechanism.plane))


def _plane_problems(space: System, plane: str) -> list[tuple[str, str]]:
    """(owner, message) of the joints and the gravity that leave `plane`."""
    problems = joint_problems(space.mechanism, plane)
    if abs(float(space.gravity @ plane_axes(plane)[2])) > 0.0:
        problems.append(
            ("", f"gravity has a component along {normal_name(plane)}, out of plane {plane}")
        )
    return problems


def out_of_plane_rows(system: System, k: Kin) -> set[int]:
    """The equations of a planar mechanism built in 3-D (flexible bodies: `make_system`)
    that in-plane motion satisfies identically at state `k` (in the plane): their
    Jacobian has no component along any body's in-plane motion (the translations along
    e1, e2 and the rotation about n, the planar T). Those the planar formulation leaves
    out, so a redundancy among them is not one of the planar model. Empty for a 3-D
    mechanism or a `PlanarSystem` (it has none)."""
    plane = system.mechanism.plane
    if plane is None or system.per_body != 7:
        return set()
    e1, e2, normal = plane_axes(plane)
    rigid = 7 * system.nb
    dense = system.phi_q_sparse(k).toarray()[:, :rigid]
    reduced = np.empty((dense.shape[0], 3 * system.nb))
    planar_reduce(np.ascontiguousarray(dense), k.x, np.column_stack([e1, e2]), normal, reduced)
    size = np.abs(reduced).max(axis=1)
    scale = max(float(np.abs(dense).max(initial=0.0)), 1.0)
    bodies = set(system.body_names)  # the Euler-parameter normalisations: not the joints'
    idle = np.flatnonzero(size <= _IN_PLANE * scale)
    return {int(i) for i in idle if system.owners[i] not in bodies}


def joint_problems(mechanism: Mechanism, plane: str) -> list[tuple[str, str]]:
    """(joint, message) of the joints that do not keep their bodies in `plane`
    (mechlib.model.plane.joint_problem)."""
    out = []
    for j in mechanism.joints.values():
        problem = joint_problem(j.type, plane, axis=j.axis, axes=j.axes, normal=j.normal)
        if problem is not None:
            out.append((j.name, f"joint {j.name}: {problem[1]}"))
    return out


def _contact_problems(space: System, plane: str) -> list[tuple[str, str]]:
    """(contact, message) of the contacts whose geometry leaves `plane`; the others are
    kept, without their own tangent (it is in 3-D coordinates): the solvers difference
    their forces in planar ones, as the other elements'."""
    out = []
    for e in space.elements:
        if not hasattr(e, "geometry"):
            continue
        problem = contact_problem(e.geometry, plane)
        if problem is not None:
            out.append((e.name, f"contact {e.name}: {problem[1]}"))
        e.own_tangent = False
    return out


class PlanarSystem:
    """The `System` interface in planar coordinates (3 per body, no modal ones): what the
    solvers call is reduced here; everything else (names, rows, events, elements, outputs)
    is the 3-D `space`'s, which the force elements are bound to and which evaluates the
    requests on the trajectory lifted back to 3-D (`in_space`)."""

    per_body = 3
    normalisations = 0  # an angle per body: no Euler-parameter rows

    def __init__(self, space: System, plane: str):
        problems = _plane_problems(space, plane)
        if space.flexible:
            problems.append(("", "flexible bodies need the 3-D model: remove `plane`"))
        problems += _contact_problems(space, plane)
        if problems:
            raise ModelError(problems)
        self.space, self.plane = space, plane
        e1, e2, self.normal = plane_axes(plane)
        self._in = np.column_stack([e1, e2])  # (3, 2): planar -> global directions
        self.nb, self.nz, self.nq = space.nb, 0, 3 * space.nb
        cm = space.cm[:-1]
        self._offset = np.outer(cm @ self.normal, self.normal)  # (nb, 3) along n, fixed
        inertia = np.einsum("i,bij,j->b", self.normal, space.inertia, self.normal)
        self._mass = np.column_stack([space.masses, space.masses, inertia]).ravel()
        self._no_rates = np.zeros(self.nq)
        self._pattern: tuple[np.ndarray, SaddlePattern] | None = None
        self._jacobian: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self._drop_out_of_plane()

    def __getattr__(self, name: str):
        """Whatever the reduction leaves unchanged is the 3-D system's."""
        if name == "space":  # not set yet (copying, unpickling): no recursion
            raise AttributeError(name)
        return getattr(self.space, name)

    def packed_constraints(self) -> None:
        """None: the packed kernels (mechlib.kinematics.constraint_arrays) work in 3-D coordinates,
        not in the planar ones the solvers see here (the 3-D `space` uses them itself)."""
        return None

    # ---- the map to 3-D ---------------------------------------------------------------
    def design_q(self) -> np.ndarray:
        q = np.zeros((self.nb, 3))
        q[:, :2] = self.space.cm[:-1] @ self._in
        return q.ravel()

    def kin(self, q: np.ndarray, qd: np.ndarray | None = None, t: float = 0.0) -> Kin:
        """The 3-D state (Kin) of planar q, qd (3 nb,); without qd, at rest."""
        x = np.empty((self.nb + 1, 7))
        xd = np.zeros((self.nb + 1, 7))
        x[-1] = GROUND_Q
        rates = self._no_rates if qd is None else np.asarray(qd, dtype=float)
        planar_state(np.asarray(q, dtype=float), rates, self._offset, self._in, self.normal, x, xd)
        return Kin(x, xd, t, at_rest=qd is None)

    def state_of(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(q, qd) (3 nb,) of a state `kin` made: phi within (-2 pi, 2 pi] (the same
        Euler parameters as any phi + 4 pi n)."""
        x, xd = k.x[:-1], k.xd[:-1]
        sine, cosine = x[:, 4:] @ self.normal, x[:, 3]
        q = np.column_stack([(x[:, :3] - self._offset) @ self._in, 2.0 * np.arctan2(sine, cosine)])
        rate = 2.0 * (cosine * (xd[:, 4:] @ self.normal) - sine * xd[:, 3])
        qd = np.column_stack([xd[:, :3] @ self._in, rate])
        return q.ravel(), qd.ravel()

    def _dp(self, x: np.ndarray) -> np.ndarray:
        """dp/dphi (nb, 4) of the moving bodies at 3-D positions x (nb+1, 7)."""
        p0, along = x[:-1, 3], x[:-1, 4:] @ self.normal
        return 0.5 * np.column_stack([-along, np.outer(p0, self.normal)])

    def reduce(self, rows: np.ndarray, k: Kin) -> np.ndarray:
        """T^T applied to 3-D generalised forces or Jacobian rows (..., 7 nb) -> (..., 3 nb)."""
        flat = np.ascontiguousarray(rows.reshape(-1, rows.shape[-1]))
        out = np.empty((flat.shape[0], self.nq))
        planar_reduce(flat, k.x, self._in, self.normal, out)
        return out.reshape(rows.shape[:-1] + (self.nq,))

    def _lift_rates(self, k: Kin, qdd: np.ndarray) -> np.ndarray:
        """3-D accelerations (7 nb,) of planar qdd at state k: T qdd + Td qd."""
        qdd = np.asarray(qdd, dtype=float).reshape(self.nb, 3)
        out = np.empty((self.nb, 7))
        out[:, :3] = qdd[:, :2] @ self._in.T
        out[:, 3:] = self._dp(k.x) * qdd[:, 2:3] + self._curvature(k)
        return out.ravel()

    def _curvature(self, k: Kin) -> np.ndarray:
        """Td qd in the Euler-parameter slots (nb, 4): -p phi_d^2 / 4."""
        omega2 = 4.0 * np.einsum("bi,bi->b", k.xd[:-1, 3:], k.xd[:-1, 3:])  # |pd| = |phi_d|/2
        return -0.25 * k.x[:-1, 3:] * omega2[:, None]

    # ---- rows kept ----------------------------------------------------------------------
    def _drop_out_of_plane(self) -> None:
        """Leave out the equations that in-plane motion satisfies identically: zero reduced
        Jacobian at a generic planar state; refused when not satisfied at design."""
        rng = np.random.default_rng(11)
        q = self.design_q() + 0.1 * self.space.length * rng.standard_normal(self.nq)
        jac = self.phi_q_sparse(self.kin(q))
        size = np.zeros(jac.shape[0])
        np.maximum.at(size, jac.rows, np.abs(jac.values))
        idle = np.flatnonzero(size <= _IN_PLANE * max(float(size.max(initial=0.0)), 1.0))
        residual = self.space.phi(self.kin(self.design_q()))[idle]
        off = [i for i, r in zip(idle, residual) if abs(r) > 1e-9 * self.space.length]
        if off:
            raise ModelError(
                [
                    (self.space.owners[i], f"{self.space.labels[i]}: not met in plane {self.plane}")
                    for i in off
                ]
            )
        self.space.drop_rows(idle)

    # ---- what the solvers call ----------------------------------------------------------
    def phi(self, k: Kin) -> np.ndarray:
        return self.space.phi(k)

    def _space_jacobian(self, k: Kin, jac: np.ndarray | None = None) -> np.ndarray:
        """phi_q3 at k's positions: `jac` when given (kept), else the one kept for the same
        positions and rows (gamma asks again at each velocity), else evaluated."""
        kept = self._jacobian
        if (
            jac is None
            and kept is not None
            and kept[0] is self.space.active
            and np.array_equal(kept[1], k.x)
        ):
            return kept[2]
        if jac is None:
            jac = self.space.phi_q(k)
        self._jacobian = (self.space.active, k.x.copy(), jac)
        return jac

    def phi_q(self, k: Kin) -> np.ndarray:
        return self.reduce(self._space_jacobian(k), k)

    def phi_q_sparse(self, k: Kin) -> SparseRows:
        """`phi_q(k)` as its non-zeros, never the dense matrix (the checks of a large model)."""
        return planar_reduced(self.space.phi_q_sparse(k), k.x, self._in, self.normal)

    def phi_and_jacobian(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        phi, jac = self.space.phi_and_jacobian(k)
        return phi, self.reduce(self._space_jacobian(k, jac), k)

    def nu(self, k: Kin) -> np.ndarray:
        return self.space.nu(k)

    def gamma(self, k: Kin) -> np.ndarray:
        curvature = np.zeros((self.nb, 7))
        curvature[:, 3:] = self._curvature(k)
        return self.space.gamma(k) - self._space_jacobian(k) @ curvature.ravel()

    def coordinate_gradient(self, measure, k: Kin) -> np.ndarray:
        """d(measure)/dq (nq,) of a joint angle or travel."""
        return self.reduce(self.space.coordinate_gradient(measure, k), k)

    def body_rates(self, k: Kin, body: int) -> np.ndarray:
        """(6, nq): qd -> the velocity (m/s) and angular velocity (rad/s) of `body`, global."""
        return self.reduce(self.space.body_rates(k, body), k)

    def mass(self, k: Kin) -> np.ndarray:
        return np.diag(self._mass)

    def mass_times(self, k: Kin, x: np.ndarray) -> np.ndarray:
        return self._mass * x

    def forces(self, k: Kin, *, inertia: bool = True, lam=None, skip=(), jac=None) -> np.ndarray:
        """T^T Q3 (`jac`, planar, is not what the 3-D elements read: left out)."""
        return self.reduce(self.space.forces(k, inertia=inertia, lam=lam, skip=skip), k)

    def generalized(self, k: Kin, F: np.ndarray, N: np.ndarray) -> np.ndarray:
        return self.reduce(self.space.generalized(k, F, N), k)

    def reaction_coupling(self, coupling: np.ndarray, k: Kin) -> np.ndarray:
        """dQ/dlam (3-D rows, (7 nb, m)) reduced to (nq, m)."""
        return self.reduce(coupling.T, k).T

    def view(self, k: Kin, lam=None, jac=None):
        return self.space.view(k, lam)

    def body_weights(self, translation: float, rotation: float) -> np.ndarray:
        """Per-body weights (3,): as the 3-D ones, phi counting twice an Euler parameter."""
        return np.array([translation, translation, 2.0 * rotation])

    def cm_positions(self, q: np.ndarray) -> np.ndarray:
        """Centres of mass (nb, 3), m, global."""
        return self.kin(q).r[:-1].copy()

    def cm_forces(self, generalized: np.ndarray) -> np.ndarray:
        """The force parts (nb, 3), N, global, of planar generalised forces (3 nb,)."""
        return generalized[: self.nq].reshape(self.nb, 3)[:, :2] @ self._in.T

    def saddle_pattern(self) -> SaddlePattern:
        """Sparsity of [[M, phi_q^T], [phi_q, 0]] for the current rows (found once each)."""
        if self._pattern is None or self._pattern[0] is not self.space.active:
            self._pattern = (self.space.active, known_pattern(self))
        return self._pattern[1]

    def output_notes(self, reactions: bool) -> list[str]:
        """What a planar solution leaves out of the outputs asked for (`reactions`: joint
        reactions are among them)."""
        if not reactions:
            return []
        n = normal_name(self.plane)
        across = "".join(c for c in "xyz" if c != n)
        return [
            f"planar mechanism (plane {self.plane}): the out-of-plane reaction components "
            f"(f{n}, t{across[0]}, t{across[1]}) are not computed and are reported as 0; "
            "pin moments and forces out of the plane need the 3-D model"
        ]

    # ---- back to 3-D for the outputs ----------------------------------------------------
    def in_space(self, trajectory: Trajectory) -> tuple[System, Trajectory]:
        """The 3-D system and the trajectory in its coordinates (q, qd, qdd in 7 nb; the
        multipliers are those of the same rows)."""
        lifted = Trajectory(at_rest=trajectory.at_rest)
        for i, t in enumerate(trajectory.time):
            k = self.kin(trajectory.q[i], trajectory.qd[i], t)
            lifted.record(
                t,
                k.x[:-1].ravel(),
                k.xd[:-1].ravel(),
                self._lift_rates(k, trajectory.qdd[i]),
                trajectory.lam[i],
                trajectory.references[i],
            )
        return self.space, lifted
