"""A system's force elements packed by type for the compiled kernels: the generalized-alpha
Newton loop (step by step and whole runs) and the dense rows. The one packer of compiled
element loads.

`CompiledForces.of(system)` packs the active force elements that have a compiled form, each
type into its own arrays (the design rule: elements grouped by type, one loop per type):
- linear springs (tension-only too): mechlib.elements.groups.springs_wrench;
- linear torsion springs, and rotational dampers as torsion springs of no stiffness (the same
  law, moment = damping * omega): groups.torsion_springs_wrench;
- joint friction of revolute and cylindrical joints that slide (not stuck, not locked):
  mechlib.elements.friction_kernel.rotation_friction_wrench, whose regularised law is
  mechlib.elements.regularize.coulomb_factor, the one the Python path and Exudyn's bench
  model call;
- servo-actuators of the `valve` fidelity, active or not (their states advance either way),
  with their element states: mechlib.elements.hydraulics.valve_group;
- contacts of a primitive geometry (sphere on plane, ball in socket, pin in hole), with a
  clearance joint's wear work as its element state: mechlib.elements.contact.group. Their
  tangent stays the elements' own (Contact.tangent, re-evaluated at each refactorisation:
  `rest` is `args` without them, for the differenced rest); their memory is committed on
  each accepted state by one compiled rule (mechlib.elements.contact.memory), in Python
  (Contact.commit) or in the compiled whole run (mechlib.solvers.genalpha.run).
It gives None when an active element has none (a table law, a profile contact, a point
force...) or element states belong to another element, or a clearance joint's wear states
come with actuators' states: the caller then keeps the Python path. The
kernels take the packed arrays as one tuple (`args`); `element_wrenches` adds every group's
loads at element states z, `advance_states` advances those states over a step,
`element_forces` gives the loads' generalized forces and `element_tangent` (K, C) =
-(dQ/dq, dQ/dqd) by forward differences with the step of the Python path's tangent
(mechlib.solvers.genalpha.integrator), through `differenced_forces`, the one column
differencer of the compiled tangents (the Python steps' applied_tangent takes it too, with
gravity and the velocity terms).

Adding a group: pack its arrays in `__init__`, append them to `args` (and to `no_forces`),
call its kernel in `element_wrenches` (and `advance_states` for its states); the solvers
need nothing else.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.differences import fd_step
from mechlib.core.jit import KERNEL, njit
from mechlib.elements import friction_kernel
from mechlib.elements.contact import group as contact_group
from mechlib.elements.contact.element import Contact
from mechlib.elements.contact.group import advance_wear, contacts_rates, contacts_wrench
from mechlib.elements.contact.memory import MEMORY
from mechlib.elements.damper import RotationalDamper
from mechlib.elements.forces import Spring, TorsionSpring
from mechlib.elements.friction import JointFriction
from mechlib.elements.groups import (
    spring_rows,
    springs_wrench,
    torsion_rows,
    torsion_springs_wrench,
)
from mechlib.elements.hydraulics.actuator import ServoActuator
from mechlib.elements.hydraulics.valve_group import (
    VALVE_FLOATS,
    VALVE_INTS,
    advance_valves,
    refresh_valves,
    valve_arrays,
    valves_rates,
    valves_wrench,
)
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics.kernels import angle_rate, body_forces

__all__ = [
    "ROW_COUNT",
    "CompiledForces",
    "advance_states",
    "any_elements",
    "applied_forces",
    "differenced_forces",
    "element_forces",
    "element_rates",
    "element_tangent",
    "element_wrenches",
    "no_forces",
    "slip_rates",
    "slipping_on",
    "update_references",
]

MAX_ROWS = 6  # equations of a friction joint carrying its reaction (a revolute has 5)
ROW_COUNT = friction_kernel.INTS  # a packed friction's ints: the kernel's, row count, rows
_F_INTS = friction_kernel.INTS + 1 + MAX_ROWS
_NO_JAC, _NO_LAM, _NO_ROWS = np.zeros((0, 0)), np.zeros(0), np.zeros(0, dtype=np.int64)


class CompiledForces:
    """The packed groups of a system's active force elements (`args`, the kernels' tuple),
    the frictions among them (slip rates read back after a compiled run), whether any
    friction is loaded by its joint's reaction (`reactions`) and the coordinates the
    elements act on (`columns`, for the tangent and the iteration matrix's pattern); `rest`
    the packed elements but the contacts, which give their own tangent, and `rest_columns`
    the coordinates those act on (the differenced tangent's columns)."""

    def __init__(self, system, springs, torsions, frictions, actuators=(), contacts=()) -> None:
        self.frictions, self.actuators, self.contacts = frictions, list(actuators), list(contacts)
        self.reactions = any(f.mu != 0.0 for f in frictions)
        position = {id(m): j for j, m in enumerate(system.angle_measures)}
        spring_i, spring_f = spring_rows(springs)
        constants = [  # a damper: a torsion spring of no stiffness
            e.linear_constants if isinstance(e, TorsionSpring) else (0.0, e.damping, 0.0, 0.0)
            for e in torsions
        ]
        torsion_i, torsion_f = torsion_rows(torsions, constants)
        refs = [position[id(e._m)] for e in torsions]
        bodies = {int(b) for b in (*spring_i[:, :2].ravel(), *torsion_i.ravel())}
        fric_i = np.zeros((len(frictions), _F_INTS), dtype=np.int64)
        fric_f, fric_v = [], []
        for i, f in enumerate(frictions):
            m, ints, floats = f._compiled
            fric_i[i, : friction_kernel.INTS] = ints
            sign = 1.0
            if f.mu != 0.0:
                rows, body, sign = system.joint_force_rows(f.joint)
                fric_i[i, friction_kernel.INTS - 1] = body
                fric_i[i, friction_kernel.INTS] = len(rows)
                fric_i[i, friction_kernel.INTS + 1 : friction_kernel.INTS + 1 + len(rows)] = rows
            fric_f.append(floats)
            fric_v.append([sign, m.reference, f.v_threshold, f.impending])
            refs.append(position[id(m)])
            bodies |= {int(ints[0]), int(ints[1]), m.bi, m.bj}
        for a in self.actuators:
            bodies |= {a._geometry[0], a._geometry[2]}
        rest_bodies = set(bodies)
        for c in self.contacts:
            bodies |= set(c.body_pair())
        slices = system.states.slices
        wear = [slices[id(c)].start if id(c) in slices else -1 for c in self.contacts]
        starts = [system.states.slices[id(a)].start for a in self.actuators]
        valve_i, valve_f = valve_arrays(self.actuators, starts)
        nb = system.nb
        self.columns, self.rest_columns = (
            np.array([7 * b + c for b in sorted(found) if b < nb for c in range(7)], np.int64)
            for found in (bodies, rest_bodies)
        )
        self.args = (
            spring_i,
            spring_f,
            torsion_i,
            torsion_f,
            np.array([system.angle_measures[j].reference for j in refs[: len(torsions)]]),
            fric_i,
            np.array(fric_f, dtype=float).reshape(-1, friction_kernel.FLOATS),
            np.array(fric_v, dtype=float).reshape(-1, friction_kernel.VARYING),
            np.array(refs, dtype=np.int64),
            np.ones(max(len(springs), len(torsions)), dtype=np.bool_),  # the groups' `on`
            valve_i,
            valve_f,
            *contact_group.contact_arrays(self.contacts, wear),
        )
        self.rest = (*self.args[:12], *(a[:0] for a in self.args[12:]))

    @classmethod
    def of(cls, system) -> CompiledForces | None:
        """The system's active elements packed, or None when one of them has no compiled
        form (or a friction sticks: its stick equation and release stay in Python) or
        element states belong to elements not packed."""
        springs, torsions, frictions, actuators, contacts = [], [], [], [], []
        for e in system.elements:
            kind = type(e)
            if kind is ServoActuator and e.fidelity == "valve":
                actuators.append(e)
                continue
            if not e.active:
                continue
            if kind is Spring and e.law is None:
                springs.append(e)
            elif (kind is TorsionSpring and e.law is None) or kind is RotationalDamper:
                torsions.append(e)
            elif kind is JointFriction and e._compiled is not None and not e.stuck:
                if e._compiled[1].size and not e.locked:  # a locked joint's friction is off
                    if e.mu != 0.0 and len(system.joint_force_rows(e.joint)[0]) > MAX_ROWS:
                        return None
                    frictions.append(e)
            elif isinstance(e, Contact) and contact_group.packable(e):
                contacts.append(e)
            else:
                return None
        wear = sum(id(c) in system.states.slices for c in contacts)
        if len(system.states.owners) != len(actuators) + wear or (wear and actuators):
            return None
        return cls(system, springs, torsions, frictions, actuators, contacts)

    @staticmethod
    def switches(system) -> tuple:
        """What `of` depends on beyond the bound system: the active equations and each
        element's active, stuck and locked flags (packed anew when they change)."""
        flags = (
            (e.active, getattr(e, "stuck", False), getattr(e, "locked", False))
            for e in system.elements
        )
        return (id(getattr(system, "active", None)), *flags)

    @property
    def empty(self) -> bool:
        return not self.columns.size

    def refresh(self, system, t: float | None = None) -> None:
        """The values that move between steps: the angles' unwrapping references (rad),
        the frictions' impending slip directions, the actuators' on flags and, with a time
        t (s), their stroke demands at t."""
        refresh_valves(self.actuators, self.args[10], self.args[11], t)
        if self.contacts:
            contact_group.refresh_contacts(self.contacts, self.args[12:19])
        torsion_refs, varying, index = self.args[4], self.args[7], self.args[8]
        measures = system.angle_measures
        nt = torsion_refs.size
        for j in range(nt):
            torsion_refs[j] = measures[index[j]].reference
        for i, f in enumerate(self.frictions):
            varying[i, 1] = measures[index[nt + i]].reference
            varying[i, 3] = f.impending

    def read_back(self, rates: np.ndarray, taken: int, history: tuple) -> None:
        """After a compiled run that took `taken` steps: each friction's slip rates
        (rates[i] = (before, last), rad/s, of the last two accepted states) and its
        impending direction cleared, as JointFriction.commit leaves them; the contacts'
        memories and the approach speeds committed (`history`: contact_group.history)."""
        if not taken:
            return
        contact_group.read_back_contacts(self.contacts, self.args[12:19], history, taken)
        for f, (before, last) in zip(self.frictions, rates):
            f._rate_before, f._rate = float(before), float(last)
            if abs(f._rate) >= f.v_threshold:
                f._impending = 0.0
        varying = self.args[7]
        for i, f in enumerate(self.frictions):
            varying[i, 3] = f._impending

    def start_rates(self) -> np.ndarray:
        """(before, last) slip rates (rad/s) of each friction, as committed."""
        return np.array([[f._rate_before, f._rate] for f in self.frictions]).reshape(-1, 2)


@njit(**KERNEL)
def no_forces():
    """The `args` of a system without packed elements."""
    return (
        np.zeros((0, 3), dtype=np.int64),
        np.zeros((0, 10)),
        np.zeros((0, 2), dtype=np.int64),
        np.zeros((0, 13)),
        np.zeros(0),
        np.zeros((0, _F_INTS), dtype=np.int64),
        np.zeros((0, friction_kernel.FLOATS)),
        np.zeros((0, friction_kernel.VARYING)),
        np.zeros(0, dtype=np.int64),
        np.ones(0, dtype=np.bool_),
        np.zeros((0, VALVE_INTS), dtype=np.int64),
        np.zeros((0, VALVE_FLOATS)),
        np.zeros((0, contact_group.CONTACT_INTS), dtype=np.int64),
        np.zeros((0, contact_group.GEOMETRY)),
        np.zeros((0, contact_group.PARAMETERS)),
        np.zeros((0, contact_group.PARAMETERS)),
        np.zeros((0, contact_group.MOVING)),
        np.zeros((0, 2, 12)),
        np.zeros((0, MEMORY)),
    )


@njit(**KERNEL, inline="always")
def any_elements(forces):
    """Any element is packed (springs, angle elements: torsion springs, dampers,
    frictions; actuators; contacts)."""
    return (
        forces[0].shape[0] > 0
        or forces[8].shape[0] > 0
        or forces[10].shape[0] > 0
        or forces[12].shape[0] > 0
    )


@njit(**KERNEL)
def update_references(forces, refs_all):
    """The angle elements' unwrapping references (rad) from all of the system's angle
    measures' (`refs_all`, in the order of system.angle_measures)."""
    torsion_i, torsion_refs, fric_v, index = forces[2], forces[4], forces[7], forces[8]
    nt = torsion_i.shape[0]
    for j in range(nt):
        torsion_refs[j] = refs_all[index[j]]
    for j in range(fric_v.shape[0]):
        fric_v[j, 1] = refs_all[index[nt + j]]


@njit(**KERNEL)
def element_wrenches(x, xd, z, forces, rows, active, lam, F, N):
    """F, N (nb+1, 3) = the loads of the packed elements at the state x, xd (nb+1, 7) with
    element states z; `rows`, `active`: the constraint rows' blocks and active rows
    (mechlib.kinematics.constraint_arrays.unpacked_rows) and `lam` the multipliers, read by
    the frictions loaded by their joint's reaction."""
    spring_i, spring_f, torsion_i, torsion_f, torsion_refs = forces[:5]
    fric_i, fric_f, fric_v, on = forces[5], forces[6], forces[7], forces[9]
    F[:] = 0.0
    N[:] = 0.0
    if forces[10].shape[0]:
        valves_wrench(x, xd, z, forces[10], forces[11], F, N)
    if spring_i.shape[0]:
        springs_wrench(x, xd, spring_i, spring_f, on, F, N)
    if torsion_i.shape[0]:
        torsion_springs_wrench(x, xd, torsion_i, torsion_f, torsion_refs, on, N)
    if forces[12].shape[0]:
        contacts_wrench(
            x, xd, forces[12], forces[13], forces[14], forces[15], forces[16], forces[17], F, N
        )
    k = friction_kernel.INTS
    for i in range(fric_i.shape[0]):
        count = fric_i[i, k]
        if count == 0:  # the preload alone: no reaction to read
            friction_kernel.rotation_friction_wrench(
                x, xd, _NO_JAC, _NO_LAM, _NO_ROWS, fric_i[i, :k], fric_f[i], fric_v[i], N
            )
            continue
        jac, values = np.empty((count, rows.shape[1])), np.empty(count)
        for r in range(count):
            row = fric_i[i, k + 1 + r]
            jac[r] = rows[active[row]]
            values[r] = lam[row]
        friction_kernel.rotation_friction_wrench(
            x, xd, jac, values, np.arange(count), fric_i[i, :k], fric_f[i], fric_v[i], N
        )


@njit(**KERNEL)
def advance_states(x, xd, z0, f0, h, forces, z):
    """The packed elements' states over a step h (s) from z0 (rates f0) to the state
    x, xd, in place in z (the actuators': valve_group.advance_valves)."""
    if forces[10].shape[0]:
        advance_valves(x, xd, z0, f0, h, forces[10], forces[11], z)
    if forces[12].shape[0]:
        advance_wear(
            x, xd, z0, f0, h, forces[12], forces[13], forces[14], forces[15], forces[16], z
        )


@njit(**KERNEL)
def element_forces(x, xd, z, forces, masses, inertia, rows, active, lam, out):
    """out (nq,) = the generalized forces of the packed elements alone (no gravity, no
    velocity terms) at x, xd (`element_wrenches`' arguments)."""
    applied_forces(x, xd, z, forces, masses, inertia, np.zeros(3), False, rows, active, lam, out)


@njit(**KERNEL)
def applied_forces(x, xd, z, forces, masses, inertia, gravity, body_terms, rows, active, lam,
                   out):  # fmt: skip
    """out (nq,) = the generalized forces of the packed elements at x, xd with element
    states z, and with `body_terms` gravity `gravity` (m/s^2) and the bodies' quadratic
    velocity terms (System.forces)."""
    F, N = np.empty((x.shape[0], 3)), np.empty((x.shape[0], 3))
    element_wrenches(x, xd, z, forces, rows, active, lam, F, N)
    body_forces(x, xd, masses, inertia, gravity, F, N, body_terms, out)


@njit(**KERNEL)
def element_tangent(q, qd, z, forces, columns, masses, inertia, rows, active, lam, K, C, moved_z):
    """K = -dQ/dq and C = -dQ/dqd (nq, nq, zero outside `columns`) of the packed elements
    at (q, qd) and element states z, by forward differences of step 1e-7 max(1, |q_j|) (as
    the Python path's tangent, mechlib.solvers.genalpha.integrator.Integrator.
    _differenced_tangent). `moved_z` = (z0, f0, h, zp): with element states, z is the
    trial advanced at (q, qd) over the step h (s) from z0 (rates f0), and at each moved
    state the states are advanced again from z into zp (the oil columns are a stiffness
    only through their pressures); without (z empty) they are held."""
    differenced_forces(q, qd, z, forces, columns, masses, inertia, np.zeros(3), False, rows,
                       active, lam, moved_z, None, K, C)  # fmt: skip


@njit(**KERNEL)
def differenced_forces(q, qd, z, forces, columns, masses, inertia, gravity, body_terms, rows,
                       active, lam, moved_z, anew, K, C):  # fmt: skip
    """K = -dQ/dq and C = -dQ/dqd (nq, nq, zero outside `columns`) of `applied_forces` at
    (q, qd), by forward differences of step `fd_step` (mechlib.core.differences): the one
    column differencer of the compiled tangents. `moved_z` as `element_tangent`'s; `anew`
    None (the constraint rows `rows` held at every moved state) or (ints, floats,
    functions, refs, full, moved_rows) to evaluate the rows anew at each moved position
    (a friction loaded by its joint's reaction; the velocity columns keep `rows`)."""
    nq = q.shape[0]
    nb = nq // 7
    K[:] = 0.0
    C[:] = 0.0
    base, moved = np.empty(nq), np.empty(nq)
    x, xd = ca.state_arrays(q, qd, nb)
    applied_forces(x, xd, z, forces, masses, inertia, gravity, body_terms, rows, active, lam,
                   base)  # fmt: skip
    qp, qdp = q.copy(), qd.copy()
    for j in columns:
        eps = fd_step(q[j])
        qp[j] = q[j] + eps
        x, xd = ca.state_arrays(qp, qd, nb)
        at = rows
        if anew is not None:
            ints, floats, functions, refs, full, moved_rows = anew
            ca.constraint_rows(x, ints, floats, functions, refs, full, moved_rows)
            at = moved_rows
        _moved_forces(x, xd, z, forces, masses, inertia, gravity, body_terms, at, active, lam,
                      moved_z, moved)  # fmt: skip
        for i in range(nq):
            K[i, j] = -(moved[i] - base[i]) / eps
        qp[j] = q[j]
        eps = fd_step(qd[j])
        qdp[j] = qd[j] + eps
        x, xd = ca.state_arrays(q, qdp, nb)
        _moved_forces(x, xd, z, forces, masses, inertia, gravity, body_terms, rows, active, lam,
                      moved_z, moved)  # fmt: skip
        for i in range(nq):
            C[i, j] = -(moved[i] - base[i]) / eps
        qdp[j] = qd[j]


@njit(**KERNEL)
def _moved_forces(x, xd, z, forces, masses, inertia, gravity, body_terms, rows, active, lam,
                  moved_z, out):  # fmt: skip
    """`applied_forces` at a moved state x, xd, the element states advanced there anew
    from z (`element_tangent`'s moved_z) when there are any."""
    if not z.shape[0]:
        applied_forces(x, xd, z, forces, masses, inertia, gravity, body_terms, rows, active,
                       lam, out)  # fmt: skip
        return
    z0, f0, h, zp = moved_z
    zp[:] = z
    advance_states(x, xd, z0, f0, h, forces, zp)
    applied_forces(x, xd, zp, forces, masses, inertia, gravity, body_terms, rows, active, lam,
                   out)  # fmt: skip


@njit(**KERNEL)
def element_rates(x, xd, z, forces, out):
    """out (nz,) = the packed elements' state rates at the state x, xd with element states
    z (the actuators': valve_group.valves_rates)."""
    if forces[10].shape[0]:
        valves_rates(x, xd, z, forces[10], forces[11], out)
    if forces[12].shape[0]:
        contacts_rates(x, xd, forces[12], forces[13], forces[14], forces[15], forces[16], out)


@njit(**KERNEL)
def slip_rates(q, qd, forces, out):
    """out (n,) = the slip rate (rad/s) of each packed friction's joint at (q, qd)."""
    fric_i, fric_f, fric_v = forces[5], forces[6], forces[7]
    x, xd = ca.state_arrays(q, qd, q.shape[0] // 7)
    for i in range(fric_i.shape[0]):
        f = fric_f[i]
        _, out[i] = angle_rate(x, xd, fric_i[i, 2], fric_i[i, 3], f[0:3], f[3:6], fric_v[i, 1])


@njit(**KERNEL)
def slipping_on(before, after, forces):
    """Every packed friction's slip rate (rad/s) keeps its sign from `before` to `after`
    and stays out of the regularised band |rate| < v_threshold: none may stick there
    (mechlib.solvers.stick's tests, JointFriction.may_stick, find nothing to do)."""
    fric_v = forces[7]
    for i in range(before.shape[0]):
        b, a, threshold = before[i], after[i], fric_v[i, 2]
        if not (b * a > 0.0 and min(abs(b), abs(a)) >= threshold and math.isfinite(a)):
            return False
    return True
