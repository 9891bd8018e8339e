"""The `Torque margin` sheet of a set's workbook: per run and hinge line, the minimum TM and
restart TM along the run (seed 003 eq. 2.1), where they occur and the verdict; a hinge line
below the required ratio is shown red. Read from the runs' `tm_HL.*` columns alone
(loadcases/torque_margin.py), so saved results give the same sheet."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from loadcases.build.torque_margin import TM_PREFIX
from loadcases.results.saved import SavedRun

__all__ = ["TM_SHEET_COLUMNS", "has_torque_margin", "margin_rows", "torque_margin_sheet"]

TM_SHEET_COLUMNS = (
    "run",
    "hinge line",
    "required",
    "min TM",
    "angle at min [deg]",
    "time at min [s]",
    "min restart TM",
    "restart angle at min [deg]",
    "driving at min [N*m]",
    "resistive at min [N*m]",
    "verdict",
)


def _hinge_lines(run: SavedRun) -> list[str]:
    return [
        c[len(TM_PREFIX) : -len(".ratio")]
        for c in run.channels
        if c.startswith(TM_PREFIX) and c.endswith(".ratio")
    ]


def has_torque_margin(runs: list[SavedRun]) -> bool:
    """True when a run carries torque-margin columns."""
    return any(_hinge_lines(run) for run in runs)


def _minimum(values: np.ndarray) -> int | None:
    finite = np.isfinite(values)
    return int(np.argmin(np.where(finite, values, np.inf))) if finite.any() else None


def margin_rows(run: SavedRun) -> list[tuple]:
    """One row per hinge line of `run` (TM_SHEET_COLUMNS); required = (D - excess) / R."""
    out: list[tuple] = []
    for line in _hinge_lines(run):
        ch = {
            c: run.channels[f"{TM_PREFIX}{line}.{c}"]
            for c in ("driving", "resistive", "ratio", "restart_ratio", "excess", "angle")
        }
        has_r = ch["resistive"] > 0
        required = (
            float(np.median((ch["driving"] - ch["excess"])[has_r] / ch["resistive"][has_r]))
            if has_r.any()
            else math.nan
        )
        i, j = _minimum(ch["ratio"]), _minimum(ch["restart_ratio"])
        if i is None or j is None:
            out.append((run.name, line, required) + (None,) * 7 + ("undefined",))
            continue
        passed = (
            ch["ratio"][i] >= required
            and ch["restart_ratio"][j] >= required
            and bool(np.all(np.isfinite(ch["ratio"])))
            and run.status == "ok"
        )
        out.append(
            (
                run.name,
                line,
                required,
                float(ch["ratio"][i]),
                math.degrees(ch["angle"][i]),
                float(run.time[i]),
                float(ch["restart_ratio"][j]),
                math.degrees(ch["angle"][j]),
                float(ch["driving"][i]),
                float(ch["resistive"][i]),
                "pass" if passed else "FAIL",
            )
        )
    return out


def torque_margin_sheet(sheet: Any, runs: list[SavedRun]) -> None:
    """Fill `sheet` with the rows of every run that has a torque margin."""
    rows = [row for run in runs for row in margin_rows(run)]
    for column, title in enumerate(TM_SHEET_COLUMNS, start=1):
        sheet.cell(row=1, column=column, value=title).style = "loads header"
    for r, row in enumerate(rows, start=2):
        for column, value in enumerate(row, start=1):
            sheet.cell(row=r, column=column, value=value)
        if row[-1] != "pass":
            for column in (4, 7, len(TM_SHEET_COLUMNS)):
                sheet.cell(row=r, column=column).style = "loads failed"
    sheet.freeze_panes = "C2"
    sheet.column_dimensions["A"].width = 40
