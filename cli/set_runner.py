"""`loads run SET.yaml`: run a load-case set through `loadcases.sets.campaign` and report it."""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

import typer

from cli.engine import RunSet
from cli.render import TerminalLine
from cli.runner import FileReport, RunLine
from loadcases.foundation.diagnostics import SHOWN_RUNS, InputError

if TYPE_CHECKING:
    from loadcases.sets.campaign import SetResult

__all__ = ["SetProgress", "run_set_file"]


class SetProgress(TerminalLine):
    """One line on a terminal: runs done / total, failed, estimated time left; then what
    part of the report is being written (`report`)."""

    def __init__(self, label: str, stream: TextIO | None = None) -> None:
        super().__init__(stream)
        self._label = label
        self._start = time.monotonic()
        self._failed = 0
        self._report_start = 0.0

    def __call__(self, record: object, done: int, total: int) -> None:
        self._failed += not getattr(record, "ok", True)
        if not self.due(final=done >= total):
            return
        now = time.monotonic()
        left = (now - self._start) / done * (total - done) if done else float("nan")
        self.draw(f"{self._label}: {done}/{total} runs, {self._failed} failed, ~{left:.0f} s left")

    def report(self, part: str) -> None:
        """`door.set.yaml: writing the report: workbook: time histories 3/22 (4 s)`."""
        seconds = time.monotonic() - self._report_start if self._report_start else 0.0
        self._report_start = self._report_start or time.monotonic()
        self.draw(f"{self._label}: writing the report: {part} ({seconds:.0f} s)")


def run_set_file(
    path: Path,
    *,
    run_set: RunSet,
    output_dir: Path,
    xlsx: bool,
    jobs: int | None,
    scheduler: str | None,
    force: bool,
    show_progress: bool,
    what_if: tuple = (),
) -> FileReport:
    """Run every run of a set file with `run_set` (loadcases'); one status line per run,
    failures and files listed. `what_if` are the `--set` overrides (passed on only when
    given, so that a test's own `run_set` need not take them)."""
    from loadcases.foundation.folder_lock import FolderBusy
    from loadcases.sets.executors import make_executor

    progress = SetProgress(path.name) if show_progress else None
    executor = make_executor(jobs=jobs, scheduler=scheduler)
    options = {"jobs": str(jobs or "cores"), "scheduler": scheduler or "local processes"}
    if what_if:  # on the workbook's Provenance sheet
        options["--set"] = ", ".join(f"{o.name}={o.text}" for o in what_if)
    try:
        result = run_set(
            path,
            output_dir=output_dir,
            executor=executor,
            force=force,
            on_record=progress,
            on_report=progress.report if progress is not None else None,
            options=options,
            xlsx=xlsx,
            on_warning=_warn,
            **({"what_if": what_if} if what_if else {}),
        )
    except InputError as error:
        return FileReport(path, diagnostics=list(error.diagnostics))
    except FolderBusy as busy:  # another `loads run` writes DIR/SET: nothing touched
        return FileReport(path, refused=str(busy))
    finally:
        if progress is not None:
            progress.close()
    lines = [
        RunLine(
            r.name + (" (reused)" if r.reused else ""),
            r.status,
            r.message,
            r.steps,
            r.cpu_seconds,
            r.csv_path if r.csv_path.is_file() else result.directory,
            warnings=r.input_warnings,
            solver_warnings=r.warnings,
        )
        for r in result.records
    ]
    footer = [
        f"{result.compiled.name}: {len(result.records)} runs, {len(result.failed)} "
        f"failed, {sum(r.reused for r in result.records)} reused"
    ]
    if result.interrupted:
        footer = [_interrupted_footer(result)]
    failed = [r for r in result.failed if r.status != "interrupted"]
    if failed:
        footer.append(f"failed runs ({len(failed)}):")
        footer += [f"  {r.name}: {r.message}" for r in failed]
    footer += [f"  -> {file}" for file in result.files[:2]]
    if result.unwritten:
        footer.append(f"{result.compiled.name}: {result.unwritten}")
    invalid = [r.name for r in result.records if r.input_error]
    if invalid:
        footer.append(
            f"runs whose parameter values make the input invalid ({len(invalid)}, exit 2): "
            + ", ".join(invalid[:SHOWN_RUNS])
            + (" ..." if len(invalid) > SHOWN_RUNS else "")
        )
    return FileReport(
        path,
        runs=lines,
        footer=footer,
        input_errors=bool(invalid),
        unwritten=bool(result.unwritten),
    )


def _warn(text: str) -> None:
    """`loads: warning: ...` on stderr, at once (e.g. a stale lock taken over)."""
    typer.echo(f"loads: warning: {text}", err=True)


def _interrupted_footer(result: SetResult) -> str:
    """What an interrupted set left: runs finished, stopped, not started; no report."""
    total = len(result.compiled.runs)
    stopped = sum(r.status == "interrupted" for r in result.records)
    return (
        f"{result.compiled.name}: interrupted: {len(result.records) - stopped} of {total} runs "
        f"finished, {stopped} stopped while solving (rows so far saved), "
        f"{total - len(result.records)} not started; envelope and workbook not written"
    )
