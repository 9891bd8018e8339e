"""Reference curves of a set (`curves:`): external curves read from CSV, checked against the
set's cases.

A reference file is a CSV table as a spreadsheet exports it: a header row whose every cell
is `NAME [unit]` (`latch angle [deg], P2P6 [N]`; `[-]` for a number without unit), then
one row per point. The first column is the abscissa, increasing down the file; the others
are curves. Cells are plain numbers, read as text (never expressions). Values are kept in
SI (`to_si` of the header's unit). The path is relative to the set file and stays inside
its folder tree. Problems name the CSV file, line and column, or the set's key.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.limits import MAX_HARDPOINT_BYTES, local_path_problem
from loadcases.foundation.units import UnitError, to_si
from loadcases.inputs.hardpoints import split_cells
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import Locator

__all__ = ["ReferenceTable", "check_reference_curves", "read_reference_table", "reference_path"]

_HEADER = re.compile(r"^(?P<name>.*?)\s*\[(?P<unit>[^\[\]]*)\]\s*$")
_NO_UNIT = ("-", "", "1")
MAX_REFERENCE_POINTS = 100_000


@dataclass
class ReferenceTable:
    """A reference CSV: `x` (n,) SI on the first column `x_header`; `columns` {header:
    (n,) SI}; `units` {header: unit as written}; `problems` as diagnostics."""

    path: Path
    x_header: str = ""
    x: np.ndarray = field(default_factory=lambda: np.empty(0))
    columns: dict[str, np.ndarray] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    problems: list[Diagnostic] = field(default_factory=list)

    def problem(self, line: int, column: int, key: str, message: str) -> None:
        self.problems.append(Diagnostic(str(self.path), line, column, key, message))


def _scale(unit: str) -> float:
    """SI value of one `unit` (1 for `-`); raises UnitError."""
    return 1.0 if unit.strip() in _NO_UNIT else to_si(f"1 {unit.strip()}", "any")


def _header(table: ReferenceTable, cells: list[tuple[int, str]]) -> list[float] | None:
    """The scale of each header cell, or None (problems recorded)."""
    scales = []
    for col, text in cells:
        match = _HEADER.match(text)
        if match is None or not match["name"]:
            table.problem(1, col, text, f"header '{text}' has no unit: write it 'NAME [unit]'")
            return None
        try:
            scales.append(_scale(match["unit"]))
        except UnitError as error:
            table.problem(1, col, text, f"unit of '{text}': {error}")
            return None
        table.units[text] = match["unit"].strip()
    return scales


def read_reference_table(path: Path) -> ReferenceTable:
    """Every point of a reference CSV in SI, and every problem of it."""
    table = ReferenceTable(path)
    lines = path.read_text(encoding="utf-8-sig").splitlines()
    numbered = [(n, line) for n, line in enumerate(lines, start=1) if line.strip()]
    if not numbered:
        table.problem(1, 1, "header", "empty file: expected a header 'x [unit], NAME [unit], ...'")
        return table
    header = split_cells(numbered[0][1])
    scales = _header(table, header)
    if scales is None:
        return table
    if len(numbered) - 1 > MAX_REFERENCE_POINTS:
        table.problem(numbered[0][0], 1, "", f"more than {MAX_REFERENCE_POINTS:,} points")
        return table
    names = [text for _, text in header]
    rows = []
    for number, line in numbered[1:]:
        cells = split_cells(line)
        if len(cells) != len(names):
            table.problem(number, 1, "", f"expected {len(names)} cells, got {len(cells)}")
            continue
        row = []
        for (col, text), name, scale in zip(cells, names, scales):
            value = _number(text)
            if value is None:
                table.problem(number, col, name, f"expected a finite number, got '{text[:40]}'")
            row.append((value or 0.0) * scale)
        rows.append(row)
    values = np.array(rows, dtype=float).reshape(-1, len(names))
    table.x_header, table.x = names[0], values[:, 0]
    table.columns = {name: values[:, k] for k, name in enumerate(names) if k > 0}
    if table.x.size < 2 or not np.all(np.diff(table.x) > 0.0):
        table.problem(
            numbered[0][0],
            1,
            names[0],
            "expected 2 points or more, the abscissa increasing down the file",
        )
    return table


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def reference_path(set_path: str | Path, file: str) -> tuple[Path | None, str | None]:
    """The reference CSV named by a set (relative to it), or why it cannot be read."""
    folder = Path(os.path.dirname(str(set_path)) or ".")
    problem = local_path_problem(file.strip(), folder, "the set file")
    if problem is not None:
        return None, problem
    path = folder / file.strip()
    if not path.is_file():
        return None, f"reference file not found: {path}"
    if path.stat().st_size > MAX_HARDPOINT_BYTES:
        return None, f"{path}: larger than {MAX_HARDPOINT_BYTES:,} bytes"
    return path, None


def _case_of(name: str, cases: Sequence[Any]) -> Any | None:
    """The loaded case (CaseFile) that `name` (a case or one of its runs) names."""
    family = name.split("[")[0]
    return next((cf for cf in cases if cf.case.case == family), None)


def check_reference_curves(
    model: Any, at: Locator, set_path: str | Path, cases: Sequence[Any]
) -> list[Diagnostic]:
    """Every problem of the set's `curves:`: the file (inside the set's folder, readable),
    its headers, the case (one of the set's, with an abscissa equal to `x`) and the
    columns (a request of the case; a header of the file)."""
    found: list[Diagnostic] = []
    for name, curve in model.curves.items():
        key = ("curves", name)
        path, problem = reference_path(set_path, curve.file)
        if problem is not None:
            found.append(at.diagnostic((*key, "file"), problem))
        else:
            assert path is not None
            table = read_reference_table(path)
            found += table.problems
            found += _missing_headers(at, key, curve.columns, table)
        found += _case_problems(at, key, curve, cases)
    return found


def _missing_headers(
    at: Locator, key: tuple[str, ...], columns: dict[str, str], table: ReferenceTable
) -> list[Diagnostic]:
    if table.problems:
        return []
    return [
        at.diagnostic(
            (*key, "columns", column),
            f"no column '{header}' in {table.path.name}",
            hint=did_you_mean(header, list(table.columns)),
        )
        for column, header in columns.items()
        if header not in table.columns
    ]


def _case_problems(
    at: Locator, key: tuple[str, ...], curve: Any, cases: Sequence[Any]
) -> list[Diagnostic]:
    cf = _case_of(curve.case, cases)
    if cf is None:
        names = [c.case.case for c in cases]
        return [
            at.diagnostic(
                (*key, "case"),
                f"no case '{curve.case}' in this set",
                hint=did_you_mean(curve.case.split("[")[0], names),
            )
        ]
    abscissa = cf.case.abscissa
    if abscissa is None:
        return [at.diagnostic((*key, "case"), f"case '{cf.case.case}' has no abscissa: add one")]
    found = []
    if curve.x is not None and "".join(curve.x.split()) != "".join(str(abscissa).split()):
        found.append(
            at.diagnostic(
                (*key, "x"), f"case '{cf.case.case}' has the abscissa '{abscissa}', not '{curve.x}'"
            )
        )
    requests = set(cf.case.requests)
    found += [
        at.diagnostic(
            (*key, "columns", column),
            f"no request '{column.split('.')[0]}' in case '{cf.case.case}'",
            hint=did_you_mean(column.split(".")[0], sorted(requests)),
        )
        for column in curve.columns
        if column.split(".")[0] not in requests
    ]
    return found
