"""Load levels (a case's `level:`): the runs of a set brought to limit level before sizing.

A case gives its applied loads at `limit` level (default: the set's ultimate factor
multiplies them) or at `ultimate` level (e.g. the 1334 N jam load of seed 000). An
ultimate-level run's load columns are its ultimate loads as computed, so its limit loads
are the computed ones divided by the set's ultimate factor; its other columns (angles,
positions ...) stay as computed. With every run at limit level the envelope, the loads
matrix and the curves show limit loads, and ultimate = factor x limit gives an
ultimate-level run's computed loads back (fitting and case factors still multiply in).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

from loadcases.report.margins import ULTIMATE, fitting_factor
from loadcases.results.saved import SavedRun

__all__ = ["LIMIT", "ULTIMATE_LEVEL", "at_limit_level", "limit_divisor", "ultimate_level_runs"]

LIMIT = "limit"
ULTIMATE_LEVEL = "ultimate"


def limit_divisor(level: str, factors: Mapping[str, float]) -> float:
    """What a run's load columns are divided by to give limit loads: the set's ultimate
    factor for an ultimate-level run, else 1."""
    return float(factors.get(ULTIMATE, 1.0)) if level == ULTIMATE_LEVEL else 1.0


def at_limit_level(
    runs: Sequence[SavedRun], factors: Mapping[str, float], named: frozenset[str] = frozenset()
) -> list[SavedRun]:
    """The runs with every ultimate-level run's load columns (those that take factors:
    `loadcases.report.margins.fitting_factor`; `named`: columns an allowable names) divided
    by the ultimate factor; limit-level runs are returned as they are (no copy)."""
    out = []
    for run in runs:
        divisor = limit_divisor(run.level, factors)
        if divisor == 1.0:
            out.append(run)
            continue
        channels = {
            column: (
                values / divisor
                if fitting_factor(column, run.units.get(column), factors, column in named)
                is not None
                else values
            )
            for column, values in run.channels.items()
        }
        out.append(replace(run, channels=channels))
    return out


def ultimate_level_runs(runs: Sequence[SavedRun]) -> list[str]:
    """Names of the runs whose loads are given at ultimate level."""
    return [run.name for run in runs if run.level == ULTIMATE_LEVEL]
