"""Saved results of runs (SPEC section 3) read back: `NAME.csv` with its `NAME.summary.json`.

A run's family is the case it comes from: its name without the `[p=v,...]` of a sweep.
Used by envelopes and workbooks, whether the runs were just solved or saved long ago.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.results.files import SUMMARY_SUFFIX, TIME_COLUMN, checked_arrays
from loadcases.results.outcome import RunOutcome
from loadcases.results.reading import check_against_csv, read_checked_summary, read_run_csv
from loadcases.results.verdict import AccuracyVerdict

__all__ = [
    "RunRecord",
    "SavedRun",
    "family_of",
    "find_result_files",
    "load_saved_run",
    "read_summary",
    "record_from_summary",
    "saved_run_of",
    "summary_path",
]

_SWEEP_SUFFIX = re.compile(r"\[[^\[\]]*\]$")


def family_of(run_name: str) -> str:
    """`door[clearance=0.0001]` -> `door` (the case name of a run)."""
    return _SWEEP_SUFFIX.sub("", run_name)


@dataclass
class SavedRun:
    """The time histories of one run: `time` (n,) s and `channels` {column: (n,)} in SI."""

    name: str
    time: np.ndarray
    channels: dict[str, np.ndarray]
    units: dict[str, str] = field(default_factory=dict)
    family: str = ""
    status: str = "ok"
    kinds: dict[str, str] = field(default_factory=dict)  # {request: kind}, summary `kinds`
    level: str = "limit"  # the level of the case's applied loads (limit or ultimate)
    summary: dict[str, Any] = field(default_factory=dict, repr=False)  # as read (checked)
    notes: list[Diagnostic] = field(default_factory=list, repr=False)  # warnings of reading

    def __post_init__(self) -> None:
        self.family = self.family or family_of(self.name)

    def as_run(self) -> tuple[str, np.ndarray, dict[str, np.ndarray]]:
        """`(name, time, channels)` as plots take it (` (failed)` appended if so)."""
        label = self.name if self.status == "ok" else f"{self.name} ({self.status})"
        return label, self.time, self.channels


@dataclass(frozen=True)
class RunRecord:
    """What a set report says of one run (small and picklable): provenance and status."""

    name: str
    family: str
    case_file: str
    parameters: dict[str, float]
    analysis: str
    status: str
    message: str
    steps: int
    cpu_seconds: float
    input_sha256: str
    csv_path: Path
    reused: bool = False
    input_error: bool = False  # its parameter values make the input invalid (exit 2)
    level: str = "limit"  # the level of its case's applied loads (limit or ultimate)
    # the solver's warnings, the input's as data (a reused run: its summary's, all as text)
    warnings: tuple[str, ...] = ()
    input_warnings: tuple[Diagnostic, ...] = ()
    accuracy: AccuracyVerdict | None = None  # a dynamic run's, from its summary's `accuracy`

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def summary_path(csv_path: Path) -> Path:
    """`NAME.summary.json` next to `NAME.csv`."""
    return csv_path.with_name(csv_path.name[: -len(".csv")] + SUMMARY_SUFFIX)


def read_summary(path: Path) -> dict[str, Any] | None:
    """A summary as a dict, or None if missing or unreadable (then it is not reusable)."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def record_from_summary(
    summary: dict[str, Any], csv_path: Path, *, reused: bool = False
) -> RunRecord:
    """The record of a run from its saved summary."""
    stats = summary.get("stats") or {}
    name = str(summary.get("case") or csv_path.stem)
    return RunRecord(
        name=name,
        family=family_of(name),
        case_file=str(summary.get("case_file", "")),
        parameters={
            k: float(v) for k, v in (summary.get("parameters") or {}).items() if v is not None
        },
        analysis=str(summary.get("analysis", "")),
        status=str(summary.get("status", "failed")),
        message=str(summary.get("message", "")),
        steps=int(stats.get("steps") or 0),
        cpu_seconds=float(stats.get("cpu_seconds") or 0.0),
        input_sha256=str(summary.get("input_sha256", "")),
        csv_path=csv_path,
        reused=reused,
        level="ultimate" if summary.get("level") == "ultimate" else "limit",
        warnings=tuple(str(w) for w in summary.get("warnings") or ()),
        accuracy=AccuracyVerdict.of(summary.get("accuracy")),
    )


def load_saved_run(csv_path: Path, directory: Path | None = None) -> SavedRun:
    """Read one run back; named by its summary's `case`, else its path below `directory`.

    The CSV and its summary are checked as input (`loadcases.results.reading`): InputError
    naming the file, line and column of the first problem."""
    csv_path = Path(csv_path)
    summary_file = summary_path(csv_path)
    summary = read_checked_summary(summary_file) or {}
    table = read_run_csv(csv_path)
    notes = check_against_csv(summary_file, summary, csv_path, table) if summary else []
    data = table.data
    time = data[:, 0].copy()
    channels = {name: data[:, k].copy() for k, name in enumerate(table.names) if k}
    name = summary.get("case")
    if not name:
        base = csv_path.relative_to(directory) if directory is not None else Path(csv_path.name)
        name = base.as_posix()[: -len(".csv")]
    units = dict(summary.get("units") or {})
    kinds = dict(summary.get("kinds") or {})  # checked: an object of texts
    level = "ultimate" if summary.get("level") == "ultimate" else "limit"
    status = summary.get("status", "ok")
    run = SavedRun(name, time, channels, units, status=status, kinds=kinds, level=level)
    run.summary, run.notes = summary, notes
    return run


def saved_run_of(outcome: RunOutcome) -> SavedRun:
    """The run as `load_saved_run` reads it back once `write_results` has written it (a
    loadcases.run.RunOutcome; the CSV's numbers round-trip exactly): a set's report takes
    the runs it has just solved from memory, not from disk."""
    time, channels = checked_arrays(outcome.solution)
    units = {TIME_COLUMN: "s", **outcome.column_units}
    return SavedRun(
        outcome.name,
        time,
        channels,
        units,
        status=outcome.solution.status,
        kinds=dict(outcome.request_kinds),
        level=outcome.level,
    )


def find_result_files(directories: Iterable[Path]) -> list[tuple[Path, Path]]:
    """`(directory, csv_path)` of every results CSV below the directories (recursive, sorted).

    A results CSV is one whose first header cell is `time`; others (such as an
    `envelope.csv`) are not results and are left out.
    """
    found = []
    for directory in directories:
        for path in sorted(Path(directory).rglob("*.csv")):
            if path.is_file() and _first_header_cell(path) == TIME_COLUMN:
                found.append((Path(directory), path))
    return found


def _first_header_cell(path: Path) -> str:
    """The first cell of a CSV's first line, read no further than needed: a first line of
    megabytes is left to `read_run_csv` to report, not parsed here."""
    with open(path, encoding="utf-8", errors="replace") as stream:
        first = stream.read(len(TIME_COLUMN) + 1)
    return first.split(",", 1)[0].split("\n", 1)[0].strip()
