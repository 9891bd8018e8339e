"""Factors, ultimate loads and margins of safety on an envelope (SPEC 1.4 `factors`,
`allowables`; `case_factors`).

- `factors: {ultimate: 1.5, ROD: 1.15, ROD.value: 1.2}`: `ultimate` applies to every load
  column (unit N or N*m, or any column named in `factors` or `allowables`); any other key
  is a fitting (special) factor of a request `ROD` or of one column `ROD.value`, multiplied
  into the ultimate factor (a column key wins over its request's key). Columns that are not
  loads get no factor.
- `case_factors: {"freefall-*": 1.25}`: a factor of the runs whose name or case (family)
  matches the glob (`*`, `?`; brackets literal), every matching pattern multiplied in.
  The factor of a side of a row is ultimate x fitting x case factor of the run whose
  factored load governs: the largest case factor x max over the runs (the smallest x min
  for the min side); without case factors that is the envelope's max_run / min_run.
- ultimate_max = factor x load of that run (its limit load), likewise ultimate_min.
- margin of safety on each side: MS = allowable / (factor x load) - 1, the ultimate
  allowable (`max`/`min` or `ultimate:`) against the ultimate factor; the limit allowable
  (`limit:`) against the limit factor fitting x case factor (no ultimate factor). Negative
  loads: `min` allowables are given negative (compression -8 kN), so the ratio of two
  negatives is positive and MS reads as usual. A side whose load is zero or of the other
  sign than its allowable never loads that way: its margin is left empty (unbounded).
- a row marked `~0` (numerical noise: `loadcases.report.noise`) gets no factor, no
  ultimate load and no margin.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from loadcases.report.curves import LOAD_UNITS
from loadcases.report.envelope import EnvelopeRow
from loadcases.report.noise import NOISE_MARK
from loadcases.report.peaks import RunPeak
from loadcases.schema.setfile import matches

__all__ = [
    "LOAD_UNITS",
    "ULTIMATE",
    "apply_margins",
    "case_factor",
    "column_factor",
    "fitting_factor",
    "margin",
]

ULTIMATE = "ultimate"


def fitting_factor(
    column: str, unit: str | None, factors: Mapping[str, float], named: bool = False
) -> float | None:
    """The fitting factor of one column (1 when none is given); None for a column that is
    not a load. `named`: the column is named by an allowable (a load whatever its unit)."""
    request = column.rsplit(".", 1)[0]
    fitting = factors.get(column, factors.get(request))
    if fitting is None and not named and unit not in LOAD_UNITS:
        return None
    return float(1.0 if fitting is None else fitting)


def column_factor(
    column: str, unit: str | None, factors: Mapping[str, float], named: bool = False
) -> float | None:
    """Ultimate x fitting factor of one column; None for a column that is not a load."""
    fitting = fitting_factor(column, unit, factors, named)
    return None if fitting is None else float(factors.get(ULTIMATE, 1.0)) * fitting


def case_factor(run: str, family: str, case_factors: Mapping[str, float]) -> float:
    """Product of the factors whose glob pattern matches the run's name or its family."""
    factor = 1.0
    for pattern, value in case_factors.items():
        if matches(run, pattern) or matches(family, pattern):
            factor *= float(value)
    return factor


def margin(allowable: float | None, factor: float | None, load: float | None) -> float | None:
    """MS = allowable / (factor x load) - 1; None when not applicable (see module notes)."""
    if allowable is None or factor is None or load is None:
        return None
    ultimate = factor * load
    if ultimate == 0.0 or (ultimate > 0.0) != (allowable > 0.0):
        return None
    return allowable / ultimate - 1.0


def _limits(allowables: Mapping[str, Any], column: str) -> tuple[float | None, ...]:
    """(ultimate max, ultimate min, limit max, limit min) allowables of a column; entries
    are `Allowable` objects or dicts with max/min."""
    entry = allowables.get(column)
    if entry is None:
        return None, None, None, None
    if isinstance(entry, Mapping):
        return entry.get("max"), entry.get("min"), None, None
    return (*entry.ultimate_limits(), *entry.limit_limits())


def _governing(
    row: EnvelopeRow, side: str, peaks: Sequence[RunPeak], case_factors: Mapping[str, float]
) -> tuple[float, float | None, str | None]:
    """(case factor, limit load, run) whose factored load governs `side` of `row`."""
    if not case_factors or not peaks:
        return 1.0, getattr(row, side), getattr(row, f"{side}_run")
    sign = 1.0 if side == "max" else -1.0
    best: tuple[float, float | None, str | None] = (1.0, None, None)
    for peak in peaks:
        load = getattr(peak, side)
        factor = case_factor(peak.run, peak.family, case_factors)
        if load is not None and (
            best[1] is None or sign * factor * load > sign * best[0] * best[1]
        ):
            best = (factor, load, peak.run)
    return best


def _factored(
    row: EnvelopeRow,
    fitting: float,
    ultimate: float,
    peaks: Sequence[RunPeak],
    case_factors: Mapping[str, float],
    limits: tuple[float | None, ...],
) -> dict[str, Any]:
    """The factor, ultimate load, governing run and margins of both sides of a load row."""
    changes: dict[str, Any] = {}
    for k, side in enumerate(("max", "min")):
        cf, load, run = _governing(row, side, peaks, case_factors)
        factor = ultimate * fitting if cf == 1.0 else ultimate * fitting * cf
        changes["factor" if side == "max" else "factor_min"] = factor
        changes[f"ultimate_{side}"] = None if load is None else factor * load
        changes[f"ultimate_{side}_run"] = run
        changes[f"ms_{side}"] = margin(limits[k], factor, load)
        changes[f"ms_limit_{side}"] = margin(limits[2 + k], fitting * cf, load)
    return changes


def apply_margins(
    rows: list[EnvelopeRow],
    factors: Mapping[str, float],
    allowables: Mapping[str, Any],
    *,
    case_factors: Mapping[str, float] | None = None,
    peaks: Mapping[str, Sequence[RunPeak]] | None = None,
    noise: frozenset[str] | set[str] = frozenset(),
) -> list[EnvelopeRow]:
    """New rows with factors, ultimate loads, allowables and margins filled in; `peaks`
    (`loadcases.report.peaks.run_peaks`) are needed for `case_factors`; rows of `noise`
    are marked `~0`."""
    ultimate = float(factors.get(ULTIMATE, 1.0))
    out = []
    for row in rows:
        limits = _limits(allowables, row.column)
        shown: dict[str, Any] = dict(zip(("allowable_max", "allowable_min"), limits[:2]))
        shown.update(zip(("limit_allowable_max", "limit_allowable_min"), limits[2:]))
        fitting = fitting_factor(row.column, row.unit, factors, row.column in allowables)
        if row.column in noise:
            out.append(replace(row, noise=NOISE_MARK, **shown))
        elif fitting is None:
            out.append(replace(row, **shown))
        else:
            changes = _factored(
                row,
                fitting,
                ultimate,
                (peaks or {}).get(row.column, ()),
                case_factors or {},
                limits,
            )
            out.append(replace(row, **shown, **changes))
    return out
