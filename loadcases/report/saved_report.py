"""`loads envelope DIR...`: the envelope, curves and workbook data of saved results.

Runs are the results CSVs below the folders (sorted by path); runs whose summary says they
failed are listed but left out of the envelope, as in a set run. Factors and allowables
come from a set file when one is given.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.report.curves import EnvelopeCurve
from loadcases.report.envelope import EnvelopeRow
from loadcases.report.number_format import SIGNIFICANT_DIGITS
from loadcases.report.sizing import Sizing, size_runs
from loadcases.results.files import package_version
from loadcases.results.saved import (
    RunRecord,
    SavedRun,
    find_result_files,
    load_saved_run,
    record_from_summary,
)

if TYPE_CHECKING:
    from loadcases.report.workbook import WorkbookData

__all__ = ["SavedReport", "saved_report"]


@dataclass
class SavedReport:
    """Every saved run (`records`), the ok runs, their envelope and curves (SI); `units`:
    the set's `report.units` ({kind: unit}) the workbook shows them in."""

    records: list[RunRecord]
    runs: list[SavedRun]
    rows: list[EnvelopeRow]
    curves: list[EnvelopeCurve]
    sources: list[Path]
    units: dict[str, str] = field(default_factory=dict)
    sizing: Sizing | None = None
    histories: str = "envelope"
    digits: int = SIGNIFICANT_DIGITS
    warnings: list[Diagnostic] = field(default_factory=list)  # of the files read

    def workbook_data(self, title: str, set_path: Path | None = None) -> WorkbookData:
        """The workbook of these results (Provenance lists each CSV with its hash)."""
        from loadcases.report.units import ReportUnits
        from loadcases.report.workbook import WorkbookData, file_sha256

        inputs = [(str(p), file_sha256(p)) for p in ([set_path] if set_path else [])]
        inputs += [(str(p), file_sha256(p)) for p in self.sources]
        return ReportUnits.of(self.units).workbook_data(
            WorkbookData(
                title,
                self.records,
                self.runs,
                self.rows,
                self.curves,
                inputs,
                [("made by", "loads envelope")],
                package_version(),
                str(set_path or ""),
                matrix=self.sizing.matrix if self.sizing is not None else None,
                ultimate=self.sizing.ultimate if self.sizing is not None else 1.0,
                noise=self.sizing.noise if self.sizing is not None else frozenset(),
                histories=self.histories,
                digits=self.digits,
            )
        )


def _record(csv_path: Path, run: SavedRun) -> RunRecord:
    """The record of a run read back (its summary checked by `load_saved_run`)."""
    return record_from_summary({"status": "ok", **run.summary, "case": run.name}, csv_path)


def saved_report(directories: Iterable[Path], *, set_path: Path | None = None) -> SavedReport:
    """Read every run below `directories`; factors/allowables from `set_path` if given.

    InputError (every problem of every file, each naming the file, line and column) if a
    saved file is not what `loads run` writes (`loadcases.results.reading`)."""
    files = find_result_files(directories)
    records, runs, problems = [], [], []
    for directory, csv_path in files:
        try:
            run = load_saved_run(csv_path, directory)
        except InputError as error:
            problems += error.diagnostics
            continue
        records.append(_record(csv_path, run))
        if records[-1].ok:
            runs.append(run)
    if problems:
        raise InputError(problems)
    model, units, histories, digits = None, {}, "envelope", SIGNIFICANT_DIGITS
    if set_path is not None:
        from loadcases.inputs.loader import load_set

        model = load_set(set_path).model
        if model.report is not None:
            units, histories = model.report.units.given(), model.report.histories
            digits = model.report.digits
    sizing = size_runs(runs, model)
    sources = [p for _, p in files]
    warnings = [note for run in runs for note in run.notes]
    return SavedReport(
        records,
        runs,
        sizing.rows,
        sizing.curves,
        sources,
        units,
        sizing,
        histories,
        digits=digits,
        warnings=warnings,
    )
