"""`loads run`: run case/set files one after another or in a process pool, and report each."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from cli.engine import Engine
from loadcases.foundation.diagnostics import Diagnostic, InputError

__all__ = ["FileReport", "RunLine", "run_all", "run_one"]

Progress = Callable[[float, float], None]


@dataclass(frozen=True)
class RunLine:
    """What `loads run` prints for one run (small and picklable, unlike a Solution)."""

    name: str
    status: str
    message: str
    steps: int
    cpu_seconds: float
    where: Path
    warnings: tuple[Diagnostic, ...] = ()  # the input's, as data
    solver_warnings: tuple[str, ...] = ()  # mechlib's messages (a reused run: its summary's)


@dataclass
class FileReport:
    """The runs of one input file, or the diagnostics that stopped it."""

    file: Path
    runs: list[RunLine] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    footer: list[str] = field(default_factory=list)  # printed after the run lines
    input_errors: bool = False  # a run's own input (its parameter values) is invalid: exit 2
    refused: str | None = None  # not run at all (another run writes its folder): exit 1
    unwritten: bool = False  # a set's report could not be written (disk full): exit 1

    @property
    def failed(self) -> bool:
        return (
            self.refused is not None
            or self.unwritten
            or any(run.status != "ok" for run in self.runs)
        )


def run_one(
    path: Path,
    *,
    engine: Engine,
    output_dir: Path,
    xlsx: bool,
    progress: Progress | None = None,
    what_if: tuple = (),
) -> FileReport:
    """Run one case file with `engine.run_file` (which writes the results); a mechanism file
    is checked with `engine.check_mechanism_file`. `what_if` are the `--set` overrides
    (passed on only when given; a mechanism file has no run to override: a note says so)."""
    from loadcases.inputs.kinds import file_kind, unknown_kind

    try:
        kind = file_kind(path)
        if kind is None:
            return FileReport(path, diagnostics=[unknown_kind(path)])
        if kind == "mechanism":
            notes = engine.check_mechanism_file(path)
            if what_if:
                notes.append(f"  note: --set does nothing for a mechanism file ({path.name})")
            return FileReport(path, notes=notes)
        options = {"what_if": what_if} if what_if else {}
        outcomes = engine.run_file(
            path, output_dir=output_dir, xlsx=xlsx, progress=progress, **options
        )
    except InputError as error:
        return FileReport(path, diagnostics=list(error.diagnostics))
    lines = []
    for outcome in outcomes:
        solution = outcome.solution
        lines.append(
            RunLine(
                outcome.name,
                "failed" if outcome.unwritten else solution.status,
                outcome.unwritten or solution.message,
                int(solution.stats.steps),
                float(solution.stats.cpu_seconds),
                _where(output_dir, outcome.name),
                tuple(outcome.warnings),
                tuple(solution.warnings),
            )
        )
    return FileReport(path, runs=lines)


def run_all(
    paths: list[Path],
    *,
    engine: Engine,
    output_dir: Path,
    xlsx: bool,
    jobs: int,
    progress_for: Callable[[Path], Progress | None],
    what_if: tuple = (),
) -> Iterator[FileReport]:
    """Reports in input order; files in parallel processes when `jobs > 1`.

    `progress_for(path)` gives the progress callback of a file run in this process
    (worker processes run without one).
    """
    from loadcases.foundation import interrupts

    workers = min(jobs, len(paths))
    if workers <= 1:
        for path in paths:
            if interrupts.received() is not None:
                return
            yield run_one(
                path,
                engine=engine,
                output_dir=output_dir,
                xlsx=xlsx,
                progress=progress_for(path),
                what_if=what_if,
            )
        return
    from loadcases.sets.executors import PoolExecutor

    task = functools.partial(
        run_one, engine=engine, output_dir=output_dir, xlsx=xlsx, what_if=what_if
    )
    ready: dict[int, FileReport] = {}
    following = 0  # the next report in input order
    try:
        for index, report in PoolExecutor(workers).map_unordered(task, paths):
            ready[index] = report
            while following in ready:
                yield ready.pop(following)
                following += 1
    except KeyboardInterrupt:  # the files that came back, then the interrupt goes on
        for index in sorted(ready):
            yield ready[index]
        raise


def _where(output_dir: Path, name: str) -> Path:
    """The CSV of a run if it is where section 3 puts it, else the output folder."""
    from loadcases.results.files import result_base  # imports mechlib: not for `loads --help`

    try:
        csv_path = result_base(output_dir, name)
    except ValueError:
        return output_dir
    csv_path = csv_path.with_name(csv_path.name + ".csv")
    return csv_path if csv_path.is_file() else output_dir
