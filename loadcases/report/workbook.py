"""The sizing workbook of a set (openpyxl), built on a template (`templates/envelope.xlsx`).

Sheets, in order: the template's `Cover` (filled in), `Cases` (every run, linked to its
sheet and its CSV file), `Envelope` (the table of `envelope.csv`, same header and values,
without the abscissa row: the abscissa is the x axis, not a load), `Margins` (every margin,
lowest first: `loadcases.report.margin_table`), `Loads matrix` (peaks per component and run:
`loadcases.report.loads_matrix`; beyond 4,095 runs on `Loads matrix 2`, ...), `Torque
margin` (when runs have one: loadcases/workbook_tm.py), `Comparison` (the set's
`comparisons:`: loadcases.report.comparison), `Charts` (native line charts: per family
the envelope curves of its main load columns, `loadcases.report.curves.main_columns`, and
those columns against time for each run), one `Curves FAMILY` sheet per family (the
envelope curves' numbers, without the columns marked `~0`), the time histories,
`Provenance` (with every allowable given).

Time histories (`report.histories`): `envelope` (default) keeps the rows the charts need
(`loadcases.report.decimate`: at most `CHART_ROWS` evenly spaced rows per run and curve, plus
the rows of every column's max and min, so peaks read from the sheets are exact; columns
marked `~0` left out; of a set with more than `MAX_HISTORY_RUNS` ok runs, only the runs that
govern an envelope row, so that a campaign's workbook grows with its envelope); `all`
every output row (and the full curves); `none` no history sheets (and no per-run charts).
Every run's full rows stay in its `NAME.csv`, linked from the Cases sheet. One sheet per run
when the set has at most `MAX_RUN_SHEETS` runs, else one sheet per family with the runs
stacked (first column `run`). Numbers show `report.digits` (default
`number_format.SIGNIFICANT_DIGITS`) significant digits of each row's or column's peak.
Headers carry their units (`pivot_force.fx [N]`): SI, or the set's `report.units`
(`loadcases.report.units` converts the data before they get here); SI values are the
CSV's exactly (NaN becomes an empty cell: Excel has no NaN). The workbook is written
atomically.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import hashlib
import os
import platform
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.foundation.atomic import atomic_path
from loadcases.foundation.clip import hidden_character, visible
from loadcases.report.comparison import comparison_rows, comparison_sheet
from loadcases.report.curves import EnvelopeCurve
from loadcases.report.decimate import CHART_ROWS, decimate_curve, decimate_run
from loadcases.report.envelope import EnvelopeRow
from loadcases.report.loads_matrix import LoadsMatrix
from loadcases.report.margin_table import margin_lines
from loadcases.report.number_format import SIGNIFICANT_DIGITS
from loadcases.report.wear_map import WEAR_SHEET, polar_requests, wear_map_sheet
from loadcases.report.workbook_template import (
    COVER_FIELDS,
    COVER_SHEET,
    build_template,
    ensure_styles,
)
from loadcases.report.workbook_tm import has_torque_margin, torque_margin_sheet
from loadcases.results.saved import RunRecord, SavedRun, family_of
from loadcases.results.xlsx_floats import exact_floats
from loadcases.results.xlsx_text import text_cells

__all__ = [
    "DEFAULT_TEMPLATE",
    "MAX_HISTORY_RUNS",
    "MAX_RUN_SHEETS",
    "WorkbookData",
    "file_sha256",
    "sheet_title",
    "write_workbook",
]

MAX_RUN_SHEETS = 40  # more runs: one time-history sheet per family
# More ok runs than this (a campaign): `histories: envelope` keeps the runs that govern an
# envelope row only, so the workbook grows with the envelope, not with the number of runs.
MAX_HISTORY_RUNS = 100
SHEET_TITLE_LENGTH = 31  # Excel's limit
DEFAULT_TEMPLATE = Path(__file__).resolve().parents[2] / "templates" / "envelope.xlsx"
_FORBIDDEN = re.compile(r"[\[\]:*?/\\]")


@dataclass
class WorkbookData:
    """Everything a workbook shows; `runs` are the runs with time histories (status ok)."""

    title: str
    records: list[RunRecord]
    runs: list[SavedRun]
    rows: list[EnvelopeRow]
    curves: list[EnvelopeCurve]
    inputs: list[tuple[str, str]] = field(default_factory=list)  # (file, sha256)
    settings: list[tuple[str, str]] = field(default_factory=list)  # (key, value)
    version: str = ""
    source: str = ""
    matrix: LoadsMatrix | None = None
    ultimate: float = 1.0  # the ultimate factor (margins: limit factor = factor / ultimate)
    noise: frozenset[str] = frozenset()  # columns marked ~0
    histories: str = "envelope"  # report.histories: all | envelope | none
    comparisons: dict[str, Any] = field(default_factory=dict)  # the set's `comparisons:`
    digits: int = SIGNIFICANT_DIGITS  # report.digits: significant digits shown
    references: list[Any] = field(default_factory=list)  # reference_curves.Overlay, report units
    mass: Any | None = None  # loadcases.sets.mass.MassTable of `mass_properties:` (SI)

    @classmethod
    def from_set(cls, result: Any, runs: list[SavedRun], options: dict[str, str]) -> WorkbookData:
        """From a `loadcases.sets.campaign.SetResult` and its loaded ok runs."""
        compiled = result.compiled
        files = [compiled.set_file.path]
        for cf in compiled.cases:
            files += [cf.path] + ([cf.mechanism_path] if cf.mechanism_path else [])
        settings = [
            (f"analysis of {cf.case.case}", _analysis_text(cf.case.analysis))
            for cf in compiled.cases
        ]
        model = compiled.set_file.model
        settings += [(f"factor {k}", repr(v)) for k, v in model.factors.items()]
        settings += [(f"case factor {k}", repr(v)) for k, v in model.case_factors.items()]
        histories = model.report.histories if model.report is not None else "envelope"
        digits = model.report.digits if model.report is not None else SIGNIFICANT_DIGITS
        settings += [("histories", histories), *options.items()]
        sizing = result.sizing
        return cls(
            compiled.name,
            result.records,
            runs,
            result.envelope,
            result.curves,
            [(str(p), file_sha256(p)) for p in dict.fromkeys(files)],
            settings,
            compiled.version,
            str(compiled.set_file.path),
            matrix=sizing.matrix if sizing is not None else None,
            ultimate=sizing.ultimate if sizing is not None else 1.0,
            noise=sizing.noise if sizing is not None else frozenset(),
            histories=histories,
            comparisons=dict(model.comparisons),
            digits=digits,
        )


def _analysis_text(analysis: Any) -> str:
    values = analysis.model_dump(exclude_none=True) if hasattr(analysis, "model_dump") else {}
    return ", ".join(f"{k}={v}" for k, v in values.items())


def file_sha256(path: str | Path) -> str:
    """SHA-256 of a file's bytes (empty if it cannot be read)."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return ""


def sheet_title(text: str, used: set[str]) -> str:
    """A valid, unused Excel sheet title from `text` (`[]` -> `()`, `:*?/\\` -> `_`, a
    hidden character such as BEL or U+202E an escape, its backslash `_`)."""
    text = visible(text)
    clean = _FORBIDDEN.sub(lambda m: {"[": "(", "]": ")"}.get(m.group(), "_"), text).strip("'")
    clean = clean or "sheet"
    title, k = clean[:SHEET_TITLE_LENGTH], 1
    while title.lower() in {u.lower() for u in used}:
        k += 1
        suffix = f" ({k})"
        title = clean[: SHEET_TITLE_LENGTH - len(suffix)] + suffix
    used.add(title)
    return title


def _load_template(template: Path | None) -> Any:
    """The template workbook: the given file, the repository's, or a built one."""
    from openpyxl import load_workbook

    path = template if template is not None else DEFAULT_TEMPLATE
    if template is not None or path.is_file():
        workbook = load_workbook(path)
    else:
        workbook = build_template()
    ensure_styles(workbook)
    return workbook


def _fill_cover(workbook: Any, data: WorkbookData) -> None:
    if COVER_SHEET not in workbook.sheetnames:
        return
    values = dict(
        zip(
            COVER_FIELDS,
            (
                data.title,
                data.source,
                dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M:%S"),
                data.version,
                len(data.records),
                sum(not r.ok for r in data.records),
                sum(r.reused for r in data.records),
            ),
        )
    )
    sheet = workbook[COVER_SHEET]
    for row in range(1, sheet.max_row + 1):
        label = sheet.cell(row=row, column=1).value
        if label in values:
            sheet.cell(row=row, column=2, value=values[label])


@text_cells()  # input text is never a formula
def write_workbook(
    data: WorkbookData,
    path: Path,
    *,
    template: Path | None = None,
    progress: Callable[[str], None] | None = None,
) -> Path:
    """Write the workbook to `path` atomically; return `path`. `progress(text)` is told
    which part is being written."""
    from loadcases.report import workbook_charts as charts
    from loadcases.report import workbook_sheets as sheets
    from loadcases.report import workbook_tables as tables
    from loadcases.report.workbook_history import history_sheet

    say = progress or (lambda text: None)
    say("workbook: tables")
    workbook = _load_template(template)
    _fill_cover(workbook, data)
    used = set(workbook.sheetnames)
    new = lambda title: workbook.create_sheet(sheet_title(title, used))  # noqa: E731
    runs = _history_runs(data)
    per_run = len(runs) <= MAX_RUN_SHEETS
    groups = [(run.name, [run]) for run in runs] if per_run else list(_families(runs).items())
    titles = {
        name: sheet_title(_short(name, k), used) for k, (name, _) in enumerate(groups, start=1)
    }
    run_sheets = {run.name: titles[run.name if per_run else run.family] for run in runs}
    sheets.cases_sheet(new("Cases"), data.records, run_sheets, _csv_links(data, Path(path)))
    shown = [row for row in data.rows if row.column != ABSCISSA_COLUMN]
    digits = data.digits
    sheets.envelope_sheet(new("Envelope"), shown, run_sheets, digits)
    tables.margins_sheet(new("Margins"), margin_lines(shown, data.ultimate), digits)
    if data.matrix is not None:
        tables.matrix_sheets(new, data.matrix, digits)
    if has_torque_margin(data.runs):
        torque_margin_sheet(new("Torque margin"), data.runs)
    if data.comparisons:
        comparison_sheet(new("Comparison"), comparison_rows(data.comparisons, data.runs))
    if data.references:
        from loadcases.report.reference_sheet import REFERENCE_SHEET, reference_sheet

        reference_sheet(new(REFERENCE_SHEET), data.references, digits)
    if data.mass is not None:
        from loadcases.report.mass_properties import MASS_SHEET, mass_sheet

        mass = data.mass
        mass_sheet(new(MASS_SHEET), mass.rows, mass.axis_name, mass.where, digits)
    if any(polar_requests(run) for run in data.runs):
        wear_map_sheet(new(WEAR_SHEET), data.runs)
    curves = _shown_curves(data)
    chart_sheet = new("Charts") if curves else None
    curve_sheets = [new(f"Curves {c.family}") for c in curves]
    wheres = [charts.curves_sheet(s, c, digits) for s, c in zip(curve_sheets, curves)]
    blocks = {}
    for k, (name, group) in enumerate(groups, start=1):
        say(f"workbook: time histories {k}/{len(groups)}")
        sheet = workbook.create_sheet(titles[name])
        note = _history_note(data)
        blocks.update(history_sheet(sheet, group, stacked=not per_run, note=note, digits=digits))
    if chart_sheet is not None:
        charts.charts_sheet(chart_sheet, curves, curve_sheets, wheres, blocks)
    sheets.provenance_sheet(new("Provenance"), data, platform.python_version())
    say("workbook: saving")
    with atomic_path(Path(path)) as tmp, exact_floats():
        workbook.save(tmp)
    return Path(path)


_NOTE = {
    "all": None,
    "envelope": f"rows thinned for the charts (at most {CHART_ROWS} evenly spaced, plus every "
    "column's max and min row), columns marked ~0 left out: the run's CSV (linked from "
    "Cases) holds every row and column",
    "none": None,
}


def _history_note(data: WorkbookData) -> str | None:
    """The note above the time histories: what was left out (None: nothing)."""
    note = _NOTE[data.histories]
    if note is None or len(data.runs) <= MAX_HISTORY_RUNS:
        return note
    return (
        f"only the runs that govern an envelope row (the set has {len(data.runs)} ok runs, "
        f"more than {MAX_HISTORY_RUNS}); {note}"
    )


def _governing(data: WorkbookData) -> list[SavedRun]:
    """The ok runs, or only those that govern an envelope row when there are more than
    MAX_HISTORY_RUNS of them (run order kept)."""
    if len(data.runs) <= MAX_HISTORY_RUNS:
        return data.runs
    names = {row.max_run for row in data.rows} | {row.min_run for row in data.rows}
    return [run for run in data.runs if run.name in names]


def _history_runs(data: WorkbookData) -> list[SavedRun]:
    """The runs whose time histories the workbook holds (`report.histories`)."""
    if data.histories == "none":
        return []
    if data.histories == "all":
        return data.runs
    return [decimate_run(run, skip=data.noise) for run in _governing(data)]


def _shown_curves(data: WorkbookData) -> list[EnvelopeCurve]:
    """The envelope curves without the `~0` columns, thinned unless `histories: all`."""
    curves = []
    for curve in data.curves:
        kept = [c for c in curve.upper if c not in data.noise]
        curve = dataclasses.replace(
            curve,
            upper={c: curve.upper[c] for c in kept},
            lower={c: curve.lower[c] for c in kept},
        )
        curves.append(curve if data.histories == "all" else decimate_curve(curve))
    return curves


def _csv_links(data: WorkbookData, path: Path) -> dict[str, str]:
    """{run: its CSV file relative to the workbook's folder} of the runs with a CSV (but a
    file whose name holds a hidden character, which a link cannot hold: a saved run named
    by hand; the csv column names it, escaped)."""
    folder = path.resolve().parent
    links = {
        r.name: Path(os.path.relpath(Path(r.csv_path).resolve(), folder)).as_posix()
        for r in data.records
        if r.csv_path and Path(r.csv_path).is_file()
    }
    return {run: link for run, link in links.items() if hidden_character(link) is None}


def _short(run: str, number: int) -> str:
    """`press-stroke[crank_speed=180deg_per_s,press_force=500N]` ->
    `press-stroke(180deg_per_s,500N)`, the family cut to fit Excel's 31 characters; `run N`
    if the values alone do not fit."""
    family = family_of(run)
    if family == run:
        return run
    values = ",".join(part.split("=", 1)[-1] for part in run[len(family) + 1 : -1].split(","))
    room = SHEET_TITLE_LENGTH - len(values) - 2
    if room < 6:
        return f"run {number}"
    return f"{family[:room]}({values})"


def _families(runs: list[SavedRun]) -> dict[str, list[SavedRun]]:
    out: dict[str, list[SavedRun]] = {}
    for run in runs:
        out.setdefault(run.family, []).append(run)
    return out
