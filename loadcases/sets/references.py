"""A set's reference curves (`curves:`) after its runs: the reference CSV files read again
(checked when the set was loaded), the overlays of the runs, `reference-curves.csv` (SI)
and the PNG plots (report units) in the set's folder."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.reference_tables import read_reference_table, reference_path
from loadcases.report.reference_curves import (
    REFERENCE_FILE,
    Overlay,
    in_report_units,
    overlays,
    write_reference_csv,
)
from loadcases.results.saved import SavedRun

__all__ = ["reference_overlays", "write_reference_files"]


def reference_overlays(compiled: Any, runs: Sequence[SavedRun]) -> list[Overlay]:
    """The overlays (SI) of a compiled set's `curves:` over its ok `runs`; InputError if a
    reference file changed into an unreadable one since the set was loaded."""
    model = compiled.set_file.model
    tables = {}
    for name, curve in model.curves.items():
        path, problem = reference_path(compiled.set_file.path, curve.file)
        if path is None:
            key = f"curves.{name}.file"
            raise InputError([Diagnostic(str(compiled.set_file.path), 0, 0, key, str(problem))])
        table = read_reference_table(path)
        if table.problems:
            raise InputError(table.problems)
        tables[name] = table
    abscissae = {cf.case.case: str(cf.case.abscissa) for cf in compiled.cases if cf.case.abscissa}
    return overlays(model.curves, tables, runs, abscissae)


def write_reference_files(
    found: Sequence[Overlay], units: Any, directory: Path
) -> tuple[list[Overlay], list[Path]]:
    """`reference-curves.csv` (SI) and the plots (report units) of `found`; the overlays in
    report units (for the workbook) and the paths written."""
    from loadcases.report.reference_plots import write_reference_plots  # matplotlib: here

    files = [write_reference_csv([o.difference for o in found], directory / REFERENCE_FILE)]
    shown = [in_report_units(o, units) for o in found]
    return shown, files + write_reference_plots(shown, directory)
