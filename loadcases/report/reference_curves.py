"""Reference curves against the runs of a set (`curves:`): each reference curve beside the
run's curve of the same quantity over the case's abscissa, and their difference.

For each curve, column and run of the case (every ok run of it, or the one run named): the
run's column is interpolated linearly on its abscissa (`abscissa.value`, which must go one
way only: a run whose abscissa goes back and forth is not compared) at the reference's
points inside the run's range (within ENDS of its length at either end). The difference
is run - reference (SI):
- `max_difference`: the signed difference of largest magnitude, `at` its abscissa;
- `of_peak`: max_difference / the reference's peak magnitude over the compared points;
- `max_relative`: the largest |run - reference| / |reference| over the points where the
  reference is at least RELATIVE_FLOOR of its peak (near its zero crossings a relative
  difference says nothing), `relative_at` its abscissa.
Written as `reference-curves.csv` (SI) and the workbook's `Reference curves` sheet; the
curves themselves are drawn by `loadcases.report.reference_plots` and the sheet's charts.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.foundation.atomic import atomic_write_text
from loadcases.foundation.units import dimension_mismatch
from loadcases.inputs.reference_tables import ReferenceTable
from loadcases.report.csv_rows import rows_csv_text
from loadcases.results.saved import SavedRun

__all__ = [
    "REFERENCE_FILE",
    "RELATIVE_FLOOR",
    "CurveDifference",
    "Overlay",
    "in_report_units",
    "overlays",
    "reference_csv_text",
    "write_reference_csv",
]

REFERENCE_FILE = "reference-curves.csv"
RELATIVE_FLOOR = 0.05  # of the reference's peak: below it no relative difference is taken
ENDS = 1e-9  # of the run's abscissa range: a reference point that near its ends is inside


@dataclass(frozen=True)
class CurveDifference:
    """The difference of one run's column from one reference curve (SI; None: none)."""

    curve: str
    column: str
    reference: str
    run: str
    unit: str
    abscissa_unit: str
    points: int
    max_difference: float | None
    at: float | None
    of_peak: float | None
    max_relative: float | None
    relative_at: float | None
    note: str = ""


DIFFERENCE_COLUMNS = tuple(f.name for f in fields(CurveDifference))


@dataclass
class Overlay:
    """A run's curve and a reference curve of one column, for plots and charts (SI):
    the run's `x`, `y` and the reference's `ref_x`, `ref_y`; `label` the reference's."""

    curve: str
    column: str
    run: str
    label: str
    abscissa: str
    unit: str
    abscissa_unit: str
    x: np.ndarray
    y: np.ndarray
    ref_x: np.ndarray
    ref_y: np.ndarray
    difference: CurveDifference


def _one_way(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The run's (x, y) with x increasing (reversed if it decreases), finite rows only;
    None if x goes back and forth."""
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    if x.size < 2:
        return None
    steps = np.diff(x)
    if np.all(steps >= 0.0):
        return x, y
    if np.all(steps <= 0.0):
        return x[::-1], y[::-1]
    return None


def difference(
    x: np.ndarray, y: np.ndarray, ref_x: np.ndarray, ref_y: np.ndarray
) -> tuple[int, float | None, float | None, float | None, float | None, float | None]:
    """(points, max_difference, at, of_peak, max_relative, relative_at) of a run's curve
    (x increasing) against the reference's points inside its range."""
    tol = ENDS * (x[-1] - x[0])  # a run ending at 110 deg within round-off covers 110 deg
    inside = (ref_x >= x[0] - tol) & (ref_x <= x[-1] + tol)
    if not inside.any():
        return 0, None, None, None, None, None
    rx, ry = ref_x[inside], ref_y[inside]
    diff = np.interp(rx, x, y) - ry
    k = int(np.argmax(np.abs(diff)))
    peak = float(np.max(np.abs(ry)))
    of_peak = float(diff[k] / peak) if peak > 0.0 else None
    counted = np.abs(ry) >= RELATIVE_FLOOR * peak if peak > 0.0 else np.zeros_like(ry, bool)
    if not counted.any():
        return int(rx.size), float(diff[k]), float(rx[k]), of_peak, None, None
    relative = np.where(counted, np.abs(diff) / np.where(counted, np.abs(ry), 1.0), -1.0)
    j = int(np.argmax(relative))
    return int(rx.size), float(diff[k]), float(rx[k]), of_peak, float(relative[j]), float(rx[j])


def _overlay(
    name: str, curve: Any, column: str, table: ReferenceTable, run: SavedRun, abscissa: str
) -> Overlay:
    header = curve.columns[column]
    unit = run.units.get(column, "")
    x_unit = run.units.get(ABSCISSA_COLUMN, "")
    ref_x, ref_y = table.x, table.columns[header]
    empty = np.empty(0)
    x, y = run.channels.get(ABSCISSA_COLUMN), run.channels.get(column)
    note = ""
    if x is None or y is None:
        note = f"the run has no column {column if y is None else ABSCISSA_COLUMN}"
    elif (why := _unit_problem(table, header, unit, table.x_header, x_unit)) is not None:
        note = why
    elif (one_way := _one_way(np.asarray(x, float), np.asarray(y, float))) is None:
        note = "the run's abscissa goes back and forth: not compared"
    numbers: tuple[int, float | None, float | None, float | None, float | None, float | None]
    numbers = (0, None, None, None, None, None)
    if not note:
        x, y = one_way  # type: ignore[misc]
        numbers = difference(x, y, ref_x, ref_y)
        note = "" if numbers[0] else "no reference point inside the run's abscissa range"
    else:
        x, y = (empty, empty) if x is None or y is None else (x, y)
    diff = CurveDifference(name, column, header, run.name, unit, x_unit, *numbers, note=note)
    return Overlay(
        name, column, run.name, curve.label, abscissa, unit, x_unit, x, y, ref_x, ref_y, diff
    )


def _unit_problem(
    table: ReferenceTable, header: str, unit: str, x_header: str, x_unit: str
) -> str | None:
    """Why the reference's units do not fit the run's columns (SI units), or None."""
    for name, si in ((header, unit), (x_header, x_unit)):
        written = table.units.get(name, "-")
        if (
            si
            and written not in ("-", "", "1")
            and dimension_mismatch(f"1 {written}", f"1 {si}") is not None
        ):
            return f"'{name}' is not in a unit of the run's {si}"
    return None


def overlays(
    curves: Mapping[str, Any],
    tables: Mapping[str, ReferenceTable],
    runs: Sequence[SavedRun],
    abscissae: Mapping[str, str],
) -> list[Overlay]:
    """One overlay per curve, column and ok run of its case (`abscissae` {case: its
    abscissa expression}); `tables` {curve name: its read reference table}."""
    out = []
    for name, curve in curves.items():
        table = tables[name]
        chosen = [
            run
            for run in runs
            if run.status == "ok" and (run.name == curve.case or run.family == curve.case)
        ]
        for column in curve.columns:
            for run in chosen:
                abscissa = abscissae.get(run.family, ABSCISSA_COLUMN)
                out.append(_overlay(name, curve, column, table, run, abscissa))
    return out


def reference_csv_text(rows: Sequence[CurveDifference]) -> str:
    """`reference-curves.csv`: one line per curve, column and run (SI)."""
    return rows_csv_text(DIFFERENCE_COLUMNS, rows)


def write_reference_csv(rows: Sequence[CurveDifference], path: Path) -> Path:
    """Write `reference-curves.csv` atomically."""
    return atomic_write_text(path, reference_csv_text(rows))


def in_report_units(overlay: Overlay, units: Any) -> Overlay:
    """The overlay in the report's units (`loadcases.report.units.ReportUnits`)."""
    u, xu = overlay.unit, overlay.abscissa_unit
    d = overlay.difference
    shown = replace(
        d,
        unit=units.unit(u) or "",
        abscissa_unit=units.unit(xu) or "",
        max_difference=units.value(d.max_difference, u),
        at=units.value(d.at, xu),
        relative_at=units.value(d.relative_at, xu),
    )
    return replace(
        overlay,
        unit=shown.unit,
        abscissa_unit=shown.abscissa_unit,
        x=units.array(overlay.x, xu),
        y=units.array(overlay.y, u),
        ref_x=units.array(overlay.ref_x, xu),
        ref_y=units.array(overlay.ref_y, u),
        difference=shown,
    )
