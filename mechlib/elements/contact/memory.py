"""A contact's memory, committed on each accepted state: one compiled rule for the Python
step (Contact.commit) and the compiled whole run (mechlib.solvers.genalpha.run, through
mechlib.elements.contact.group.commit_contacts), so that both remember the same numbers.

The memory (`MEMORY` floats): [in contact (1.0 or 0.0), penetration x (m), its rate xd
(m/s, > 0 approaching)] at the last accepted state. The approach speed of a law that
`remembers` (hertz, restitution): while apart, the rate of the latest state; at the first
state in contact, the rate interpolated to x = 0 between that state and the last one apart
(the step across the impact is not resolved). A contact with friction also keeps the poses
of its two bodies at the accepted state (`anchor` (2, 12): per body r (m), then its
rotation matrix by rows), from which a static evaluation measures the slip.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.contact.kernels import GAP_SIZE, gap
from mechlib.kinematics.kernels import rotation_matrix

__all__ = ["IN_CONTACT", "MEMORY", "PENETRATION", "RATE", "commit_memory"]

MEMORY = 3
IN_CONTACT, PENETRATION, RATE = 0, 1, 2


@njit(**KERNEL)
def _posed(x, b1, b2, anchor):
    """anchor (2, 12) = the poses of bodies b1 and b2 in x (nb+1, 7): r, then A(p) by rows."""
    for k in range(2):
        b = b1 if k == 0 else b2
        rotation = rotation_matrix(x[b, 3:])
        for c in range(3):
            anchor[k, c] = x[b, c]
            for j in range(3):
                anchor[k, 3 + 3 * c + j] = rotation[c, j]


@njit(**KERNEL)
def commit_memory(kind, b1, b2, g, remembers, posed, x, xd, memory, approach, anchor):
    """Commit the accepted state x, xd (nb+1, 7) of a contact of geometry `kind` between b1
    and b2 (parameters g, mechlib.elements.contact.kernels.gap): `memory` (MEMORY,) in place
    where the law `remembers`, the poses into `anchor` where `posed` (a contact with
    friction). Returns (the approach speed (m/s) from now on, given `approach` the one
    before; the penetration (m) at the state)."""
    gp = np.empty(GAP_SIZE)
    gap(kind, x, xd, b1, b2, g, gp)
    if posed:
        _posed(x, b1, b2, anchor)
    x1 = gp[0]
    if not remembers:
        return approach, x1
    xd1 = -(gp[7] * gp[1] + gp[8] * gp[2] + gp[9] * gp[3])  # Gap.rate
    x0, xd0 = memory[PENETRATION], memory[RATE]
    if x1 <= 0.0:
        approach = xd1
    elif memory[IN_CONTACT] == 0.0 and x0 < 0.0:
        approach = xd0 + (xd1 - xd0) * (-x0) / (x1 - x0)
    memory[IN_CONTACT] = 1.0 if x1 > 0.0 else 0.0
    memory[PENETRATION], memory[RATE] = x1, xd1
    return approach, x1
