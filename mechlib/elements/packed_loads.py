"""A system's force elements packed for the compiled kernels of the integrator, where every
active element has a compiled wrench: linear springs (mechlib.kinematics.kernels.
spring_wrench) and servo-actuators of the `valve` fidelity (their piston force from the
chamber pressures, mechlib.elements.hydraulics.valve_states.chamber_wrench; their states
advanced by valve_states.advance_valve).

`PackedLoads.of(system)` packs them once (None where element states belong to other
elements; springs are packed beside an actuator only); `args(t)` gives the arrays the
kernels take, `LoadArgs`, read at each call (the elements' `active` flags, the actuators'
stroke demand at t), or None while any other element is active (the Python path takes
those). `loads_wrench` and `advance_states` are the kernels' side of this interface;
`no_loads()` the arrays of a system without elements.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.forces import Spring
from mechlib.elements.hydraulics.actuator import ServoActuator
from mechlib.elements.hydraulics.laws import N_PARAMS
from mechlib.elements.hydraulics.valve_states import advance_valve, chamber_wrench, stroke_line
from mechlib.kinematics.kernels import spring_wrench

__all__ = ["PackedLoads", "advance_states", "loads_wrench", "no_loads"]

# LoadArgs: (ints, floats), flat (one array each: a kernel's arguments are typed fast)
# ints: [springs, actuators, then per spring (body 1, body 2, wire, on), per actuator
# (body 1, body 2, its first state, on)]; floats: per spring (point 1, point 2, stiffness,
# damping, free length, preload: kernels.spring_wrench's), per actuator (point 1, point 2,
# design length, its parameters (laws.pack), the stroke demand (m) now)
_HEAD, _SPRING_INTS, _ACTUATOR_INTS = 2, 4, 4
_SPRING_FLOATS, _ACTUATOR_FLOATS = 10, 7 + N_PARAMS + 1


@njit(**KERNEL)
def no_loads():
    """The LoadArgs of a system without packed elements."""
    return np.zeros(_HEAD, dtype=np.int64), np.zeros(0)


class PackedLoads:
    """The springs and valve actuators of a system as arrays (see the module docstring)."""

    def __init__(
        self,
        springs: Sequence[Spring],
        actuators: Sequence[ServoActuator],
        starts: Sequence[int],
        others: Sequence,
    ):
        self.springs, self.actuators, self.others = list(springs), list(actuators), list(others)
        ints: list[int] = [len(self.springs), len(self.actuators)]
        floats: list[float] = []
        for spring in self.springs:  # kernels.spring_wrench's arguments, taken at bind
            b1, s1, b2, s2, stiffness, damping, free_length, preload, slack = spring._compiled
            ints += [b1, b2, int(slack), 1]
            floats += [*s1, *s2, stiffness, damping, free_length, preload]
        for actuator, start in zip(self.actuators, starts):
            b1, s1, b2, s2 = actuator._geometry
            ints += [b1, b2, start, 1]
            floats += [*s1, *s2, actuator._design_length, *actuator._params, 0.0]
        self.ints = np.array(ints, dtype=np.int64)
        self.floats = np.array(floats, dtype=float)
        ns, na = len(self.springs), len(self.actuators)
        self._spring_on = _HEAD + _SPRING_INTS * np.arange(ns) + 3
        self._actuator_on = _HEAD + _SPRING_INTS * ns + _ACTUATOR_INTS * np.arange(na) + 3
        self._demand = _SPRING_FLOATS * ns + _ACTUATOR_FLOATS * np.arange(1, na + 1) - 1

    @classmethod
    def of(cls, system) -> PackedLoads | None:
        """The linear springs and `valve` servo-actuators of a bound system packed, the
        other elements kept aside; None when element states belong to other elements."""
        springs, actuators, others = [], [], []
        for e in system.elements:
            if type(e) is Spring and e.law is None:
                springs.append(e)
            elif type(e) is ServoActuator and e.fidelity == "valve":
                actuators.append(e)
            else:
                others.append(e)
        states = system.states
        if len(states.owners) != len(actuators):
            return None
        if not actuators:  # springs alone keep the Python path (issue 40: compiled forces)
            springs, others = [], springs + others
        starts = [states.slices[id(a)].start for a in actuators]
        return cls(springs, actuators, starts, others)

    def args(self, t: float, demands: bool = True) -> tuple[np.ndarray, np.ndarray] | None:
        """The kernels' LoadArgs at time t (s): the active flags now, the demands at t
        (`demands` False: left as they were, for the loads alone, which do not read them);
        None while another element is active."""
        if any(e.active for e in self.others):
            return None
        for i, spring in zip(self._spring_on, self.springs):
            self.ints[i] = spring.active
        for i, j, actuator in zip(self._actuator_on, self._demand, self.actuators):
            self.ints[i] = actuator.active
            if demands:
                self.floats[j] = float(actuator.command(t))
        return self.ints, self.floats


@njit(**KERNEL)
def loads_wrench(x, xd, z, ints, floats, F, N):
    """Add the loads of the active packed elements (LoadArgs ints, floats) at the state
    x, xd (nb+1, 7) with element states z to F and N (nb+1, 3)."""
    ns, na = ints[0], ints[1]
    for i in range(ns):
        k, f = _HEAD + _SPRING_INTS * i, floats[_SPRING_FLOATS * i : _SPRING_FLOATS * (i + 1)]
        if ints[k + 3]:
            spring_wrench(
                x, xd, ints[k], f[0:3], ints[k + 1], f[3:6], f[6], f[7], f[8], f[9],
                ints[k + 2] != 0, F, N,
            )  # fmt: skip
    for i in range(na):
        k = _HEAD + _SPRING_INTS * ns + _ACTUATOR_INTS * i
        o = _SPRING_FLOATS * ns + _ACTUATOR_FLOATS * i
        if ints[k + 3]:
            first = ints[k + 2]
            chamber_wrench(
                x, xd, ints[k], floats[o : o + 3], ints[k + 1], floats[o + 3 : o + 6],
                floats[o + 6], floats[o + 7 : o + 7 + N_PARAMS], z[first + 3], z[first + 4],
                F, N,
            )  # fmt: skip


@njit(**KERNEL)
def advance_states(x, xd, z0, f0, h, ints, floats, z):
    """The actuators' states over a step h (s) from z0 (rates f0) to the state x, xd:
    valve_states.advance_valve of each, in place in z (mechlib.elements.states'
    ElementStates.advance: every actuator, active or not)."""
    ns, na = ints[0], ints[1]
    line = np.empty(5)
    for i in range(na):
        k = _HEAD + _SPRING_INTS * ns + _ACTUATOR_INTS * i
        o = _SPRING_FLOATS * ns + _ACTUATOR_FLOATS * i
        stroke_line(
            x, xd, ints[k], floats[o : o + 3], ints[k + 1], floats[o + 3 : o + 6], floats[o + 6],
            line,
        )  # fmt: skip
        params = floats[o + 7 : o + 7 + N_PARAMS]
        demand = floats[o + _ACTUATOR_FLOATS - 1]
        block = slice(ints[k + 2], ints[k + 2] + 5)
        advance_valve(params, demand, line[0], line[1], z0[block], f0[block], h, z[block])
