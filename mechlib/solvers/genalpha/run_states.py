"""Element states in the compiled whole runs (mechlib.solvers.genalpha.run): the `valve`
servo-actuators' five states each, or the packed contacts' wear work (a clearance joint's
one state, mechlib.elements.contact.group.advance_wear), advanced at every Newton iterate
of a step by the trapezoidal rule (mechlib.elements.states.ElementStates, whose rules
these kernels follow), their local error in the step's error test, their accepted values
and rates, and the rows' states within a step by the cubic Hermite interpolant of both
ends' values and rates (mechlib.solvers.dense_states, as mechlib.solvers.march
interpolates them).

The states travel as one tuple (`RunStates.pack`): z (accepted, nz), trial (the step under
way, nz), rates (dz/dt at the accepted state, nz), before (the rates of the accepted state
before it, nz), memo ([previous step (s), 1 when `before` holds, 0 otherwise]), weights
(tol x each state's scale: Scales.z_abs), ends (the rates at the step's end, nz:
`end_rates`), rows (the rows' states, (rows, nz)). A system without element states has
nz = 0 and every kernel here does nothing.

A run serves actuators whose stroke demand is held constant (mechlib.elements.hydraulics.
command.HeldDemand): the kernels read it once, exactly; a demand that is a function of time
keeps the steps in Python.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.compiled_forces import element_rates
from mechlib.elements.hydraulics.command import held_value
from mechlib.kinematics import constraint_arrays as ca
from mechlib.solvers.dense_states import hermite_states

__all__ = [
    "RunStates",
    "accept_states",
    "end_rates",
    "interpolate_states",
    "record_states",
    "states_error",
    "trial_start",
]

Z, TRIAL, RATES, BEFORE, MEMO, WEIGHTS, ENDS, ROWS = 0, 1, 2, 3, 4, 5, 6, 7
PREVIOUS_H, HAS_BEFORE = 0, 1  # slots of memo


@njit(**KERNEL)
def trial_start(states):
    """The trial values of a new attempt start from the accepted ones (ElementStates.reject)."""
    states[TRIAL][:] = states[Z]


@njit(**KERNEL)
def states_error(err, h, states, tol):
    """The step's scaled error: `err` (the positions') or the element states' when larger
    (GeneralizedAlphaStepper._error): their local error by Milne's device
    (ElementStates.local_error: the trial values against the explicit second-order
    predictor, times h / (3 (h + k)), k the previous step) weighed by Scales.state_error's
    rule; none before a previous accepted step."""
    z, trial, f, before, memo, weights = states[:6]
    if not z.shape[0] or memo[HAS_BEFORE] == 0.0:
        return err
    k = memo[PREVIOUS_H]
    worst = 0.0
    for i in range(z.shape[0]):
        predicted = z[i] + h * f[i] + 0.5 * h * h * (f[i] - before[i]) / k
        e = abs((trial[i] - predicted) * (h / (3.0 * (h + k))))
        size = e / (weights[i] + tol * abs(trial[i]))
        if size > worst or size != size:
            worst = size
    return worst if worst > err else err  # as Python's max(err, worst): a NaN is not larger


@njit(**KERNEL)
def end_rates(q1, qd1, elements, states):
    """The rates of the trial values at the end (q1, qd1 raw) of a step that passed its
    error test, into states[ENDS]: what the rows within it and `accept_states` read (the
    one evaluation of the states' equations an accepted step makes)."""
    if states[Z].shape[0]:
        x, xd = ca.state_arrays(q1, qd1, q1.shape[0] // 7)
        element_rates(x, xd, states[TRIAL], elements, states[ENDS])


@njit(**KERNEL)
def accept_states(h, states):
    """An accepted step h (s) (its end's rates from `end_rates`): its trial values become
    the accepted ones, their rates there the trapezoidal rule's next first half, the last
    rates kept for the error estimate (ElementStates.accept)."""
    z, trial, f, before, memo = states[:5]
    if not z.shape[0]:
        return
    before[:] = f
    memo[PREVIOUS_H], memo[HAS_BEFORE] = h, 1.0
    z[:] = trial
    f[:] = states[ENDS]


@njit(**KERNEL)
def interpolate_states(states, h, w, row):
    """Row `row`'s element states (returned, a view of the rows' array) at the fraction w
    of the step h (s) under way: the cubic Hermite interpolant (mechlib.solvers.
    dense_states.hermite_states) of the accepted values and rates at its start and the
    trial values and their rates (`end_rates`) at its end (mechlib.solvers.march._Rows.upto)."""
    return hermite_states(
        states[Z], states[RATES], states[TRIAL], states[ENDS], h, w, states[ROWS][row]
    )


@njit(**KERNEL)
def record_states(states, row):
    """Row `row` at an accepted state: its element states are the accepted ones."""
    states[ROWS][row, :] = states[Z]


class RunStates:
    """The system's element states as a run's tuple (`pack`) and back (`unpack`)."""

    def __init__(self, system):
        self.system = system

    @staticmethod
    def servable(system) -> bool:
        """Whether a run can carry the system's element states: none, integrals no force
        reads (a clearance joint's wear work: StepRun finds whether its contact is packed),
        or only the packed `valve` actuators' (compiled advance) with demands held
        constant."""
        states = system.states
        if not states or not states.drive_forces:
            return True
        return (
            states.compiled
            and states.drive_forces
            and all(held_value(e.command) is not None for e in states.owners)
        )

    def pack(self, weights: np.ndarray, rows: int) -> tuple:
        """The run's tuple of the states now (their trial values from the accepted ones)
        with the error weights `weights` (nz,) and room for `rows` rows."""
        states = self.system.states
        nz = states.z.size
        if not nz:
            empty = np.zeros(0)
            return (empty, empty, empty, empty, np.zeros(2), empty, empty, np.zeros((rows, 0)))
        previous = states._previous
        memo = np.array([previous[1], 1.0] if previous is not None else [0.0, 0.0])
        before = previous[0].copy() if previous is not None else np.zeros(nz)
        assert states.rates_accepted is not None, "a run starts from an accepted state"
        return (
            states.z.copy(), states.z.copy(), np.array(states.rates_accepted, dtype=float),
            before, memo, np.asarray(weights, dtype=float), np.empty(nz), np.empty((rows, nz)),
        )  # fmt: skip

    def unpack(self, packed: tuple, taken: bool) -> None:
        """After a run that took steps (`taken`): its accepted states, rates and history
        are the system's (as ElementStates.accept leaves them)."""
        states = self.system.states
        if not taken or not states:
            return
        z, _, f, before, memo = packed[:5]
        states.z, states.trial = z.copy(), z.copy()
        states.rates_accepted = f.copy()
        states._previous = (before.copy(), float(memo[PREVIOUS_H])) if memo[HAS_BEFORE] else None
        states._h = float(memo[PREVIOUS_H])
