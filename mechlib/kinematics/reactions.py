"""Joint reactions and motion efforts from the Lagrange multipliers, for all outputs at once.

The generalised force that the rows of a joint (or motion) put on a body is
-phi_q[rows, body]^T lam[rows]: its first three entries are the force (N, global), the last
four map to the torque about the centre of mass by n = E(p) Q_p / 2 (N*m, global).
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.core.rotation import cross, e_matrix, rotate, rotation_matrix
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics.constraint_arrays import selected_pack

__all__ = [
    "FORCE",
    "TORQUE",
    "Gatherer",
    "effort_series",
    "gather_in_batches",
    "joint_wrench",
    "motion_effort",
    "reaction_series",
]

#: the column names of a reaction's force (N) and torque (N*m) components
FORCE = ("fx", "fy", "fz")
TORQUE = ("tx", "ty", "tz")


class Gatherer:
    """Collects, output by output, the generalised force of some rows on one body."""

    def __init__(self, system, owners: set[str], body: int):
        self.system, self.owners, self.body = system, owners, body
        self.values: list[np.ndarray] = []  # rows (7,) or blocks of rows (n, 7), in order
        self._rows: tuple[int, np.ndarray] | None = None

    def _current_rows(self) -> np.ndarray:
        """Rows of the owners among the active equations (events change them)."""
        active = self.system.active
        if self._rows is None or self._rows[0] != id(active):
            owners = self.system.owners
            self._rows = (
                id(active),
                np.array([i for i, o in enumerate(owners) if o in self.owners], dtype=int),
            )
        return self._rows[1]

    def gather(self, jac: np.ndarray, lam: np.ndarray) -> None:
        rows = self._current_rows()
        if self.body < 0 or len(rows) == 0:
            self.values.append(np.zeros(7))
            return
        block = jac[rows, 7 * self.body : 7 * self.body + 7]
        self.values.append(-(block.T @ lam[rows]))

    def wrench(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Force and torque about the cm (n, 3) given the body's Euler parameters (n, 4)."""
        g = np.concatenate([np.reshape(v, (-1, 7)) for v in self.values] or [np.zeros((0, 7))])
        return g[:, :3], 0.5 * np.einsum("nij,nj->ni", e_matrix(p), g[:, 3:])


def gather_in_batches(system, trajectory, gatherers: list[Gatherer]) -> None:
    """Every recorded row's `Gatherer.gather` for `gatherers` of a packed system
    (mechlib.kinematics.constraint_arrays), in one compiled call per run of rows with the same
    active equations instead of a Jacobian per row in Python: the same products, of only
    the gatherers' own constraint rows (`selected_pack`: a joint's reaction needs its rows,
    not the mechanism's). Leaves the system restored to the last row, as the row loop does."""
    arrays = system.packed_constraints()
    assert arrays is not None, "the caller checks that the system is packed"
    n, i = len(trajectory), 0
    while i < n:
        system.restore_snapshot(trajectory.references[i])
        end = trajectory.same_active(i, n)
        rows = [g._current_rows() for g in gatherers]
        starts = np.cumsum([0] + [len(r) for r in rows])
        rows_of = np.concatenate([np.zeros(0, dtype=np.int64), *rows]).astype(np.int64)
        bodies = np.array([g.body for g in gatherers], dtype=np.int64)
        out = np.empty((end - i, len(gatherers), 7))
        ints, floats = selected_pack(system, np.asarray(system.active, dtype=np.int64)[rows_of])
        m = system.active.size
        lams = np.ascontiguousarray(trajectory.stacked("lam", i, end).reshape(end - i, m))
        gathered_loads(
            np.ascontiguousarray(trajectory.stacked("q", i, end)), lams, ints, floats,
            arrays.references(), rows_of, starts, bodies, out,
        )  # fmt: skip
        for g, gatherer in enumerate(gatherers):
            gatherer.values.append(out[:, g, :])  # a block: not a row at a time
        i = end
    system.restore_snapshot(trajectory.references[n - 1])


@njit(**KERNEL)
def gathered_loads(qs, lams, ints, floats, refs, rows_of, starts, bodies, out):
    """out (n, gatherers, 7): per recorded state (qs (n, nq), lams (n, m)) and gatherer g,
    -phi_q[rows, body g's columns]^T lam[rows] over its active rows
    rows_of[starts[g]:starts[g + 1]] (zeros for a body < 0). (ints, floats): a pack whose
    e-th active row is the Jacobian row of rows_of[e] (`selected_pack`). The Jacobian rows
    read no time function, so none is given."""
    n, nq = qs.shape
    nb = nq // 7
    nall = ca.row_count(ints)
    full = np.empty(nall)
    rows = np.zeros((nall, nq + 7))
    functions = np.zeros((ints[6], 3))
    packed = ca.unpack(ints, floats)
    x, xd = np.empty((nb + 1, 7)), np.empty((nb + 1, 7))  # once: not a row's allocations
    for i in range(n):
        ca.state_into(qs[i], qs[i], x, xd)
        active, row_bodies = ca.unpacked_rows(x, packed, functions, refs, full, rows)
        for g in range(bodies.shape[0]):
            b = bodies[g]
            out[i, g, :] = 0.0
            if b < 0:
                continue
            for e in range(starts[g], starts[g + 1]):
                r = active[e]
                # a row fills only its bodies' blocks (constraint_rows): elsewhere it is 0
                if row_bodies[r, 0] != ca.DENSE_ROW and not _touches(row_bodies[r], b):
                    continue
                w = lams[i, rows_of[e]]
                for c in range(7):
                    out[i, g, c] -= rows[r, 7 * b + c] * w


@njit(**KERNEL)
def _touches(bodies, b):
    """Whether a row's recorded bodies include body b."""
    for c in range(bodies.shape[0]):  # noqa: SIM110 -- numba compiles no generator in any()
        if bodies[c] == b:
            return True
    return False


def _body_states(trajectory, body: int, nb: int) -> np.ndarray:
    if body == nb or body < 0:
        return np.tile([1.0, 0.0, 0.0, 0.0], (len(trajectory), 1))
    return trajectory.stacked("q")[:, 7 * body + 3 : 7 * body + 7]


def reaction_series(
    system,
    trajectory,
    gatherer: Gatherer,
    point_local: np.ndarray,
    sign: float,
    axes: np.ndarray | None,
) -> dict[str, np.ndarray]:
    """fx fy fz tx ty tz f t of a joint reaction (torque about the joint point) in `axes`
    (n, 3, 3) columns, or ground axes when None."""
    p = _body_states(trajectory, gatherer.body, system.nb)
    force, torque_cm = gatherer.wrench(p)
    torque = sign * (torque_cm - cross(rotate(p, point_local), force))
    force = sign * force
    if axes is not None:
        force = np.einsum("nji,nj->ni", axes, force)
        torque = np.einsum("nji,nj->ni", axes, torque)
    out = dict(zip(FORCE, force.T)) | dict(zip(TORQUE, torque.T))
    # hypot, not the root of the squares: a component above 1e154 must not overflow
    out["f"], out["t"] = np.hypot.reduce(force, axis=1), np.hypot.reduce(torque, axis=1)
    return out


def effort_series(
    system, trajectory, gatherer: Gatherer, measure, sign: float
) -> dict[str, np.ndarray]:
    """Torque (angle) or force (travel) along the joint axis fixed in body 2."""
    p = _body_states(trajectory, gatherer.body, system.nb)
    force, torque = gatherer.wrench(p)
    p2 = _body_states(trajectory, measure.bj, system.nb)
    axis = np.einsum("nij,j->ni", rotation_matrix(p2), measure.axis_local)
    along = torque if measure.kind == "angle" else force
    return {"value": sign * np.einsum("ni,ni->n", along, axis)}


def joint_wrench(
    system, k, jac: np.ndarray, lam: np.ndarray, joint: str
) -> tuple[np.ndarray, np.ndarray]:
    """Force and torque about the joint point on body 1 of `joint` (its own rows only),
    global axes, at one state: what elements that load a joint by its reaction use."""
    j = system.mechanism.joints[joint]
    sign, body_name = (1.0, j.body1) if j.body1 != "ground" else (-1.0, j.body2)
    b, local = system.body_point(body_name, j.at)
    gatherer = Gatherer(system, {joint}, b)
    gatherer.gather(jac, lam)
    p = k.p[b][None, :]
    force, torque_cm = gatherer.wrench(p)
    torque = torque_cm - cross(rotate(p, local), force)
    return sign * force[0], sign * torque[0]


def motion_effort(system, k, jac: np.ndarray, lam: np.ndarray, motion: str) -> float:
    """The torque (N*m) or force (N) a motion applies to body 1 of its joint along the
    joint coordinate, at one state (what `effort(motion)` in expressions reads)."""
    measure = next(c for c in system.coordinates if c.owner == motion).terms[0][1]
    body, sign = (measure.bi, 1.0) if measure.bi != system.nb else (measure.bj, -1.0)
    gatherer = Gatherer(system, {motion}, body)
    gatherer.gather(jac, lam)
    force, torque = gatherer.wrench(k.p[body][None, :])
    axis = rotation_matrix(k.p[measure.bj]) @ measure.axis_local
    along = torque if measure.kind == "angle" else force
    return float(sign * along[0] @ axis)
