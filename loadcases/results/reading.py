"""Saved result files read back as input (`loads envelope`, `loads compare`, `loads plot`, a
set's reused runs): checked before any number is used.

A results CSV: a header of unique, visible column names starting with `time`, then rows
of as many cells, every cell a number (`nan`, `inf` written for values that are not
numbers). Its summary: a JSON object whose fields have their types (SPEC section 3), a
status of `ok`, `failed` or `interrupted`, a run name (hidden characters in it are shown
as escapes wherever it goes); and, where it gives them,
as many rows as the CSV and a unit for every column of it. A run whose summary says `ok`
has only finite numbers unless its CSV is the very file `loads` wrote (its summary's
`csv_sha256`); a CSV changed since is a warning. Every problem is a `SavedFileError` (an
InputError, and a ValueError for the callers of `read_results` before) naming the file,
the line and column, and the key or column (exit 2), never a traceback.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.foundation.clip import describe_character, hidden_character
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.foundation.engine_hash import file_sha256

__all__ = [
    "MAX_LINE_CHARS",
    "MAX_SUMMARY_BYTES",
    "RUN_STATUSES",
    "TIME_COLUMN",
    "RunTable",
    "SavedFileError",
    "check_against_csv",
    "input_text",
    "read_checked_summary",
    "read_run_csv",
]

TIME_COLUMN = "time"
RUN_STATUSES = ("ok", "failed", "interrupted")
MAX_LINE_CHARS = 4_000_000  # one CSV line: 16 384 columns (Excel's) of 25 characters, x10
MAX_SUMMARY_BYTES = 64_000_000  # one summary: its extremes of 100 000 columns, x10


class SavedFileError(InputError, ValueError):
    """A saved file that is not what `loads` writes (its diagnostics name the place)."""


def _problem(path: Path, line: int, column: int, key: str, message: str) -> SavedFileError:
    return SavedFileError([Diagnostic(str(path), line, column, key, message)])


def input_text(path: Path) -> str:
    """The file as text (UTF-8, universal newlines), or the InputError saying why not."""
    try:
        data = path.read_bytes()
    except OSError as error:
        raise _problem(path, 0, 0, "", f"cannot be read: {error.strerror or error}") from None
    try:
        return data.decode("utf-8").replace("\r\n", "\n").replace("\r", "\n")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        raise _problem(path, line, 0, "", "not UTF-8 text: not a saved result file") from None


def _header(path: Path, line: str) -> list[str]:
    """The column names of a results CSV's first line (checked)."""
    if len(line) > MAX_LINE_CHARS:
        raise _problem(path, 1, 1, "", f"header longer than {MAX_LINE_CHARS} characters")
    names = next(csv.reader([line]), [])
    if not names or names[0] != TIME_COLUMN:
        raise _problem(path, 1, 1, "", f"not a results file (first column must be '{TIME_COLUMN}')")
    seen: set[str] = set()
    for index, name in enumerate(names):
        hidden = hidden_character(name)
        if not name.strip() or hidden is not None or name in seen:
            why = (
                "empty column name"
                if not name.strip()
                else f"column name with {describe_character(hidden)}"
                if hidden is not None
                else f"column '{name}' given twice"
            )
            raise _problem(path, 1, index + 1, name, why)
        seen.add(name)
    return names


def _bad_row(path: Path, lines: list[str], names: list[str]) -> SavedFileError:
    """The first row of the CSV body (`lines`, line 2 on) that is not a row of numbers."""
    for number, line in enumerate(lines, start=2):
        if not line.strip():
            continue
        if len(line) > MAX_LINE_CHARS:
            return _problem(path, number, 1, "", f"line longer than {MAX_LINE_CHARS} characters")
        cells = line.split(",")
        if len(cells) != len(names):
            return _problem(
                path,
                number,
                1,
                "",
                f"{len(cells)} values for {len(names)} columns (a short, long or truncated row)",
            )
        for index, cell in enumerate(cells):
            try:
                float(cell)
            except ValueError:
                return _problem(path, number, index + 1, names[index], f"'{cell}' is not a number")
    return _problem(path, 0, 0, "", "not a table of numbers")


@dataclass(frozen=True)
class RunTable:
    """A results CSV read and checked: column names, values (rows, columns) and its body
    (text after the header), kept to name the line of a row when one is found wrong."""

    names: list[str]
    data: np.ndarray
    body: str = ""

    def line_of(self, row: int) -> int:
        """The line (1-based) of data row `row` (blank lines are skipped by the reader)."""
        if "\n\n" not in self.body and not self.body.startswith("\n"):
            return row + 2
        numbers = (n for n, line in enumerate(self.body.split("\n"), 2) if line.strip())
        return next(n for k, n in enumerate(numbers) if k == row)


def read_run_csv(path: Path) -> RunTable:
    """A results CSV read and checked. SavedFileError naming the file, line and column of
    the first problem."""
    path = Path(path)
    text = input_text(path)
    first, _, body = text.partition("\n")
    names = _header(path, first)
    if not body.strip():
        return RunTable(names, np.empty((0, len(names))))
    try:
        # numpy's C reader parses each number as float() does (correctly rounded, `nan`,
        # `inf`), blank lines skipped: 5x faster than a list of csv rows
        data = np.loadtxt(io.StringIO(body), delimiter=",", dtype=float, ndmin=2)
    except ValueError:
        raise _bad_row(path, body.split("\n"), names) from None
    if data.shape[1] != len(names):
        raise _bad_row(path, body.split("\n"), names)
    return RunTable(names, data, body)


def _line_of(text: str, key: str, after: int = 0) -> tuple[int, int]:
    """Line and column (1-based) of `"key"` in a JSON text (from offset `after`), else
    (1, 1): where a person editing the file finds the field."""
    at = text.find(json.dumps(key), after)
    if at < 0:
        return 1, 1
    return text.count("\n", 0, at) + 1, at - (text.rfind("\n", 0, at) + 1) + 1


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _is_count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _mapping_of(check: Callable[[Any], bool]) -> Callable[[Any], bool]:
    return lambda value: isinstance(value, dict) and all(check(v) for v in value.values())


def _number_or_null(value: Any) -> bool:
    return value is None or (_is_number(value) and math.isfinite(value))


def _accuracy_verdict(value: Any) -> bool:
    """The part of an `accuracy` block a workbook reads (loadcases.results.verdict)."""
    return (
        isinstance(value, dict)
        and _is_number(value.get("target"))
        and math.isfinite(value["target"])
        and (value.get("met") is None or isinstance(value["met"], bool))
        and isinstance(value.get("outcome", ""), str)
    )


# field: (what it must be, the check); fields not listed are not read
_FIELDS: dict[str, tuple[str, Callable[[Any], bool]]] = {
    "case": ("a text", lambda v: isinstance(v, str)),
    "status": (f"one of {', '.join(RUN_STATUSES)}", lambda v: v in RUN_STATUSES),
    "analysis": ("a text", lambda v: isinstance(v, str)),
    "level": ("limit or ultimate", lambda v: v in ("limit", "ultimate")),
    "message": ("a text", lambda v: isinstance(v, str)),
    "input_sha256": ("a text", lambda v: isinstance(v, str)),
    "csv_sha256": ("a text", lambda v: isinstance(v, str)),
    "case_file": ("a text", lambda v: isinstance(v, str)),
    "version": ("a text", lambda v: isinstance(v, str)),
    "rows": ("a whole number >= 0", _is_count),
    "stats": (
        "an object of numbers >= 0",
        _mapping_of(lambda v: _is_number(v) and math.isfinite(v) and v >= 0),
    ),
    "parameters": ("an object of finite numbers", _mapping_of(_number_or_null)),
    "units": ("an object of texts", _mapping_of(lambda v: isinstance(v, str))),
    "kinds": ("an object of texts", _mapping_of(lambda v: isinstance(v, str))),
    "extremes": (
        "an object of {max, time_of_max, min, time_of_min} numbers",
        _mapping_of(_mapping_of(_number_or_null)),
    ),
    "accuracy": (
        "an object with a finite number target, met true, false or null, a text outcome",
        _accuracy_verdict,
    ),
    "warnings": (
        "a list of texts",
        lambda v: isinstance(v, list) and all(isinstance(w, str) for w in v),
    ),
}
_REQUIRED = ("case", "status")


def _summary_problem(path: Path, text: str, summary: Any) -> SavedFileError | None:
    """The first field of `summary` that is missing or not of its type, or None."""
    if not isinstance(summary, dict):
        return _problem(path, 1, 1, "", "not a run summary (a JSON object expected)")
    for key in _REQUIRED:
        if key not in summary:
            return _problem(path, 1, 1, key, "missing (a run summary names its case and status)")
    for key, (expected, check) in _FIELDS.items():
        if key in summary and not check(summary[key]):
            line, column = _line_of(text, key)
            return _problem(path, line, column, key, f"must be {expected}")
    # a name with hidden characters is shown as escapes wherever it goes (workbook, CSV,
    # console: loadcases.foundation.clip); an empty one would name no run
    if not summary["case"].strip():
        line, column = _line_of(text, "case")
        return _problem(path, line, column, "case", "empty run name")
    return None


def read_checked_summary(path: Path) -> dict[str, Any] | None:
    """A run's summary read and checked (see the module), or None if there is none.

    InputError naming the file, the line and column and the field of the first problem."""
    path = Path(path)
    if not path.is_file():
        return None
    if path.stat().st_size > MAX_SUMMARY_BYTES:
        raise _problem(path, 1, 1, "", f"larger than {MAX_SUMMARY_BYTES} bytes: not a summary")
    text = input_text(path)
    try:
        summary = json.loads(text)
    except json.JSONDecodeError as error:
        raise _problem(path, error.lineno, error.colno, "", f"not JSON: {error.msg}") from None
    except RecursionError:
        raise _problem(path, 1, 1, "", "not a run summary (nested too deep)") from None
    problem = _summary_problem(path, text, summary)
    if problem is not None:
        raise problem
    return summary


def check_against_csv(
    summary_file: Path,
    summary: dict[str, Any],
    csv_file: Path,
    table: RunTable,
) -> list[Diagnostic]:
    """The summary and its CSV agree: row count, columns (those it has extremes of); a CSV
    not the one the summary was written with (`csv_sha256`) has only finite numbers in a
    run whose status is `ok` (a run's own NaN, such as a torque margin's where nothing
    resists, is kept only in the file `loads` wrote). InputError naming the place
    otherwise; returns the warning that such a CSV was changed since."""
    names, data = table.names, table.data
    _check_rows(summary_file, summary, csv_file, data.shape[0])
    _check_columns(summary_file, summary, csv_file, names)
    recorded = summary.get("csv_sha256")
    changed = recorded is not None and recorded != file_sha256(csv_file)
    if summary.get("status") == "ok" and (changed or recorded is None):
        _check_finite(csv_file, table)
    if not changed:
        return []
    return [
        Diagnostic(
            str(csv_file),
            0,
            0,
            "",
            f"changed since {summary_file.name} was written (its csv_sha256 differs): "
            "numbers not as the run computed them",
            severity="warning",
        )
    ]


def _check_columns(
    summary_file: Path, summary: dict[str, Any], csv_file: Path, names: list[str]
) -> None:
    """The CSV's columns are those the summary has extremes of (every column the run saved)."""
    extremes = summary.get("extremes")
    if extremes is None:
        return
    missing = [name for name in extremes if name not in names]
    if missing:
        raise _problem(
            csv_file,
            1,
            1,
            missing[0],
            f"no such column, though {summary_file.name} has its "
            "extremes (a column removed or renamed)",
        )
    extra = [name for name in names[1:] if name not in extremes]
    if extra:
        raise _problem(
            csv_file,
            1,
            names.index(extra[0]) + 1,
            extra[0],
            f"column not in {summary_file.name} (not the columns the run was saved with)",
        )


def _check_rows(summary_file: Path, summary: dict[str, Any], csv_file: Path, rows: int) -> None:
    said = summary.get("rows")
    if said is not None and said != rows:
        line, column = _line_of(input_text(summary_file), "rows")
        raise _problem(
            summary_file,
            line,
            column,
            "rows",
            f"says {said} rows, but {csv_file.name} has {rows} (truncated or edited)",
        )


def _check_finite(csv_file: Path, table: RunTable) -> None:
    """SavedFileError at the first value that is not finite, if any."""
    data = table.data
    if data.size and not np.isfinite(data).all():
        row, column = (int(i) for i in np.argwhere(~np.isfinite(data))[0])
        raise _problem(
            csv_file,
            table.line_of(row),
            column + 1,
            table.names[column],
            f"{float(data[row, column])!r} in a run whose summary says ok (numbers must be finite)",
        )
