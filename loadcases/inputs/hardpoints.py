"""Hardpoint tables: `points: {from: hardpoints.csv}` reads named points from a CSV file as
CAD exports them.

The file has a header row with the columns `name, body, x, y, z, units` (any order, any
case; further columns are ignored with a warning), then one point per row: `x, y, z` its
design position in the global frame, in the length unit of the `units` cell (`mm`, `in`;
empty: the length unit of the mechanism file's `units:` header, else m). The path is
relative to the file that holds the mechanism and stays inside its folder tree. The file is
only read as text: a cell is a name, a plain number or a unit name, never an expression.
Points may also be given inline beside `from:`; a name given in both places is an error.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from loadcases.foundation.clip import describe_character, hidden_character
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.limits import MAX_HARDPOINT_BYTES, MAX_HARDPOINTS, local_path_problem
from loadcases.foundation.units import SIValue, UnitError, check_unit_name, to_si
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import Locator

__all__ = ["COLUMNS", "FROM_KEY", "expand_hardpoints", "split_cells"]

FROM_KEY = "from"
COLUMNS = ("name", "body", "x", "y", "z", "units")
_UNIT_NAME = re.compile(r"[A-Za-z_]+")


def split_cells(line: str) -> list[tuple[int, str]]:
    """(1-based column, text) of each comma-separated cell of one CSV line, stripped of
    blanks; a cell in double quotes may hold commas (`""` inside is a quote)."""
    cells: list[tuple[int, str]] = []
    index = 0
    while True:
        while index < len(line) and line[index] in " \t":
            index += 1
        col = index + 1
        text = ""
        if index < len(line) and line[index] == '"':
            text, index = _quoted(line, index + 1)
            col += 1
        end = line.find(",", index)
        end = len(line) if end < 0 else end
        cells.append((col, (text + line[index:end]).strip()))
        if end >= len(line):
            return cells
        index = end + 1


def _quoted(line: str, index: int) -> tuple[str, int]:
    """The text of a quoted cell starting at `index` (after its quote) and the index after
    its closing quote (the end of the line if it has none)."""
    text = ""
    while index < len(line):
        if line[index] == '"':
            if line[index + 1 : index + 2] != '"':
                return text, index + 1
            index += 1
        text += line[index]
        index += 1
    return text, index


class _Table:
    """One hardpoint file being read: its problems and the points found."""

    def __init__(self, path: Path, bodies: list[str], length_unit: str | None) -> None:
        self.path, self.bodies, self.length_unit = path, bodies, length_unit
        self.points: dict[str, dict[str, Any]] = {}
        self.lines: dict[str, int] = {}
        self.problems: list[Diagnostic] = []

    def problem(self, line: int, col: int, key: str, message: str, **extra: Any) -> None:
        self.problems.append(Diagnostic(str(self.path), line, col, key, message, **extra))

    def header(self, line: int, cells: list[tuple[int, str]]) -> dict[str, int] | None:
        """Column name -> cell index; None (with a problem) if a column is missing."""
        index: dict[str, int] = {}
        for position, (col, text) in enumerate(cells):
            name = text.lower()
            if name in index:
                self.problem(line, col, name, f"column '{name}' given twice")
            elif name not in COLUMNS:
                self.problem(
                    line,
                    col,
                    name,
                    f"unknown column '{text}' (ignored)",
                    severity="warning",
                    hint=did_you_mean(name, COLUMNS) or f"the columns are {', '.join(COLUMNS)}",
                )
            index.setdefault(name, position)
        missing = [name for name in COLUMNS if name not in index]
        if missing:
            self.problem(
                line,
                1,
                "header",
                f"missing column{'s' if len(missing) > 1 else ''} "
                f"{', '.join(missing)}: the header row names {', '.join(COLUMNS)}",
            )
            return None
        return index

    def row(self, line: int, cells: list[tuple[int, str]], index: dict[str, int]) -> None:
        """Check one point row and keep it as `{body, at}` (SI) if it is good."""
        if len(cells) <= max(index.values()):
            self.problem(line, 1, "", f"expected {max(index.values()) + 1} cells, got {len(cells)}")
            return
        cell = {name: cells[index[name]] for name in COLUMNS}
        name_col, name = cell["name"]
        body_col, body = cell["body"]
        ok = self._name(line, name_col, name) & self._body(line, body_col, body)
        unit = self._unit(line, *cell["units"])
        at = [self._coordinate(line, *cell[axis], axis, unit) for axis in "xyz"]
        if ok and unit is not None and None not in at:
            self.points[name] = {"body": body, "at": at}
            self.lines[name] = line

    def _name(self, line: int, col: int, name: str) -> bool:
        if not name:
            self.problem(line, col, "name", "empty point name")
            return False
        hidden = hidden_character(name)
        if hidden is not None:  # as in a key of the YAML files (loadcases.yamlfiles.source)
            self.problem(
                line,
                col,
                "name",
                f"the point name holds {describe_character(hidden)}, a character not shown "
                "as written",
                hint="retype the name: names hold no control, bidirectional or zero-width "
                "characters",
            )
            return False
        if name in self.lines:
            self.problem(
                line, col, "name", f"point '{name}' given twice (first on line {self.lines[name]})"
            )
            return False
        return True

    def _body(self, line: int, col: int, body: str) -> bool:
        if body in self.bodies:
            return True
        self.problem(
            line,
            col,
            "body",
            f"unknown body '{body}'",
            hint=did_you_mean(body, self.bodies) or f"bodies: {', '.join(self.bodies)}",
        )
        return False

    def _unit(self, line: int, col: int, text: str) -> str | None:
        """The length unit of the row (the file's when empty), or None if unknown."""
        if not text:
            return self.length_unit or "m"
        try:
            if not _UNIT_NAME.fullmatch(text):
                raise UnitError(f"unknown unit '{text}'")
            return check_unit_name(text, "length")
        except UnitError as error:
            self.problem(line, col, "units", str(error), hint="use a length unit: mm, m, in, ft")
            return None

    def _coordinate(
        self, line: int, col: int, text: str, axis: str, unit: str | None
    ) -> SIValue | None:
        """SI value of one coordinate cell, converted as a bare number under a `units:`
        header would be (so that a table and the same points inline give equal numbers)."""
        try:
            number = float(text)
        except ValueError:
            self.problem(line, col, axis, f"expected a number, got '{text}'")
            return None
        if not math.isfinite(number):
            self.problem(line, col, axis, f"expected a finite number, got '{text}'")
            return None
        if unit is None:
            return None
        return SIValue(to_si(number, "length", {"length": unit}))


def _read_table(path: Path, bodies: list[str], length_unit: str | None) -> _Table:
    """Every point of a hardpoint file and every problem of it."""
    table = _Table(path, bodies, length_unit)
    text = path.read_text(encoding="utf-8-sig")
    index = None
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        cells = split_cells(line)
        if index is None:
            index = table.header(number, cells)
            if index is None:
                return table
        elif len(table.lines) >= MAX_HARDPOINTS:
            table.problem(number, 1, "", f"more than {MAX_HARDPOINTS:,} points")
            return table
        else:
            table.row(number, cells, index)
    if index is None:
        table.problem(1, 1, "header", f"empty file: expected a header row {', '.join(COLUMNS)}")
    return table


def _table_path(locator: Locator, source: Any) -> tuple[Path | None, Diagnostic | None]:
    """The hardpoint file named by `from:` or why it cannot be read."""
    key = ("points", FROM_KEY)
    if not isinstance(source, str) or not source.strip():
        return None, locator.diagnostic(key, "expected the name of a CSV file, e.g. hardpoints.csv")
    folder = Path(os.path.dirname(locator.tree.file) or ".")
    problem = local_path_problem(source.strip(), folder, "the file that holds the mechanism")
    if problem is not None:
        return None, locator.diagnostic(key, problem)
    path = folder / source.strip()
    if not path.is_file():
        return None, locator.diagnostic(key, f"hardpoint file not found: {path}")
    if path.stat().st_size > MAX_HARDPOINT_BYTES:
        return None, locator.diagnostic(key, f"{path}: larger than {MAX_HARDPOINT_BYTES:,} bytes")
    return path, None


def expand_hardpoints(
    locator: Locator, file_units: Mapping[str, str]
) -> tuple[list[bytes], list[Diagnostic]]:
    """Put the points of `points.from` (a hardpoint CSV) into the raw mechanism data of
    `locator`, in place, beside the inline ones; return the bytes of the file read (for
    the input hash) and every problem found (in the CSV: its line, column and column name)."""
    data = locator.data
    points = data.get("points") if isinstance(data, dict) else None
    if not isinstance(points, dict) or FROM_KEY not in points:
        return [], []
    source = points.pop(FROM_KEY)
    path, problem = _table_path(locator, source)
    if path is None:
        return [], [problem] if problem is not None else []
    content = path.read_bytes()
    bodies = data.get("bodies")
    names = [*(map(str, bodies) if isinstance(bodies, dict) else []), "ground"]
    try:
        table = _read_table(path, names, file_units.get("length"))
    except UnicodeDecodeError as error:
        reason = f"{path}: not UTF-8 text ({error.reason})"
        return [content], [locator.diagnostic(("points", FROM_KEY), reason)]
    found = table.problems
    where = locator.tree.position((*locator.prefix, "points", FROM_KEY))
    for name, point in table.points.items():
        if name in points:
            line, _ = locator.tree.position((*locator.prefix, "points", name))
            inline = f"{Path(locator.tree.file).name} line {line}"
            found.append(
                Diagnostic(
                    str(path),
                    table.lines[name],
                    1,
                    "name",
                    f"point '{name}' is also given inline ({inline})",
                    hint="give each point once: in the table or inline",
                )
            )
            continue
        points[name] = point
        locator.tree.keys.setdefault((*locator.prefix, "points", name), where)
    return [content], found
