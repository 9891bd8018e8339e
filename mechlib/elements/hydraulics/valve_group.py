"""The `valve` servo-actuators of a system as one packed group of the compiled force
elements (mechlib.elements.compiled_forces): their arrays, their wrenches from the chamber
pressures (valve_states.chamber_wrench) and their states' advance over a step
(valve_states.advance_valve), each over the whole group in one kernel call (SI units).

Layout, one row per actuator: ints (body 1, body 2, its first element state, on); floats
(point 1 (3), point 2 (3), design length (m), its parameters (laws.pack), the stroke
demand (m) at the step's end).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.hydraulics.laws import N_PARAMS
from mechlib.elements.hydraulics.valve_states import (
    N_VALVE,
    advance_valve,
    chamber_wrench,
    stroke_line,
    valve_rates,
)

__all__ = [
    "VALVE_FLOATS",
    "VALVE_INTS",
    "advance_valves",
    "refresh_valves",
    "valve_arrays",
    "valves_rates",
    "valves_wrench",
]

VALVE_INTS, VALVE_FLOATS = 4, 7 + N_PARAMS + 1
_ON, _DEMAND = 3, VALVE_FLOATS - 1


def valve_arrays(actuators: Sequence, starts: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """(ints, floats) of the bound `valve` actuators whose states start at `starts` in the
    system's element states; the demands left at 0 until `refresh_valves`."""
    ints = np.zeros((len(actuators), VALVE_INTS), dtype=np.int64)
    floats = np.zeros((len(actuators), VALVE_FLOATS))
    for i, (actuator, start) in enumerate(zip(actuators, starts)):
        b1, s1, b2, s2 = actuator._geometry
        ints[i] = (b1, b2, start, 1)
        floats[i, :-1] = (*s1, *s2, actuator._design_length, *actuator._params)
    return ints, floats


def refresh_valves(actuators: Sequence, ints: np.ndarray, floats: np.ndarray, t) -> None:
    """The actuators' on flags now and, with a time t (s), their stroke demands (m) at t
    (the loads alone do not read them)."""
    for i, actuator in enumerate(actuators):
        ints[i, _ON] = actuator.active
        if t is not None:
            floats[i, _DEMAND] = float(actuator.command(t))


@njit(**KERNEL)
def valves_wrench(x, xd, z, ints, floats, F, N):
    """Add the loads of the actuators switched on, at the state x, xd (nb+1, 7) with
    element states z, to F and N (nb+1, 3)."""
    for i in range(ints.shape[0]):
        if ints[i, _ON]:
            f, first = floats[i], ints[i, 2]
            chamber_wrench(
                x, xd, ints[i, 0], f[0:3], ints[i, 1], f[3:6], f[6], f[7 : 7 + N_PARAMS],
                z[first + 3], z[first + 4], F, N,
            )  # fmt: skip


@njit(**KERNEL)
def advance_valves(x, xd, z0, f0, h, ints, floats, z):
    """Every actuator's states (on or not, as mechlib.elements.states.ElementStates.advance
    does) over a step h (s) from z0 (rates f0) to the state x, xd, in place in z."""
    line = np.empty(5)
    for i in range(ints.shape[0]):
        f = floats[i]
        stroke_line(x, xd, ints[i, 0], f[0:3], ints[i, 1], f[3:6], f[6], line)
        block = slice(ints[i, 2], ints[i, 2] + N_VALVE)
        advance_valve(
            f[7 : 7 + N_PARAMS], f[_DEMAND], line[0], line[1], z0[block], f0[block], h, z[block]
        )


@njit(**KERNEL)
def valves_rates(x, xd, z, ints, floats, out):
    """Every actuator's state rates (on or not, as ElementStates.rates gives them) at the
    state x, xd with element states z, into `out` (the system's element states' layout)."""
    line = np.empty(5)
    for i in range(ints.shape[0]):
        f = floats[i]
        stroke_line(x, xd, ints[i, 0], f[0:3], ints[i, 1], f[3:6], f[6], line)
        block = slice(ints[i, 2], ints[i, 2] + N_VALVE)
        valve_rates(f[7 : 7 + N_PARAMS], f[_DEMAND], line[0], line[1], z[block], out[block])
