"""Non-finite numbers never reach an `ok` solution: checks on recorded states and channels,
and the force element to blame when a state or a failure comes from a non-finite force.

The checks run once per recorded row (and once per channel after solving), never inside
Newton iterations: a non-finite force makes Newton fail or the recorded state non-finite,
and only then are the elements evaluated one by one to name the culprit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.core.outcome import SolverFailure, Status

__all__ = [
    "all_finite",
    "check_recorded_state",
    "explain_failure",
    "nonfinite_channel",
    "nonfinite_force",
]


@njit(**KERNEL)
def all_finite(q, qd, qdd, lam) -> bool:
    """Whether every value of the four state arrays is finite (one pass, no temporaries)."""
    for array in (q, qd, qdd, lam):
        for value in array:
            if not math.isfinite(value):
                return False
    return True


def _first_bad(*arrays: np.ndarray) -> float | None:
    """The first non-finite value among the arrays, None if all are finite."""
    for array in arrays:
        bad = ~np.isfinite(array)
        if bad.any():
            return float(np.asarray(array)[bad].flat[0])
    return None


def nonfinite_force(
    system, q: np.ndarray, qd: np.ndarray | None, t: float, lam: np.ndarray | None = None
) -> tuple[str, float] | None:
    """(name, first bad value) of the first active force element whose force or torque at
    the state (q, qd, t) is not finite; None if every element gives finite values."""
    if _first_bad(q, *(() if qd is None else (qd,))) is not None:
        return None  # on a non-finite state every element is non-finite: no culprit
    view = system.view(
        system.kin(q, qd, t), lam if lam is not None and _first_bad(lam) is None else None
    )
    for element in system.elements:
        if not element.active:
            continue
        F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
        try:
            element.apply(view, F, N)
        except SolverFailure:
            continue  # fails for a reason of its own, reported elsewhere
        value = _first_bad(F, N)
        if value is not None:
            return element.name, value
    return None


def check_recorded_state(system, t: float, q, qd, qdd, lam) -> None:
    """SolverFailure if a state about to be recorded is not finite, naming the force element
    that gave a non-finite value when there is one."""
    q, qd, qdd, lam = (np.asarray(a, dtype=float).ravel() for a in (q, qd, qdd, lam))
    if all_finite(q, qd, qdd, lam) or _first_bad(q, qd, qdd, lam) is None:
        return
    found = nonfinite_force(system, q, qd, t, lam)
    where = (found[0],) if found else ()
    cause = (
        f"force element '{found[0]}' gives {found[1]:g} (not finite) there"
        if found
        else "no force element gives a non-finite value (a diverging solution)"
    )
    raise SolverFailure(
        f"the solution is not finite at t = {t:.6g} s: {cause}",
        time=t,
        where=where,
        status=Status.NOT_FINITE,
    )


def explain_failure(system, trajectory, failure: SolverFailure) -> str:
    """The failure's message, plus the force element that is not finite at the failure time
    at the last recorded state, if any: a NaN in Newton's residual otherwise reads as a
    singular matrix or a divergence."""
    message = str(failure)
    if failure.time is None or not len(trajectory) or "not finite" in message:
        return message
    found = nonfinite_force(system, trajectory.q[-1], trajectory.qd[-1], failure.time)
    if found is None:
        return message
    return (
        f"{message}; force element '{found[0]}' gives {found[1]:g} (not finite) at "
        f"t = {failure.time:.6g} s"
    )


def nonfinite_channel(
    time: np.ndarray, channels: Mapping[str, np.ndarray]
) -> tuple[str, float, float] | None:
    """(column, time, value) of the first non-finite value of the first such column."""
    for name, values in channels.items():
        bad = ~np.isfinite(values)
        if bad.any():
            row = int(np.argmax(bad))
            return name, float(time[row]), float(values[row])
    return None
