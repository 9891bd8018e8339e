"""Which force elements a forward-difference column of the tangent can change.

A column perturbs one coordinate of q (or qd): of one body, or a modal coordinate. An
element that knows the bodies its force depends on (`state_bodies()`: the body indices
whose positions and rates it reads, and it reads no modal coordinate; None or no such
method: unknown) is left out of the columns of every other body: its force is the same at
the base and at the perturbed state. So are contacts and seals (their two bodies), springs,
torsion springs, dampers, bushings and cable loops (the bodies they join), and point forces
and torques (their body, their frame's body and the bodies their value's measures read).
The others are evaluated in every column: joint friction (it reads the multipliers),
elements with internal states, and a load whose value reads a motion's effort. A modal
coordinate moves no body: its columns leave out every element with known bodies and the
other modal bodies; a modal body's forces (inertia, elastic, gravity, stiffening) are left out
of the columns of the bodies they do not read (`flexible_bodies`). A column that leaves out
every element and every modal body, of a body without mass and inertia (a flexible body's
node body that nothing but joints reads), is exactly zero (`inert`): what remains of Q is
each rigid body's own gravity and velocity terms, of which the perturbed body's are zero
(m g and its inertia terms with m = 0, J = 0) and the others' are the same numbers at the
base and the perturbed state; it is not evaluated. Shared by
the static stiffness (mechlib.solvers.static.balance) and the dynamic tangent
(mechlib.solvers.genalpha.integrator).

`JacobianClasses` (the static stiffness): a column of body b changes only the constraint
Jacobian's rows of the equations that touch b. Bodies that share no equation are perturbed
together in one Jacobian evaluation (a colouring of the bodies); each column takes that
evaluation's rows of its own body's equations and the base Jacobian's others: the Jacobian
the column's own evaluation gives, entry for entry, from nq / (coordinates per body) times
fewer evaluations. The element forces are differenced column by column as before.
"""

from __future__ import annotations

import numpy as np

from mechlib.system.system import System

__all__ = ["ColumnSkips", "JacobianClasses", "element_bodies", "flexible_bodies"]


def element_bodies(element) -> frozenset[int] | None:
    """The body indices (ground harmless) an element's force depends on; None: unknown."""
    bodies = getattr(element, "state_bodies", None)
    found = bodies() if bodies is not None else None
    return None if found is None else frozenset(int(b) for b in found)


class ColumnSkips:
    """Per column of q: the ids of the elements its forward difference leaves out (those in
    `always`, e.g. the elements that add their own tangent, and the elements whose force
    depends on other bodies only), and the ids of the modal bodies (`System.flexible`)
    whose forces it cannot change (`flexible_bodies`)."""

    def __init__(self, system: System, always: set[int] | frozenset[int] = frozenset()):
        known = [(id(e), b) for e in system.elements if (b := element_bodies(e)) is not None]
        modal = [(id(a), flexible_bodies(a)) for a in system.flexible]
        self._per_body = system.per_body
        self._rigid = system.per_body * system.nb
        self._of_body = {
            b: frozenset({i for i, bodies in known + modal if b not in bodies} | set(always))
            for b in range(system.nb)
        }
        every = {i for i, _ in known} | set(always)
        self._modal_ends = []  # (last modal index + 1, key) per modal body
        for n, a in enumerate(system.flexible):
            others = {i for i, _ in modal if i != id(a)}
            self._of_body[-1 - n] = frozenset(every | others)
            self._modal_ends.append((a.offset + a.body.n, -1 - n))
        self._of_body.setdefault(-1, frozenset(every))  # no modal body: no such column
        self._inert = _inert_bodies(system, self._of_body)

    def body(self, column: int) -> int:
        """The body whose coordinate `column` is; -1 - n for a modal coordinate of the
        n-th modal body."""
        if column < self._rigid:
            return column // self._per_body
        modal = column - self._rigid
        return next(key for end, key in self._modal_ends if modal < end)

    def skip(self, body: int) -> frozenset[int]:
        """The ids a column of `body` (-1 - n: of the n-th modal body's modes) leaves out."""
        return self._of_body[body]

    def inert(self, body: int) -> bool:
        """The columns of `body` are exactly zero (module docstring): no mass, no inertia,
        every element and modal body left out."""
        return body in self._inert


def _inert_bodies(system: System, of_body: dict[int, frozenset[int]]) -> frozenset[int]:
    """The bodies whose forward-difference columns are exactly zero (`ColumnSkips.inert`):
    rigid bodies of 7 coordinates (System.forces' own kernel) with zero mass and inertia
    whose columns leave out every element and every modal body."""
    if system.per_body != 7:
        return frozenset()
    everything = {id(e) for e in system.elements} | {id(a) for a in system.flexible}
    inertia = np.asarray(system.inertia).reshape(system.nb, -1)
    return frozenset(
        b
        for b in range(system.nb)
        if system.masses[b] == 0.0 and not inertia[b].any() and everything <= of_body[b]
    )


def flexible_bodies(attached) -> frozenset[int]:
    """The bodies a modal body's forces read besides its own modes: its frame, and with
    geometric stiffening its node bodies (the node loads are read in the nodes' axes)."""
    nodes = attached.nodes if attached.body.component.geometric is not None else ()
    return frozenset({attached.frame, *nodes})


class JacobianClasses:
    """Bodies whose forward-difference columns share one evaluation of the constraint
    Jacobian (module docstring): `classes`, tuples of bodies no equation joins, and
    `rows[b]`, the indices of the (active) equations that touch body b. `of(system)` is
    None with modal coordinates or where no two bodies can share."""

    def __init__(self, classes: list[tuple[int, ...]], rows: dict[int, np.ndarray]):
        self.classes, self.rows = classes, rows

    @classmethod
    def of(cls, system: System) -> JacobianClasses | None:
        nb, per_body = system.nb, system.per_body
        if system.nz or nb < 2:
            return None
        touched: dict[int, list[int]] = {b: [] for b in range(nb)}
        joined: list[set[int]] = [{b} for b in range(nb)]
        for row, nonzero in enumerate(_jacobian_pattern(system)):
            bodies = {int(c) // per_body for c in np.flatnonzero(nonzero)} & set(range(nb))
            for b in bodies:
                touched[b].append(row)
                joined[b] |= bodies
        classes: list[tuple[int, ...]] = []
        for b in sorted(range(nb), key=lambda b: (-len(joined[b]), b)):
            free = next((n for n, c in enumerate(classes) if not joined[b] & set(c)), None)
            if free is None:
                classes.append((b,))
            else:
                classes[free] += (b,)
        if len(classes) == nb:
            return None
        rows = {b: np.array(found, dtype=int) for b, found in touched.items()}
        return cls([tuple(sorted(c)) for c in classes], rows)


def _jacobian_pattern(system: System) -> np.ndarray:
    """The structural nonzeros of phi_q (m, nq) of the current equations: nonzero at either
    of two generic poses (the design pose disturbed at random, as SaddlePattern)."""
    rng = np.random.default_rng(7)
    found = None
    for _ in range(2):
        q = system.design_q() + 0.1 * rng.standard_normal(system.nq)
        nonzero = system.phi_q(system.kin(q, None, 0.0)) != 0.0
        found = nonzero if found is None else found | nonzero
    assert found is not None
    return found
