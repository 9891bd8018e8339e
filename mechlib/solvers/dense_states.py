"""Element states in dense output rows: the cubic Hermite interpolant of a step's two ends.

An element state z (a chamber pressure in Pa, a spool position in m, any first-order
element state: mechlib.elements.states) is advanced by the trapezoidal rule, which gives at
both ends of a step its value and its rate dz/dt = f (the state equation's right-hand side,
evaluated there anyway: the rule's next first half). A row within the step takes the cubic
through both values with both rates: its error is h^4 / 384 max|z''''| (h the step, s),
where the straight line between the two values misses a crest by up to h^2 / 8 max|z''|,
a different amount at every crest. The one definition of the rows' element states: the
Python rows (mechlib.solvers.march), the compiled blocks (mechlib.solvers.dense_compiled.
project_loaded_rows) and the compiled whole runs (mechlib.solvers.genalpha.run_states)
call `hermite_states`. Without rates at both ends, or where the states were not advanced
over the step (Radau does not integrate them and refuses a model that has them:
mechlib.solvers.solve), `states_between` interpolates linearly.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = ["StateEnd", "advanced", "hermite_states", "state_end", "states_between"]


@njit(**KERNEL)
def hermite_states(z0, f0, z1, f1, h, w, out):
    """Element states at the fraction w of a step of h (s) into `out` (returned): the cubic
    Hermite interpolant of the values z0, z1 and rates f0, f1 (per s) at the step's start
    and end; w = 0 and w = 1 give z0 and z1 exactly."""
    w2 = w * w
    w3 = w2 * w
    a0 = 2.0 * w3 - 3.0 * w2 + 1.0  # weights of z0, h f0, z1, h f1
    b0 = (w3 - 2.0 * w2 + w) * h
    a1 = 1.0 - a0
    b1 = (w3 - w2) * h
    for i in range(out.shape[0]):
        out[i] = a0 * z0[i] + b0 * f0[i] + a1 * z1[i] + b1 * f1[i]
    return out


StateEnd = tuple[np.ndarray, np.ndarray | None]  # (z, dz/dt or None) at a step's end


def state_end(states) -> StateEnd | None:
    """(z, dz/dt) of the accepted element states `states` (ElementStates) now, copied where
    the next step changes them in place; None without states."""
    if not states:
        return None
    return states.z.copy(), states.rates_accepted


def advanced(start: StateEnd, end: StateEnd) -> bool:
    """Whether both ends have rates and the states were advanced between them (an accepted
    step sets new rates: the same rates array at both ends means they were not)."""
    return start[1] is not None and end[1] is not None and start[1] is not end[1]


def states_between(start: StateEnd, end: StateEnd, h: float, w: float) -> np.ndarray:
    """The element states at the fraction w of a step of h (s) from `start` to `end`
    (`state_end` of both): `hermite_states` where they were `advanced`, else linear."""
    (z0, f0), (z1, f1) = start, end
    if f0 is None or f1 is None or not advanced(start, end):
        return (1.0 - w) * z0 + w * z1
    return hermite_states(z0, f0, z1, f1, h, w, np.empty(z0.shape[0]))
