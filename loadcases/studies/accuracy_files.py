"""The files of `loads accuracy`: the work-precision table (CSV), the errors per column
(CSV), the work-precision diagram (PNG, error vs CPU time, log-log, one line per integrator)
and a workbook with both tables. Errors are fractions of each request's peak; CPU in s."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.foundation.clip import plain_log_ticks, plain_text_plots, visible_fields
from loadcases.results.files import result_base
from loadcases.results.xlsx_text import text_cells
from loadcases.studies.accuracy import AccuracyStudy

__all__ = [
    "COLUMN_ERROR_COLUMNS",
    "SETTING_COLUMNS",
    "recommendation_text",
    "settings_rows",
    "write_accuracy_files",
]

SETTING_COLUMNS = (
    "integrator",
    "tolerance",
    "status",
    "cpu_seconds (s)",
    "steps",
    "rejected_steps",
    "newton_iterations",
    "error_max (of peak)",
    "error_max_column",
    "error_end (of peak)",
    "error_peak (of peak)",
    "meets_target",
    "reference",
)
COLUMN_ERROR_COLUMNS = (
    "integrator",
    "tolerance",
    "column",
    "error_max (of peak)",
    "error_end (of peak)",
    "error_peak (of peak)",
)


def settings_rows(study: AccuracyStudy) -> list[list[object]]:
    """One row per setting, in SETTING_COLUMNS order."""
    rows = []
    for r in study.results:
        column, worst = r.worst()
        rows.append(
            [
                r.setting.integrator,
                r.setting.tolerance,
                r.status,
                r.cpu_seconds,
                r.stats.get("steps"),
                r.stats.get("rejected_steps"),
                r.stats.get("newton_iterations"),
                _finite(worst),
                column,
                _finite(r.worst("at_end")[1]),
                _finite(r.worst("of_peak")[1]),
                r.meets(study.target),
                study.references[r.setting.integrator].describe(),
            ]
        )
    return rows


def _column_rows(study: AccuracyStudy) -> list[list[object]]:
    return [
        [
            r.setting.integrator,
            r.setting.tolerance,
            column,
            _finite(e.over_time),
            _finite(e.at_end),
            _finite(e.of_peak),
        ]
        for r in study.results
        for column, e in r.errors.items()
    ]


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _csv(header: tuple[str, ...], rows: list[list[object]]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(visible_fields("" if v is None else v for v in row) for row in rows)
    return buffer.getvalue()


def recommendation_text(study: AccuracyStudy) -> str:
    """One sentence: the cheapest setting meeting the target, or that none does."""
    best = study.recommended
    if best is None:
        return (
            f"no setting meets {study.target:g} of peak: tighten the tolerances studied "
            "(--tolerances) or look at the worst columns"
        )
    column, worst = best.worst()
    return (
        f"cheapest setting meeting {study.target:g} of peak: {best.setting.describe()} "
        f"({best.cpu_seconds:.3g} s CPU, {best.stats.get('steps', 0):.0f} steps; worst "
        f"error {worst:.2g} of peak in {column})"
    )


@plain_text_plots()  # `$` in a name is a dollar sign
def _diagram(study: AccuracyStudy, path: Path) -> None:
    figure = Figure(figsize=(8.0, 6.0), dpi=100, layout="constrained")  # labels on the canvas
    FigureCanvasAgg(figure)
    ax = figure.add_subplot()
    for method in dict.fromkeys(r.setting.integrator for r in study.results):
        mine = [
            r
            for r in study.results
            if r.setting.integrator == method
            and r.status == "ok"
            and r.errors
            and r.worst()[1] > 0.0
        ]
        if not mine:
            continue
        ax.loglog([r.cpu_seconds for r in mine], [r.worst()[1] for r in mine], "o-", label=method)
        for r in mine:
            ax.annotate(
                f"{r.setting.tolerance:g}",
                (r.cpu_seconds, r.worst()[1]),
                textcoords="offset points",
                xytext=(4, 4),
                fontsize=8,
            )
    ax.axhline(study.target, color="red", linestyle="--", label=f"target {study.target:g}")
    if study.reference_agreement:
        ax.axhline(
            study.reference_agreement, color="grey", linestyle=":", label="reference agreement"
        )
    plain_log_ticks(ax)
    ax.set_xlabel("CPU time (s)")
    ax.set_ylabel("largest error over the run (fraction of the request's peak)")
    ax.set_title(f"{study.case}: work-precision (labels: tolerance)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    with atomic_path(path) as tmp:
        figure.savefig(tmp, format="png")


@text_cells()  # names from the case: text, hidden characters escaped
def _workbook(study: AccuracyStudy, path: Path) -> None:
    from openpyxl import Workbook
    from openpyxl.cell import WriteOnlyCell

    workbook = Workbook(write_only=True)
    for title, header, rows in (
        ("Work-precision", SETTING_COLUMNS, settings_rows(study)),
        ("Columns", COLUMN_ERROR_COLUMNS, _column_rows(study)),
        ("Notes", ("note",), [[n] for n in _notes(study)]),
    ):
        sheet = workbook.create_sheet(title)
        sheet.freeze_panes = "A2"
        for values in [list(header)] + rows:
            cells = []
            for value in values:
                cell = WriteOnlyCell(sheet, value=value)
                if isinstance(value, str):
                    cell.data_type = "s"  # names from the case are text, never formulas
                cells.append(cell)
            sheet.append(cells)
    with atomic_path(path) as tmp:
        workbook.save(tmp)


def _notes(study: AccuracyStudy) -> list[str]:
    return [recommendation_text(study)] + study.notes


def write_accuracy_files(study: AccuracyStudy, output_dir: Path) -> list[Path]:
    """NAME.accuracy.csv, NAME.accuracy-columns.csv, NAME.accuracy.png, NAME.accuracy.xlsx
    in `output_dir` (NAME the case name; each written atomically); returns the paths."""
    base = result_base(output_dir, study.case)
    paths = [
        base.with_name(base.name + suffix)
        for suffix in (".accuracy.csv", ".accuracy-columns.csv", ".accuracy.png", ".accuracy.xlsx")
    ]
    atomic_write_text(paths[0], _csv(SETTING_COLUMNS, settings_rows(study)))
    atomic_write_text(paths[1], _csv(COLUMN_ERROR_COLUMNS, _column_rows(study)))
    _diagram(study, paths[2])
    _workbook(study, paths[3])
    return paths
