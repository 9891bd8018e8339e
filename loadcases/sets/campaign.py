"""Run a load-case set: compile, solve every run (reusing unchanged ones), write its reports.

`run_set` writes into `DIR/SET/` (SPEC section 3): each run's `NAME.csv` and
`NAME.summary.json` (`/` in NAME makes sub-folders), `envelope.csv`, `margins.csv` (every
margin, lowest first), `loads-matrix.csv` (peaks per component and run), the workbook
(`report.output`, default `envelope.xlsx`) and, when `loadcases.report.plots` provides it, the
envelope plots. A run whose summary in `DIR/SET/` has status `ok`, the run's input hash
(case and mechanism bytes, parameters, engine version; see `loadcases.sets.specs`), the engine's
source hash (`loadcases.foundation.engine_hash`) and the SHA-256 of the CSV next to it is reused,
not solved again, unless `force`. Failed runs are solved again (the failure may have been
fixed elsewhere, e.g. in the engine). One failing run never stops the set: it is recorded
with its message and left out of the envelope. An interrupt (SIGINT, SIGTERM:
`loadcases.foundation.interrupts`) starts no further run; the runs finished stay valid, those under
way are written with status `interrupted` and their rows so far, and no envelope or
workbook is written (`SetResult.interrupted`). One writer per folder: `DIR/SET/.loads.lock`
(`loadcases.foundation.folder_lock`) is held from before the first file is written until the
last one is, and removed on every way out; a second run into the same folder is refused.
"""

from __future__ import annotations

import dataclasses
import importlib
import os
import time as clock
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from contextlib import ExitStack, closing, contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from loadcases.flexible.cache import caching_under
from loadcases.foundation import engine_hash, folder_lock, interrupts
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.overrides import Override
from loadcases.report.curves import EnvelopeCurve, plot_curves
from loadcases.report.envelope import EnvelopeRow, write_envelope_csv
from loadcases.report.loads_matrix import write_matrix_csv
from loadcases.report.margin_table import margin_lines, write_margin_csv
from loadcases.report.sizing import Sizing, size_runs
from loadcases.results.files import ResultsNotWritten, result_base, write_results
from loadcases.results.outcome import RunOutcome
from loadcases.results.reading import read_checked_summary
from loadcases.results.saved import (
    RunRecord,
    SavedRun,
    load_saved_run,
    record_from_summary,
    saved_run_of,
    summary_path,
)
from loadcases.results.verdict import AccuracyVerdict
from loadcases.sets.collector import collector_paused
from loadcases.sets.drawing import PLOT_MODULE, Drawing
from loadcases.sets.executors import Executor, PoolExecutor, SerialExecutor
from loadcases.sets.specs import CompiledSet, RunSpec, load_and_compile_set
from loadcases.sets.warm import warm_kernels
from mechlib.core.outcome import Solution

__all__ = [
    "DEFAULT_WORKBOOK",
    "ENVELOPE_FILE",
    "MARGINS_FILE",
    "MATRIX_FILE",
    "SetResult",
    "run_set",
    "solve_spec",
]

ENVELOPE_FILE = "envelope.csv"
MARGINS_FILE = "margins.csv"
MATRIX_FILE = "loads-matrix.csv"
DEFAULT_WORKBOOK = "envelope.xlsx"  # when the set has no `report:`

OnRecord = Callable[[RunRecord, int, int], None]  # (record, runs done, runs in total)
OnReport = Callable[[str], None]  # what the report is writing now

_PLOTS_PER_PROCESS = 16  # plots a drawing process takes at least
_RUNS_PER_PROCESS = 100  # fewer plots, but a set of this many runs: one process beside
# the workbook (1000 runs: 4 plots 0.3 s against a workbook of 1.5 s and a fork of 0.05 s)


@dataclass
class SetResult:
    """What `run_set` did: one record per run (in run order), envelope, curves, files."""

    compiled: CompiledSet
    directory: Path
    records: list[RunRecord]
    envelope: list[EnvelopeRow] = field(default_factory=list)
    curves: list[EnvelopeCurve] = field(default_factory=list)
    files: list[Path] = field(default_factory=list)
    interrupted: bool = False  # SIGINT/SIGTERM: runs missing, no envelope or report
    sizing: Sizing | None = None
    unwritten: str = ""  # the report's files that could not be written (disk full) and why

    @property
    def failed(self) -> list[RunRecord]:
        """The runs that did not finish (`status != "ok"`)."""
        return [record for record in self.records if not record.ok]


def _failed_outcome(
    spec: RunSpec, analysis: str, message: str, *, input_error: bool = False
) -> RunOutcome:
    """An outcome without rows for a run that could not be solved at all (`input_error`:
    its parameter values make the input invalid, e.g. a swept value overflowing an
    expression)."""
    solution = Solution(
        status="failed", message=message, analysis=analysis, time=np.empty(0), channels={}
    )
    return RunOutcome(
        spec.name,
        Path(spec.case_path),
        analysis,
        solution,
        spec.input_sha256,
        parameters=dict(spec.parameters),
        input_error=input_error,
        overrides=dict(spec.overrides),
    )


def solve_spec(spec: RunSpec) -> RunOutcome:
    """Solve one run (in any process); never raises: a problem is a failed outcome."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    analysis = "unknown"
    try:
        cf = load_case(spec.case_path, overrides=dict(spec.parameters))
        analysis = cf.case.analysis.type
        cf = dataclasses.replace(cf, input_sha256=spec.input_sha256)
        outcome = run_case(cf, abscissa=True, name=spec.name)
        outcome.overrides = dict(spec.overrides)
        return outcome
    except InputError as error:
        return _failed_outcome(spec, analysis, str(error), input_error=True)
    except Exception as error:  # noqa: BLE001  (a bug must not stop the other runs; reported)
        return _failed_outcome(spec, analysis, f"internal error: {type(error).__name__}: {error}")


def _csv_path(directory: Path, name: str) -> Path:
    base = result_base(directory, name)
    return base.with_name(base.name + ".csv")


def _reusable(directory: Path, spec: RunSpec) -> RunRecord | None:
    """The saved record of `spec` if its results are complete, ok, of the same input and
    engine, and its CSV is the one its summary was written with."""
    csv_path = _csv_path(directory, spec.name)
    try:
        summary = read_checked_summary(summary_path(csv_path))
    except InputError:  # not a summary `loads` wrote: solved again, the files rewritten
        return None
    if (
        summary is None
        or not csv_path.is_file()
        or summary.get("status") != "ok"
        or summary.get("input_sha256") != spec.input_sha256
        or summary.get("engine_sha256") != engine_hash.engine_sha256()
        or summary.get("csv_sha256") != engine_hash.file_sha256(csv_path)
    ):
        return None
    return record_from_summary(summary, csv_path, reused=True)


def _record(outcome: RunOutcome, spec: RunSpec, csv_path: Path) -> RunRecord:
    solution = outcome.solution
    return RunRecord(
        name=spec.name,
        family=spec.family,
        case_file=spec.case_path,
        parameters=dict(spec.parameters),
        analysis=outcome.analysis,
        status="failed" if outcome.unwritten else solution.status,
        message=outcome.unwritten or solution.message,
        steps=int(solution.stats.steps),
        cpu_seconds=float(solution.stats.cpu_seconds),
        input_sha256=spec.input_sha256,
        csv_path=csv_path,
        input_error=outcome.input_error,
        level=outcome.level,
        warnings=tuple(solution.warnings),
        input_warnings=tuple(outcome.warnings),
        accuracy=AccuracyVerdict.of(outcome.checks.get("accuracy")),
    )


def _solve_all(
    compiled: CompiledSet,
    directory: Path,
    executor: Executor,
    force: bool,
    on_record: OnRecord | None,
    xlsx: bool = False,
    solved: dict[str, SavedRun] | None = None,
    drawing: Drawing | None = None,
) -> tuple[list[RunRecord], bool]:
    """Records in run order (solved runs' results are written here as they arrive), and
    whether an interrupt stopped the set; `solved` gets each run solved ok, by name, as
    read back from its files (saved_run_of); `drawing` is started before the warm-up when
    the set draws its plots aside (`_plot_processes`)."""
    specs = list(compiled.runs)
    records: list[RunRecord | None] = [None if force else _reusable(directory, s) for s in specs]
    done = 0
    for record in records:
        if record is not None:
            done += 1
            if on_record is not None:
                on_record(record, done, len(specs))
    todo = [k for k, record in enumerate(records) if record is None]
    try:
        # the plots are not counted yet: a set whose fewest plots that go aside (two) would
        # not go aside has them drawn here, after the workbook
        if drawing is not None and _plot_processes(plots=2, runs=len(specs)) == 0:
            drawing = None
        if not _warmed(executor, [specs[k] for k in todo], drawing):  # interrupted: no run
            return [record for record in records if record is not None], True
        for index, outcome in executor.map_unordered(solve_spec, [specs[k] for k in todo]):
            if done == len(specs) - len(todo):  # the first solved run
                _import_report_modules(plots=drawing is None or drawing.pool is None)
            spec = specs[todo[index]]
            try:
                write_results(outcome, directory, version=compiled.version, xlsx=xlsx)
            except ResultsNotWritten as error:  # a failed run: out of the envelope
                outcome.unwritten = str(error)
            finished = _record(outcome, spec, _csv_path(directory, spec.name))
            if solved is not None and finished.ok:
                solved[finished.name] = saved_run_of(outcome)
            records[todo[index]] = finished
            done += 1
            if on_record is not None:
                on_record(finished, done, len(specs))
            if finished.status == "interrupted" and interrupts.received() is None:
                break  # Ctrl-C without loads' signal handlers (the Python API): stop here
    except KeyboardInterrupt:  # the runs under way came back interrupted; none starts now
        return [record for record in records if record is not None], True
    kept = [record for record in records if record is not None]
    return kept, len(kept) < len(specs) or interrupts.received() is not None


def _warmed(executor: Executor, specs: list[RunSpec], drawing: Drawing | None = None) -> bool:
    """Load the kernels of `specs` here when `executor` forks workers to solve them, which
    then inherit them (`loadcases.sets.warm`), `drawing`'s process started just before (it
    imports matplotlib on the core the warm-up leaves idle: `loadcases.sets.drawing`);
    False when an interrupt came meanwhile."""
    if isinstance(executor, PoolExecutor) and executor.forks(len(specs)):
        if drawing is not None:
            drawing.start()
        with collector_paused():
            return warm_kernels(specs)
    return True


REPORT_MODULES = (
    "loadcases.report.workbook",
    # write_workbook imports these (and with them openpyxl) only when called
    "loadcases.report.workbook_sheets",
    "loadcases.report.workbook_tables",
    "loadcases.report.workbook_charts",
    "loadcases.report.workbook_history",
    "openpyxl.packaging.extended",  # imported by openpyxl's save
    "encodings.cp437",  # zipfile's names in the saved workbook
)


def _import_report_modules(*, plots: bool = True) -> None:
    """Import what the report writes with (REPORT_MODULES: openpyxl) and, with `plots`,
    draws with (PLOT_MODULE: matplotlib; not when a process started before the warm-up
    draws the plots: `loadcases.sets.drawing`) while the workers solve, the cores busy
    anyway, instead of after the last run, when this process alone works (openpyxl and the
    workbook's sheet modules: 0.07 s of CPU of the campaign's serial report, 2026-11-29);
    the plot processes forked then inherit them. Called once the first run is back, when
    the solving processes have started (none is forked later)."""
    for module in (PLOT_MODULE, *REPORT_MODULES) if plots else REPORT_MODULES:
        importlib.import_module(module)


def _prebuild(compiled: CompiledSet) -> None:
    """Build and check every case once before solving (the checks of `loads validate`):
    what cannot be built, or is ill-posed for its analysis, is invalid input."""
    from loadcases.build.precheck import set_problems

    problems = set_problems(list(compiled.cases))
    if problems:
        raise InputError(problems)


def _report_files(
    result: SetResult,
    runs: list[SavedRun],
    options: dict[str, str],
    on_report: OnReport | None = None,
    drawing: Drawing | None = None,
) -> list[Path]:
    """envelope.csv, margins.csv, loads-matrix.csv, comparisons.csv (with `comparisons:`),
    the workbook and (if available) the plots of a set (`drawing`: its plots' process, if
    started); `on_report(text)` says what is being written."""
    from loadcases.report.comparison import (
        COMPARISON_FILE,
        comparison_rows,
        write_comparison_csv,
    )
    from loadcases.report.units import ReportUnits
    from loadcases.sets.mass import mass_table
    from loadcases.sets.references import reference_overlays, write_reference_files

    model = result.compiled.set_file.model
    units = ReportUnits.of(model.report.units.given() if model.report is not None else None)
    curves = [units.curve(curve) for curve in result.curves]  # as the workbook's
    early = drawing.pool if drawing is not None else None
    with _plots(curves, result.directory, early) as plots:  # drawn while the rest is written
        from loadcases.report.workbook import WorkbookData, write_workbook  # openpyxl: after

        files = [write_envelope_csv(result.envelope, result.directory / ENVELOPE_FILE)]
        output = model.report.output if model.report is not None else DEFAULT_WORKBOOK
        workbook = result.directory / output
        files.append(workbook)  # second, as the command lists the first two files
        if result.sizing is not None:
            lines = margin_lines(result.envelope, result.sizing.ultimate)
            files.append(write_margin_csv(lines, result.directory / MARGINS_FILE))
            files.append(write_matrix_csv(result.sizing.matrix, result.directory / MATRIX_FILE))
        if model.comparisons:
            rows = comparison_rows(model.comparisons, runs)
            files.append(write_comparison_csv(rows, result.directory / COMPARISON_FILE))
        template = None
        if model.report is not None and model.report.template:
            template = Path(result.compiled.set_file.path).parent / model.report.template
        data = units.workbook_data(WorkbookData.from_set(result, runs, options))
        if model.curves:
            found = reference_overlays(result.compiled, runs)
            data.references, written = write_reference_files(found, units, result.directory)
            files += written
        if model.mass_properties is not None:
            data.mass = mass_table(result.compiled)
            files.append(data.mass.write_csv(result.directory))
        with collector_paused():  # after the plots' processes are forked: theirs stays on
            write_workbook(data, workbook, template=template, progress=on_report)
        if on_report is not None:
            on_report("envelope plots")
        files += plots()
    return files + _polar_plots(runs, result.directory)


def _polar_plots(runs: list[SavedRun], directory: Path) -> list[Path]:
    """Polar plots and wear maps of the runs' clearance joints (`polar` requests), per run
    and overlaid per family, in `directory/polar/`."""
    from loadcases.report.wear_map import polar_requests

    with_polar = [run for run in runs if polar_requests(run)]
    if not with_polar:  # matplotlib not imported: a large set's plots are drawn aside
        return []
    from loadcases.report.polar_plots import write_runs_polar_plots  # matplotlib: here only

    return write_runs_polar_plots(with_polar, directory / "polar")


def _plot_processes(plots: int, runs: int) -> int:
    """Processes that draw `plots` envelope plots of a set of `runs` runs beside its
    workbook: up to one per core for many plots, one for a few of a large sweep, none
    (drawn here, after the workbook: a process would cost more than they take) else."""
    cores = os.cpu_count() or 1
    workers = min(cores, plots // _PLOTS_PER_PROCESS)
    if workers == 0 and cores > 1 and plots > 1 and runs >= _RUNS_PER_PROCESS:
        workers = 1  # a few plots of a large sweep: one process, beside the workbook
    return workers


@contextmanager
def _plots(
    curves: list[EnvelopeCurve], directory: Path, early: ProcessPoolExecutor | None = None
) -> Iterator[Callable[[], list[Path]]]:
    """PNG envelope plots of each family's main columns next to the workbook; yields the
    function that returns their paths. A large set's plots (`_plot_processes`: about
    0.07-0.12 s each) are drawn by processes while the caller writes the CSV files and the
    workbook, and the function waits for them: `early`'s (one process started before the
    runs, matplotlib imported: `loadcases.sets.drawing`) draws a share, and those still
    wanted are forked on entry after this process has imported matplotlib (already done
    while the runs were solved when no `early`: _import_report_modules). A small set's
    are drawn here, after the workbook."""
    chosen = plot_curves(curves)
    workers = _plot_processes(len(chosen), sum(len(curve.runs) for curve in curves))
    if early is not None and chosen:
        workers = max(workers, 1)
    if workers == 0:
        yield lambda: _draw_plots(chosen, directory)
        return
    chunks = [chosen[i::workers] for i in range(workers)]
    with ExitStack() as stack:
        pools = [early] if early is not None else []
        if workers > len(pools):
            import loadcases.report.plots  # noqa: F401  (matplotlib once: the workers inherit it)

            pools.append(stack.enter_context(ProcessPoolExecutor(max_workers=workers - len(pools))))
        # chunk 0 to the first pool (`early`'s process, if any), the others to the last
        futures = [
            pools[min(k, len(pools) - 1)].submit(_draw_plots, chunk, directory)
            for k, chunk in enumerate(chunks)
        ]

        def drawn() -> list[Path]:
            done = [future.result() for future in futures]
            # back into the curves' order: curve n is item n // workers of chunk n % workers
            return [done[n % workers][n // workers] for n in range(len(chosen))]

        yield drawn


def _draw_plots(curves: list[dict[str, object]], directory: Path) -> list[Path]:
    """`write_envelope_plots` (matplotlib imported only where plots are drawn)."""
    from loadcases.report.plots import write_envelope_plots

    return list(write_envelope_plots(curves, directory))


def run_set(
    path: str | Path,
    *,
    output_dir: str | Path,
    executor: Executor | None = None,
    force: bool = False,
    on_record: OnRecord | None = None,
    options: dict[str, str] | None = None,
    xlsx: bool = False,
    what_if: Sequence[Override] = (),
    on_report: OnReport | None = None,
    on_warning: Callable[[str], None] | None = None,
) -> SetResult:
    """Run a set file into `output_dir/SET/`; InputError (nothing run) for invalid input.

    `on_record(record, done, total)` is called as each run is reused or finishes,
    `on_report(text)` as each part of the report is written;
    `options` (e.g. jobs, scheduler) are recorded on the workbook's Provenance sheet;
    `xlsx` also writes each solved run's `NAME.xlsx`; `what_if` (`--set`) overrides
    parameters in every run of a case that has them (runs `CASE[name=value]`).
    One writer per folder: while it runs, `output_dir/SET/.loads.lock` names this process;
    `FolderBusy` (no run file written; only the cases' checks ran, which may have put a
    flexible body's content-addressed reduction in the folder's cache) if another live
    process holds it; a stale lock (its
    process gone) is taken over and `on_warning(text)` told so.
    """
    started = clock.time()
    compiled = load_and_compile_set(path, what_if=what_if)
    directory = result_base(Path(output_dir), compiled.name)
    with caching_under(directory):  # flexible bodies reduced once for all runs
        _prebuild(compiled)  # InputError here: nothing written, not even the folder
    drawing = Drawing()  # started by _solve_all if the set draws its plots aside
    with folder_lock.holding(directory, on_warning), closing(drawing):  # FolderBusy: another
        with caching_under(directory):  # run writes there
            solved: dict[str, SavedRun] = {}
            records, interrupted = _solve_all(
                compiled,
                directory,
                executor or SerialExecutor(),
                force,
                on_record,
                xlsx,
                solved,
                drawing,
            )
        if interrupted or any(r.status == "interrupted" for r in records):
            return SetResult(compiled, directory, records, interrupted=True)
        # only this set's runs, as written or reused above: never other files of the folder
        runs = [solved.get(r.name) or load_saved_run(r.csv_path) for r in records if r.ok]
        if on_report is not None:
            on_report("envelope")
        abscissae = {cf.case.case: cf.case.abscissa for cf in compiled.cases if cf.case.abscissa}
        sizing = size_runs(runs, compiled.set_file.model, abscissae)
        result = SetResult(compiled, directory, records, sizing.rows, sizing.curves, sizing=sizing)
        info = {
            "force": str(force),
            "wall seconds": f"{clock.time() - started:.3g}",
            **(options or {}),
        }
        try:
            result.files = _report_files(result, runs, info, on_report, drawing)
        except OSError as error:  # disk full, permissions: say which files are missing
            result.unwritten = _unwritten_report(result, error)
    return result


def _unwritten_report(result: SetResult, error: OSError) -> str:
    """What a report that could not be written leaves: its files missing, and why."""
    model = result.compiled.set_file.model
    names = [ENVELOPE_FILE, model.report.output if model.report is not None else DEFAULT_WORKBOOK]
    names += [MARGINS_FILE, MATRIX_FILE]
    missing = [str(result.directory / name) for name in names]
    missing = [path for path in missing if not Path(path).is_file()]
    return f"report not written ({error.strerror or error}); missing: " + (
        ", ".join(missing) or "its plots"
    )
