"""Dense output (`analysis.output: dense`): output rows between the integrator's own steps.

The integrator steps at the size its error control chooses, from a first step and up to a
largest step set by the problem's own scales (or `analysis.max_step`), whatever the output
interval; each output time within an accepted step gets a row from the step's two ends:

- positions and velocities by the quintic Hermite interpolant of (q, qd, qdd) at both
  ends (generalized-alpha), or by the integrator's own dense output (Radau);
- the positions then projected onto the position constraints, the velocities onto the
  velocity constraints (mass-weighted), and the accelerations and multipliers solved from
  the equations of motion there (`consistent_state`): the row's reactions are those of the
  equations of motion at the row's state, as at a step's end;
- element states (mechlib.states) interpolated linearly between the step's ends (they are
  advanced by the trapezoidal rule, itself linear in time over a step).

Events still end a step where they happen, and their rows are recorded as before.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.assembly import MAX_NEWTON, POSITION_TOLERANCE, REUSE_BELOW, solve_positions
from mechlib.consistent import consistent_state
from mechlib.contract import State
from mechlib.dense_compiled import DONE, project_row
from mechlib.linalg import SPARSE_FROM
from mechlib.system import System
from mechlib.work import count

__all__ = ["first_step", "hermite", "natural_time", "projected_row"]

_FIRST_FRACTION = 1e-6  # of the natural time: the start acceleration may be left at once
_PROJECTION = np.array([POSITION_TOLERANCE, REUSE_BELOW, MAX_NEWTON], dtype=float)


def natural_time(system: System) -> float:
    """The mechanism's own time scale (s): sqrt(size / gravity), gravity floored at
    1 m/s^2 (a mechanism without gravity: sqrt of its size in metres)."""
    g = max(float(np.linalg.norm(system.gravity)), 1.0)
    return math.sqrt(max(system.length, 1e-6) / g)


def largest_step(system: System, spec) -> float:
    """`analysis.max_step` when given, else the natural time (s): not the span, so that
    a longer run takes the same steps over the shorter one's time."""
    if spec.max_step:
        return float(spec.max_step)
    return natural_time(system)


def first_step(system: System, spec) -> float:
    """A small fraction of the natural time, at most the largest step (s)."""
    return min(largest_step(system, spec), _FIRST_FRACTION * natural_time(system))


def hermite(t0: float, t1: float, a: tuple, b: tuple, t: float) -> tuple:
    """(q, qd) at t from the quintic Hermite interpolant of a = (q, qd, qdd) at t0 and
    b = (q, qd, qdd) at t1: exact for quintic motions, error O(h^6) in q."""
    h = t1 - t0
    s = (t - t0) / h
    s2 = s * s
    s3, s4 = s2 * s, s2 * s2
    p = np.array((1.0, s, s2, s3, s4, s4 * s))  # 1, s, .., s^5
    dp = np.array((0.0, 1.0, 2.0 * s, 3.0 * s2, 4.0 * s3, 5.0 * s4))  # their slopes d/ds
    values, slopes = _BASIS @ p, _BASIS @ dp  # per end quantity: q0 qd0 qdd0 q1 qd1 qdd1
    scale = np.array([1.0, h, h * h, 1.0, h, h * h])
    parts = np.stack((a[0], a[1], a[2], b[0], b[1], b[2]))
    return (values * scale) @ parts, (slopes * scale / h) @ parts


# quintic Hermite basis on s in [0, 1], coefficients of 1, s, .., s^5: the weights of q0,
# h qd0, h^2 qdd0, q1, h qd1, h^2 qdd1
_BASIS = np.array(
    [
        [1, 0, 0, -10, 15, -6],
        [0, 1, 0, -6, 8, -3],
        [0, 0, 0.5, -1.5, 1.5, -0.5],
        [0, 0, 0, 10, -15, 6],
        [0, 0, 0, -4, 7, -3],
        [0, 0, 0, 0.5, -1, 0.5],
    ]
)


def projected_row(system: System, t: float, q, qd, states: np.ndarray | None) -> State:
    """The row at t from interpolated (q, qd) and element states: q onto the position
    constraints, qd onto the velocity ones, qdd and lam from the equations of motion; its
    snapshot carries the interpolated element states. The system's element states are
    left as they were."""
    snapshot = system.snapshot()
    kept = system.states.trial
    if states is not None:
        system.states.trial = states
        snapshot["states"] = states.copy()
    compiled = None if states is not None else _compiled_row(system, t, q, qd)
    if compiled is not None:
        q, qd, qdd, lam = compiled
        return State(t, q, qd, qdd, lam, snapshot=snapshot)
    try:
        q, _ = solve_positions(system, np.asarray(q, float), t)
        qd, qdd, lam = consistent_state(system, q, np.asarray(qd, float), t)
    finally:
        system.states.trial = kept
    return State(t, q, qd, qdd, lam, snapshot=snapshot)


def _compiled_row(system: System, t: float, q, qd) -> tuple[np.ndarray, ...] | None:
    """(q, qd, qdd, lam) of `projected_row` from one compiled call
    (mechlib.dense_compiled) for a small packed system with no active element and no
    element states; None where the Python path must take the row (a larger system, or
    the kernel gave up: near a toggle, no convergence)."""
    arrays = system.packed_constraints()
    if arrays is None or system.states or system.nq + system.active.size >= SPARSE_FROM:
        return None
    if any(e.active for e in system.elements):
        return None
    nq, m = system.nq, system.active.size
    out = np.empty(3 * nq + m)
    ints, floats = arrays.packed()
    status, fresh = project_row(
        np.asarray(q, float), np.asarray(qd, float), ints, floats, arrays.functions(t),
        arrays.references(), arrays.bodies(), _PROJECTION, out,
    )  # fmt: skip
    count(factorizations=fresh, jacobian_evaluations=fresh)
    if status != DONE:
        return None
    count(factorizations=1)  # the saddle matrix's, as consistent_state counts it
    return out[:nq], out[nq : 2 * nq], out[2 * nq : 3 * nq], out[3 * nq :]
