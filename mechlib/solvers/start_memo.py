"""The assembled start positions, kept per process by the values they are found from.

A sweep's runs solved in one worker often place the same mechanism at the same initial
positions, varying only what the positions do not read (an initial rate, a load, a
damping). `placed_start` keeps the last few position stages of `assemble` keyed by
everything that stage reads: the mechanism by value (every body, point, joint, motion and
force element, attribute by attribute: mechlib.core.by_value), the system's kind, its
active equations and angle references before, the time (s), the given positions and
guesses, and the branch check. A variant changing any of them (a length, a mass, a joint's
place, an initial angle) is placed anew; the rates are always solved in the run itself.
Served from memory, the stage leaves the system as it left it (its angle references) and
counts its work (factorisations, Jacobian evaluations) into the solve again, so that the
run is the same bit for bit, statistics included. Mechanisms with flexible bodies, element
memories (contacts, friction), given modal coordinates, or anything not keyed by value (a
motion's function) are placed every time.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from mechlib.core.by_value import ByValue, value_key
from mechlib.core.outcome import SolverStats
from mechlib.core.work import count, tally
from mechlib.model.analysis import BranchCheck, InitialBodyVelocity, InitialValue

__all__ = ["PLACED", "Placed", "placed_start"]


@dataclass
class Placed:
    """The position stage of an assembly: q, its Newton iterations, its notes and branch
    changes (mechlib.solvers.branches.BranchChange)."""

    q: np.ndarray
    iterations: int
    notes: list[str] = field(default_factory=list)
    changes: list = field(default_factory=list)


@dataclass(frozen=True)
class _Kept:
    """A position stage, the angle references it left and the work it counted."""

    placed: Placed
    references: dict
    factorizations: int
    jacobian_evaluations: int


PLACED: ByValue[_Kept] = ByValue(size=4)  # a few mechanisms a worker at once


def _key(system, t: float, initial: Sequence, check: BranchCheck) -> tuple | None:
    """What the position stage reads, by value; None where it cannot be told by value."""
    space = getattr(system, "space", system)  # a planar system's 3-D one holds the elements
    if system.nz or system.flexible or getattr(space, "_remembering", [None]):
        return None
    positions = []
    for item in initial:
        if isinstance(item, InitialValue):
            positions.append(replace(item, rate=None))  # the rate: the velocity stage's
        elif not isinstance(item, InitialBodyVelocity):
            return None  # modal coordinates, or what this memo does not know
    mechanism = system.mechanism
    try:  # the motions and force elements first: what refuses a key is found there
        return value_key(mechanism.motions, mechanism.forces) + value_key(
            type(system).__qualname__,
            mechanism,
            system.active,
            system.references(),
            float(t),
            positions,
            check,
        )
    except (TypeError, RecursionError):  # a motion's function, an element of unknown state
        return None


def placed_start(
    system, t: float, initial: Sequence, check: BranchCheck, place: Callable[[], Placed]
) -> Placed:
    """`place()` (the position stage of assembling `system` at `t`, s), or the stage kept
    from an earlier solve of the same values: the system's angle references as it left
    them, its work counted again."""
    key = _key(system, t, initial, check)
    if key is None:
        return place()

    def found() -> _Kept:
        work = SolverStats()
        try:
            with tally(work):
                placed = place()
        except BaseException:  # a failed assembly: nothing kept, its work counted as ever
            count(
                factorizations=work.factorizations, jacobian_evaluations=work.jacobian_evaluations
            )
            raise
        refs = system.references()
        return _Kept(_copied(placed), refs, work.factorizations, work.jacobian_evaluations)

    hits = PLACED.hits
    kept = PLACED.get(key, found)
    if PLACED.hits > hits:
        system.restore(kept.references)
    count(factorizations=kept.factorizations, jacobian_evaluations=kept.jacobian_evaluations)
    return _copied(kept.placed)


def _copied(placed: Placed) -> Placed:
    """`placed` with its own array and lists (a run moves on from them)."""
    return Placed(placed.q.copy(), placed.iterations, list(placed.notes), list(placed.changes))
