"""What the solves of one mechanism share: its model check and its assembled start.

A run's accuracy companion and its tighter runs solve the same mechanism from the same
initial values with other steps, tolerances and output intervals: the redundancy check
(the equations dropped, their warnings) and the assembled initial state (positions,
velocities, their notes, branch changes) are the run's own. `SolveMemo` keeps them from
the first solve and puts them in place in the next ones, instead of finding them again
(1.6 and 1.1 ms of the campaign slider-crank's 61 ms run); the systems it serves share
their saddle patterns (mechlib.system.known_patterns: 0.2 ms a solve). Only what is a function of
the mechanism, the initial values, the branch check, `redundant` and the analysis's kind
and start time is kept; the analysis's own steps are never. Work counted during the
assembly (factorisations, Jacobian evaluations, Newton iterations) is counted again in
each solve that reuses it, so that every solve's statistics stay those of a solve on its
own.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from mechlib.system.known_patterns import KnownPatterns

if TYPE_CHECKING:  # types only: `loads validate` builds a BuiltRun (and its memo) without
    # importing the solvers (tests/cli/test_startup.py)
    from mechlib.core.outcome import SolverStats
    from mechlib.model.mechanism import Mechanism
    from mechlib.solvers.assembly import Assembled
    from mechlib.system.system import System

__all__ = ["SolveMemo"]


@dataclass(frozen=True)
class _Checked:
    """The model check's outcome: the indices (into the rows before) of the equations it
    dropped, and its warnings."""

    dropped: np.ndarray
    warnings: tuple[str, ...]


@dataclass(frozen=True)
class _Start:
    """An assembled start and the work its finding counted."""

    assembled: Assembled
    factorizations: int
    jacobian_evaluations: int


class SolveMemo:
    """The model check and assembled start of solves of one mechanism, its initial values,
    its branch check and its `redundant` setting (kept by identity: a solve given anything
    else neither reads nor writes this memo), keyed by the analysis's kind and start time
    (s)."""

    def __init__(self) -> None:
        self._owner: tuple | None = None
        self._checked: dict[tuple, _Checked] = {}
        self._starts: dict[tuple, _Start] = {}
        self.patterns = KnownPatterns()  # the saddle patterns, by active rows

    def serves(self, mechanism: Mechanism, initial: Sequence, branches, redundant: str) -> bool:
        """Whether this memo may serve a solve of these inputs (the first one binds it)."""
        owner = (mechanism, initial, branches, redundant)
        if self._owner is None:
            self._owner = owner
        return all(a is b for a, b in zip(self._owner[:3], owner[:3])) and (
            self._owner[3] == redundant
        )

    def checked(self, system: System, key: tuple, check: Callable[[], list[str]]) -> list[str]:
        """The warnings of `check` (the model check of `system`, which may drop equations);
        the equations it dropped before dropped again without it."""
        kept = self._checked.get(key)
        if kept is None:
            before = np.array(system.active, copy=True)
            warnings = check()
            dropped = np.flatnonzero(~np.isin(before, system.active))
            self._checked[key] = _Checked(dropped, tuple(warnings))
            return warnings
        if len(kept.dropped):
            system.drop_rows(kept.dropped)
        return list(kept.warnings)

    def assembled(
        self, key: tuple, stats: SolverStats, assemble: Callable[[], Assembled]
    ) -> Assembled:
        """`assemble()` (the start, within the solve's tally of work into `stats`), or a
        copy of the one kept, its work counted into `stats` again."""
        kept = self._starts.get(key)
        if kept is None:
            before = (stats.factorizations, stats.jacobian_evaluations)
            assembled = assemble()
            self._starts[key] = _Start(
                _copied(assembled),
                stats.factorizations - before[0],
                stats.jacobian_evaluations - before[1],
            )
            return assembled
        stats.factorizations += kept.factorizations
        stats.jacobian_evaluations += kept.jacobian_evaluations
        return _copied(kept.assembled)


def _copied(assembled: Assembled) -> Assembled:
    """`assembled` with its own arrays and lists (a solve moves its state on from them)."""
    return replace(
        assembled,
        q=assembled.q.copy(),
        qd=assembled.qd.copy(),
        notes=list(assembled.notes),
        branches=list(assembled.branches),
    )
