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
its wear state's index among the element states, -1: none);
geometry (its 11 parameters); law (its parameters, padded); friction (its parameters,
padded); moving (approach speed (m/s), friction mu_dynamic, slip threshold (m)); anchor
(2, 12: the poses of the last accepted state, Contact._anchor).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.contact.kernels import (
    GAP_SIZE,
    contact_force,
    contact_wrench,
    gap,
    static_contact_wrench,
)

__all__ = [
    "CONTACT_INTS",
    "GEOMETRY",
    "MOVING",
    "PARAMETERS",
    "advance_wear",
    "contact_arrays",
    "contacts_rates",
    "contacts_wrench",
    "packable",
    "refresh_contacts",
]

CONTACT_INTS, GEOMETRY, PARAMETERS, MOVING = 6, 11, 5, 3
_STATE = 5
_APPROACH, _MU, _THRESHOLD = 0, 1, 2


def packable(contact) -> bool:
    """A contact the group serves: a primitive geometry (its compiled tangent too)."""
    return getattr(contact, "_kernel", None) is not None


def contact_arrays(contacts: Sequence, starts: Sequence[int]) -> tuple:
    """(ints, geometry, law, friction, moving, anchor) of the bound `contacts` (`starts`:
    each one's first element state, -1: none); the moving values and anchors as
    `refresh_contacts` sets them."""
    n = len(contacts)
    ints = np.zeros((n, CONTACT_INTS), dtype=np.int64)
    geometry = np.zeros((n, GEOMETRY))
    law, friction = np.zeros((n, PARAMETERS)), np.zeros((n, PARAMETERS))
    for i, c in enumerate(contacts):
        kind, b1, b2, g, law_code, _, friction_code, fp = c._kernel
        ints[i] = (kind, b1, b2, law_code, friction_code, starts[i])
        geometry[i] = g
        friction[i, : fp.size] = fp
    moving, anchor = np.zeros((n, MOVING)), np.full((n, 2, 12), np.nan)
    arrays = (ints, geometry, law, friction, moving, anchor)
    refresh_contacts(contacts, arrays)
    return arrays


def refresh_contacts(contacts: Sequence, arrays: tuple) -> None:
    """The values the contacts change between steps: the law's parameters (the impact
    ramp's start), the approach speed (m/s), mu and slip threshold (m) of the static
    friction and the anchor poses."""
    _, _, law, _, moving, anchor = arrays
    for i, c in enumerate(contacts):
        lp = c._kernel[5]
        law[i, : lp.size] = lp
        moving[i, _APPROACH] = c.approach
        if c.friction is not None:
            mu, poses, threshold = c._static_friction()
            moving[i, _MU], moving[i, _THRESHOLD] = mu, threshold
            anchor[i] = poses


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
