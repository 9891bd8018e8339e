"""Run-by-run comparisons of a set (`comparisons:`, docs/user-guide.md): for each chosen
result column, the peak of the reference run and of each compared run, where it occurs,
and the ratio run / reference.

The peak of a column is its value of largest magnitude, with its sign (a latch-up torque
of -80 N*m peaks at -80); the ratio divides the signed peaks, so a load that changes side
shows a negative ratio. A reference peak within NOISE_FLOOR of the column's largest peak
in the comparison is round-off (the out-of-plane loads of a planar rigid model, 1e-23 N
beside 0.7 N): the ratio is left empty. A column a run does not have (or a failed run) is
left empty. A column `REF = RUN` (`latch_hl3.value = hl3_lock.tz`) pairs two columns that
stand for one quantity in two models: the reference's peak of REF beside the runs' peaks
of RUN (a latch spring's torque in a rigid model, a locked joint's reaction in a flexible
one); `-RUN` negates it (a reaction on the other body). Read from the saved runs alone:
`comparisons.csv` in SI, the workbook sheet `Comparison` in the report's units.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.foundation.atomic import atomic_write_text
from loadcases.foundation.clip import visible_fields
from loadcases.report.roundoff import NOISE_FLOOR
from loadcases.results.saved import SavedRun

__all__ = [
    "COMPARISON_FILE",
    "ComparedPeak",
    "comparison_rows",
    "comparison_sheet",
    "write_comparison_csv",
]

COMPARISON_FILE = "comparisons.csv"
_CSV_HEADER = ("comparison", "column", "unit", "run", "peak", "time", "ratio")


@dataclass(frozen=True)
class ComparedPeak:
    """One column of one run in a comparison: its signed peak and time (None when the run
    lacks the column), and its ratio to the reference's peak (None when undefined)."""

    comparison: str
    column: str
    unit: str
    run: str
    peak: float | None
    time: float | None
    ratio: float | None
    time_unit: str = "s"


def _peak(run: SavedRun | None, column: str) -> tuple[float | None, float | None]:
    """Signed value of largest magnitude of `column` (`-COLUMN`: negated) in `run`, and its
    time (s)."""
    sign = -1.0 if column.startswith("-") else 1.0
    column = column.removeprefix("-").strip()
    if run is None or column not in run.channels or run.status != "ok":
        return None, None
    values = sign * np.asarray(run.channels[column], dtype=float)
    finite = np.isfinite(values)
    if not finite.any():
        return None, None
    i = int(np.argmax(np.where(finite, np.abs(values), -1.0)))
    return float(values[i]), float(run.time[i])


def _columns(wanted: Sequence[str], run: SavedRun | None) -> list[str]:
    """The columns named: `REQUEST.COMPONENT` as given, `REQUEST` as its components in the
    reference run's order (or as given when the reference lacks it)."""
    out: list[str] = []
    for key in wanted:
        if "=" in key:  # a pair, as given
            out.append(" = ".join(side.strip() for side in key.split("=", 1)))
            continue
        parts = [c for c in (run.channels if run else ()) if c.split(".")[0] == key]
        out += [key] if "." in key or not parts else parts
    return list(dict.fromkeys(out))


def _sides(column: str) -> tuple[str, str]:
    """(the reference's column, the runs' column): `REF = RUN` or one column for both."""
    ref, _, run = column.partition(" = ")
    return ref, run or ref


def comparison_rows(comparisons: Mapping[str, Any], runs: Sequence[SavedRun]) -> list[ComparedPeak]:
    """Per comparison (`loadcases.schema.setfile.Comparison`) and column: the reference's
    peak (ratio 1, or None when it has no peak) then each compared run's."""
    by_name = {run.name: run for run in runs}
    rows: list[ComparedPeak] = []
    for name, comparison in comparisons.items():
        reference = by_name.get(comparison.reference)
        for column in _columns(comparison.columns, reference):
            names = [comparison.reference, *comparison.runs]
            ref_column, run_column = _sides(column)
            sides = dict.fromkeys(names, run_column) | {comparison.reference: ref_column}
            peaks = {n: _peak(by_name.get(n), sides[n]) for n in names}
            ref_peak = peaks[comparison.reference][0]
            largest = max((abs(p) for p, _ in peaks.values() if p is not None), default=0.0)
            for run_name in names:
                run = by_name.get(run_name)
                peak, time = peaks[run_name]
                ratio = None
                if peak is not None and ref_peak and abs(ref_peak) > NOISE_FLOOR * largest:
                    ratio = peak / ref_peak
                known = [(r, c) for r, c in ((run, sides[run_name]), (reference, ref_column)) if r]
                unit = known[0][0].units.get(known[0][1].lstrip("- "), "") if known else ""
                clock = known[0][0].units.get("time", "s") if known else "s"
                rows.append(ComparedPeak(name, column, unit, run_name, peak, time, ratio, clock))
    return rows


def _text(value: float | None) -> str:
    return "" if value is None or not math.isfinite(value) else repr(value)


def write_comparison_csv(rows: Sequence[ComparedPeak], path: Path) -> Path:
    """`comparisons.csv` (SI): one line per comparison, column and run; written whole."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(_CSV_HEADER)
    for r in rows:
        names = (r.comparison, r.column, r.unit, r.run)
        writer.writerow(visible_fields((*names, _text(r.peak), _text(r.time), _text(r.ratio))))
    atomic_write_text(path, out.getvalue())
    return path


def comparison_sheet(sheet: Any, rows: Sequence[ComparedPeak]) -> None:
    """Fill `sheet`: per comparison a block, one line per column, and per run the peak
    (in the line's unit), its time (unit in the header) and the ratio to the reference."""
    line = 1
    blocks: dict[str, list[ComparedPeak]] = {}
    for r in rows:
        blocks.setdefault(r.comparison, []).append(r)
    for name, block in blocks.items():
        run_names = list(dict.fromkeys(r.run for r in block))
        clock = block[0].time_unit
        heads = ["comparison", "column", "unit"]
        for k, run in enumerate(run_names):
            heads += [f"{run} peak", f"{run} at [{clock}]"]
            heads += [] if k == 0 else [f"{run} / reference"]
        for column, title in enumerate(heads, start=1):
            sheet.cell(row=line, column=column, value=title).style = "loads header"
        for column_name in dict.fromkeys(r.column for r in block):
            line += 1
            cells = [r for r in block if r.column == column_name]
            values: list[Any] = [name, column_name, cells[0].unit]
            for k, r in enumerate(cells):
                values += [r.peak, r.time] + ([] if k == 0 else [r.ratio])
            for column, value in enumerate(values, start=1):
                sheet.cell(row=line, column=column, value=value)
        line += 2
    sheet.freeze_panes = "D2"
    sheet.column_dimensions["B"].width = 28
