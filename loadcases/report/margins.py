"""Factors, ultimate loads and margins of safety on an envelope (SPEC 1.4 `factors`, `allowables`).

- `factors: {ultimate: 1.5, ROD: 1.15, ROD.value: 1.2}`: `ultimate` applies to every load
  column (unit N or N*m, or any column named in `factors` or `allowables`); any other key
  is a fitting (special) factor of a request `ROD` or of one column `ROD.value`, multiplied
  into the ultimate factor (a column key wins over its request's key). The factor of a
  column is ultimate x fitting; columns that are not loads get no factor.
- ultimate_max = factor x max, ultimate_min = factor x min (limit loads times factor).
- margin of safety on each side: MS = allowable / (factor x load) - 1, with the `max`
  allowable against the max load and the `min` allowable against the min load. Negative
  loads: `min` allowables are given negative (compression -8 kN), so the ratio of two
  negatives is positive and MS reads as usual. A side whose load is zero or of the other
  sign than its allowable never loads that way: its margin is left empty (unbounded).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from loadcases.report.curves import LOAD_UNITS
from loadcases.report.envelope import EnvelopeRow

__all__ = ["LOAD_UNITS", "ULTIMATE", "apply_margins", "column_factor", "margin"]

ULTIMATE = "ultimate"


def column_factor(
    column: str, unit: str | None, factors: Mapping[str, float], named: bool = False
) -> float | None:
    """Ultimate x fitting factor of one column; None for a column that is not a load.

    `named`: the column is named by an allowable (then it is a load whatever its unit).
    """
    request = column.rsplit(".", 1)[0]
    fitting = factors.get(column, factors.get(request))
    if fitting is None and not named and unit not in LOAD_UNITS:
        return None
    return float(factors.get(ULTIMATE, 1.0)) * float(1.0 if fitting is None else fitting)


def margin(allowable: float | None, factor: float | None, load: float | None) -> float | None:
    """MS = allowable / (factor x load) - 1; None when not applicable (see module notes)."""
    if allowable is None or factor is None or load is None:
        return None
    ultimate = factor * load
    if ultimate == 0.0 or (ultimate > 0.0) != (allowable > 0.0):
        return None
    return allowable / ultimate - 1.0


def _limits(allowables: Mapping[str, Any], column: str) -> tuple[float | None, float | None]:
    """(max, min) allowables of a column; entries are objects or dicts with max/min."""
    entry = allowables.get(column)
    if entry is None:
        return None, None
    if isinstance(entry, Mapping):
        return entry.get("max"), entry.get("min")
    return getattr(entry, "max", None), getattr(entry, "min", None)


def apply_margins(
    rows: list[EnvelopeRow], factors: Mapping[str, float], allowables: Mapping[str, Any]
) -> list[EnvelopeRow]:
    """New rows with factor, ultimate loads, allowables and margins filled in."""
    out = []
    for row in rows:
        allow_max, allow_min = _limits(allowables, row.column)
        named = row.column in allowables
        factor = column_factor(row.column, row.unit, factors, named)
        out.append(
            replace(
                row,
                factor=factor,
                ultimate_max=None if factor is None or row.max is None else factor * row.max,
                ultimate_min=None if factor is None or row.min is None else factor * row.min,
                allowable_max=allow_max,
                allowable_min=allow_min,
                ms_max=margin(allow_max, factor, row.max),
                ms_min=margin(allow_min, factor, row.min),
            )
        )
    return out
