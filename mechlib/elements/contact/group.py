"""The primitive contacts of a system (sphere on plane, ball in socket, pin in hole: a
`kernel()` geometry) as one packed group of the compiled force elements
(mechlib.elements.compiled_forces): their arrays, the values that move between steps and
their wrenches, over the whole group in one kernel call (SI units). The wrench is the
Python path's (Contact.apply): kernels.contact_wrench, or kernels.static_contact_wrench for
a contact with friction in a state at rest (mechlib.elements.regularize.at_rest).

A clearance joint's wear work (its one element state, which no force reads) advances by
the explicit trapezoid of mechlib.elements.states.ElementStates.advance, its rate
F_N |v_t| (W) that of ClearanceJoint.state_rates.

Layout, one row per contact: ints (geometry code, body 1, body 2, law code, friction code,
its wear state's index among the element states, -1: none, 1 when the law remembers its
approach speed); geometry (its 11 parameters); law (its parameters, padded); friction (its
parameters, padded); moving (approach speed (m/s), friction mu_dynamic, slip threshold (m));
anchor (2, 12: the poses of the last accepted state, Contact._anchor); memory (the last
accepted state's, mechlib.elements.contact.memory: Contact._memory).

The compiled whole run commits the accepted states into these arrays (`commit_contacts`,
the rule of Contact.commit), keeps the approach speeds it committed (`history`) and hands
them back to the contacts (`read_back_contacts`); it adds each contact's own tangent
(`contacts_tangent`, Contact.tangent) to the iteration matrix.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.contact.kernels import (
    GAP_SIZE,
    contact_force,
    contact_tangent,
    contact_wrench,
    gap,
    static_contact_wrench,
)
from mechlib.elements.contact.laws import IMPACT
from mechlib.elements.contact.memory import MEMORY, commit_memory

__all__ = [
    "CONTACT_INTS",
    "GEOMETRY",
    "MOVING",
    "PARAMETERS",
    "advance_wear",
    "commit_contacts",
    "contact_arrays",
    "contacts_rates",
    "contacts_tangent",
    "contacts_wrench",
    "history",
    "packable",
    "read_back_contacts",
    "refresh_contacts",
    "runnable",
]

CONTACT_INTS, GEOMETRY, PARAMETERS, MOVING = 7, 11, 5, 3
_STATE, _REMEMBERS = 5, 6
_APPROACH, _MU, _THRESHOLD = 0, 1, 2


def packable(contact) -> bool:
    """A contact the group serves: a primitive geometry (its compiled tangent too)."""
    return getattr(contact, "_kernel", None) is not None


def runnable(contacts: Sequence) -> bool:
    """Contacts a compiled whole run may carry: each with its own tangent (not in a planar
    system) and no impact law's damping ramp moved by an event (Contact.start_from: its
    commit would change the law's parameters)."""
    return all(
        c.has_tangent and not (c._laws[0] == IMPACT and c._laws[1][4] != 0.0) for c in contacts
    )


def contact_arrays(contacts: Sequence, starts: Sequence[int]) -> tuple:
    """(ints, geometry, law, friction, moving, anchor, memory) of the bound `contacts`
    (`starts`: each one's first element state, -1: none); the moving values, anchors and
    memories as `refresh_contacts` sets them."""
    n = len(contacts)
    ints = np.zeros((n, CONTACT_INTS), dtype=np.int64)
    geometry = np.zeros((n, GEOMETRY))
    law, friction = np.zeros((n, PARAMETERS)), np.zeros((n, PARAMETERS))
    for i, c in enumerate(contacts):
        kind, b1, b2, g, law_code, _, friction_code, fp = c._kernel
        ints[i] = (kind, b1, b2, law_code, friction_code, starts[i], int(c.law.remembers))
        geometry[i] = g
        friction[i, : fp.size] = fp
    moving, anchor = np.zeros((n, MOVING)), np.full((n, 2, 12), np.nan)
    arrays = (ints, geometry, law, friction, moving, anchor, np.zeros((n, MEMORY)))
    refresh_contacts(contacts, arrays)
    return arrays


def refresh_contacts(contacts: Sequence, arrays: tuple) -> None:
    """The values the contacts change between steps: the law's parameters (the impact
    ramp's start), the approach speed (m/s), mu and slip threshold (m) of the static
    friction, the anchor poses and the memory of the last accepted state."""
    _, _, law, _, moving, anchor, memory = arrays
    for i, c in enumerate(contacts):
        lp = c._kernel[5]
        law[i, : lp.size] = lp
        moving[i, _APPROACH] = c.approach
        memory[i] = c._memory
        if c.friction is not None:
            mu, poses, threshold = c._static_friction()
            moving[i, _MU], moving[i, _THRESHOLD] = mu, threshold
            anchor[i] = poses


def history(most_steps: int, contacts: int) -> tuple[np.ndarray, np.ndarray]:
    """Room for the (time (s), approach speeds (m/s) of each contact) a compiled run
    commits at each of at most `most_steps` accepted steps (`commit_contacts`)."""
    return np.empty(most_steps), np.empty((most_steps, contacts))


def read_back_contacts(contacts: Sequence, arrays: tuple, kept: tuple, steps: int) -> None:
    """After a compiled run that took `steps` accepted steps: each contact's approach
    speed, memory and anchor are the run's last, its history the approach speeds the run
    committed (`kept`: `history`), as Contact.commit leaves them step by step."""
    if not steps:
        return
    _, _, _, _, moving, anchor, memory = arrays
    times, approaches = kept
    for i, c in enumerate(contacts):
        c.approach = float(moving[i, _APPROACH])
        c._memory = memory[i].copy()
        if c.friction is not None:  # a new array: recorded snapshots keep the old ones
            c._anchor = anchor[i].copy()
        c.extend_history(times[:steps], approaches[:steps, i])


@njit(**KERNEL)
def commit_contacts(x, xd, t, ints, geometry, moving, anchor, memory, kept, step):
    """The accepted state x, xd (nb+1, 7) at time t (s) committed into the packed contacts
    (memory.commit_memory, as Contact.commit): approach speeds, memories, anchors; the
    time and approach speeds kept in row `step` of `kept` (`history`)."""
    times, approaches = kept
    times[step] = t
    for i in range(ints.shape[0]):
        kind, b1, b2, _, friction_code = _codes(ints, i)
        moving[i, _APPROACH] = commit_memory(
            kind, b1, b2, geometry[i], ints[i, _REMEMBERS] != 0, friction_code != 0, x, xd,
            memory[i], moving[i, _APPROACH], anchor[i],
        )[0]  # fmt: skip
        approaches[step, i] = moving[i, _APPROACH]


@njit(**KERNEL)
def contacts_tangent(x, xd, ints, geometry, law, friction, moving, nb, K, C):
    """Add each packed contact's own tangent (kernels.contact_tangent, as Contact.tangent)
    at x, xd (nb+1, 7) to K and C (nq, nq)."""
    for i in range(ints.shape[0]):
        kind, b1, b2, law_code, friction_code = _codes(ints, i)
        contact_tangent(
            kind, b1, b2, geometry[i], law_code, law[i], friction_code, friction[i],
            moving[i, _APPROACH], x, xd, nb, K, C,
        )  # fmt: skip


@njit(**KERNEL)
def _at_rest(xd):
    """No body moves (mechlib.elements.regularize.at_rest)."""
    return not np.any(xd != 0.0)


@njit(**KERNEL)
def _codes(ints, i):
    """(kind, body 1, body 2, law code, friction code) of packed contact i."""
    return ints[i, 0], ints[i, 1], ints[i, 2], ints[i, 3], ints[i, 4]


@njit(**KERNEL)
def contacts_wrench(x, xd, ints, geometry, law, friction, moving, anchor, F, N):
    """Add the loads of the packed contacts at the state x, xd (nb+1, 7) to F and N
    (nb+1, 3), as Contact.apply."""
    rest = ints.shape[0] > 0 and _at_rest(xd)
    for i in range(ints.shape[0]):
        kind, b1, b2, law_code, friction_code = _codes(ints, i)
        approach = moving[i, _APPROACH]
        if friction_code != 0 and rest:
            static_contact_wrench(
                kind, b1, b2, geometry[i], law_code, law[i], friction_code, friction[i],
                approach, x, xd, moving[i, _MU], anchor[i], moving[i, _THRESHOLD], F, N,
            )  # fmt: skip
        else:
            contact_wrench(
                kind, b1, b2, geometry[i], law_code, law[i], friction_code, friction[i],
                approach, x, xd, F, N,
            )  # fmt: skip


@njit(**KERNEL)
def _wear_rate(x, xd, ints, geometry, law, friction, moving, i, rest):
    """F_N |v_t| (W) of contact i at x, xd (0 at rest: no sliding)."""
    if rest:
        return 0.0
    gp, out = np.empty(GAP_SIZE), np.empty(6)
    kind, b1, b2, law_code, friction_code = _codes(ints, i)
    gap(kind, x, xd, b1, b2, geometry[i], gp)
    contact_force(law_code, law[i], friction_code, friction[i], geometry[i, 9], gp,
                  moving[i, _APPROACH], out)  # fmt: skip
    return out[0] * out[5]


@njit(**KERNEL)
def contacts_rates(x, xd, ints, geometry, law, friction, moving, out):
    """out[state] = the wear work rate (W) of each contact with a wear state."""
    rest = ints.shape[0] > 0 and _at_rest(xd)
    for i in range(ints.shape[0]):
        if ints[i, _STATE] >= 0:
            out[ints[i, _STATE]] = _wear_rate(x, xd, ints, geometry, law, friction, moving, i, rest)


@njit(**KERNEL)
def advance_wear(x, xd, z0, f0, h, ints, geometry, law, friction, moving, z):
    """The wear states over a step h (s) from z0 (rates f0) to the state x, xd, in place
    in z: z = z0 + h/2 (f0 + f(x, xd))."""
    rest = ints.shape[0] > 0 and _at_rest(xd)
    for i in range(ints.shape[0]):
        s = ints[i, _STATE]
        if s >= 0:
            rate = _wear_rate(x, xd, ints, geometry, law, friction, moving, i, rest)
            z[s] = z0[s] + 0.5 * h * (f0[s] + rate)
