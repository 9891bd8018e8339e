"""The `loads` command line (SPEC section 2): run, validate, envelope, schema, bench.

Exit status: 0 success; 1 a solver failure (results up to the failure are written) or an
internal error; 2 invalid input or usage. Set `LOADS_DEBUG=1` to see tracebacks of
internal errors.
"""

import functools
import gc
import json
import os
import runpy
import sys
from collections.abc import Callable
from pathlib import Path
from textwrap import indent
from typing import Annotated, Any

import typer

from cli.engine import Engine, engine_of
from cli.help_style import use_domain_names
from cli.render import (
    ProgressBar,
    error_line,
    fail,
    invalid_input,
    not_written,
    print_diagnostics,
    status_line,
)
from cli.runner import FileReport, run_all
from loadcases.foundation.clip import visible
from loadcases.foundation.diagnostics import InputError

__all__ = ["app", "main"]

EXIT_OK, EXIT_FAILED, EXIT_INPUT = 0, 1, 2
DEBUG_ENV = "LOADS_DEBUG"
use_domain_names()

app = typer.Typer(
    name="loads",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Mechanism load cases from YAML: multibody reactions, envelopes and sizing workbooks.",
)


def _print_version(value: bool) -> None:
    if value:
        from loadcases.results.files import package_version

        typer.echo(f"loads {package_version()}")
        raise typer.Exit(EXIT_OK)


@app.callback()
def _options(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            help="Print the version of loads and exit.",
            is_eager=True,
            callback=_print_version,
        ),
    ] = False,
) -> None:
    """Mechanism load cases from YAML: multibody reactions, envelopes and sizing workbooks."""


# commands that only read their input and end within a second: the collector stays paused
_READ_ONLY_COMMANDS = frozenset({"validate", "schema"})


def guarded(command: Callable[..., int]) -> Callable[..., None]:
    """Turn a command's return value into its exit status and an unexpected exception
    into a one-line `internal error` (exit 1); `LOADS_DEBUG=1` lets the traceback through."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> None:
        if command.__name__ not in _READ_ONLY_COMMANDS:
            gc.enable()  # paused for the start-up (cli.entry); a long command needs it
        try:
            code = command(*args, **kwargs)
        except (typer.Exit, typer.Abort):
            raise
        except Exception as exc:  # any bug: short message, not a traceback
            if os.environ.get(DEBUG_ENV) == "1":
                raise
            typer.echo(_internal_error_text(exc), err=True)
            raise typer.Exit(EXIT_FAILED) from exc
        raise typer.Exit(code)

    return wrapper


def _internal_error_text(exc: BaseException) -> str:
    first_line = next(iter(str(exc).splitlines()), "")
    return (
        f"loads: internal error: {type(exc).__name__}: {first_line} (this is a bug in loads; "
        f"please report it with the input files; {DEBUG_ENV}=1 shows the traceback)"
    )


def _require_files(paths: list[Path]) -> None:
    """Exit 2 with one line per missing input file."""
    missing = [path for path in paths if not path.is_file()]
    for path in missing:
        typer.echo(error_line(f"{path}: no such file"), err=True)
    if missing:
        raise typer.Exit(EXIT_INPUT)


WhatIf = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        metavar="NAME=VALUE",
        help="Override the parameter NAME for this run, e.g. --set 'length=1.5 m' (a bare "
        "number is SI). Repeat it for more parameters. The run is named CASE[NAME=VALUE] "
        "and its summary lists the overrides.",
    ),
]


@app.command()
@guarded
def run(
    ctx: typer.Context,
    files: Annotated[
        list[Path],
        typer.Argument(
            metavar="FILE", help="The case (*.case.yaml) or set (*.set.yaml) files to run."
        ),
    ],
    output: Annotated[
        Path,
        typer.Option("-o", "--output", metavar="DIR", help="The folder the results go to."),
    ] = Path("results"),
    xlsx: Annotated[
        bool, typer.Option("--xlsx", help="Also write a workbook NAME.xlsx for each run.")
    ] = False,
    jobs: Annotated[
        int | None,
        typer.Option(
            "--jobs",
            "-j",
            min=1,
            metavar="N",
            help="The number of processes. Case files run one at a time unless N is given; "
            "the runs of a set use every core unless N is given.",
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            metavar="ADDRESS",
            help="Run the runs of sets on the Dask cluster whose scheduler is at ADDRESS, or "
            "on a local Dask cluster with 'local'. A scheduler that does not answer within "
            "10 s is an error.",
        ),
    ] = None,
    force: Annotated[
        bool,
        typer.Option(
            "--force",
            help="Solve every run of a set again, even when its saved results are of the "
            "same input.",
        ),
    ] = False,
    what_if: WhatIf = None,
) -> int:
    """Run case or set files and write their results. Each run writes NAME.csv and
    NAME.summary.json; a set SET also writes DIR/SET/envelope.csv and its workbook."""
    _require_files(files)
    engine = engine_of(ctx)
    from loadcases.foundation.limits import capped_jobs

    overrides = _overrides(what_if or [])
    _preflight(files, output, scheduler)
    jobs, note = capped_jobs(jobs)
    if note is not None:
        typer.echo(f"loads: warning: {note}", err=True)
    from loadcases.foundation import interrupts
    from mechlib.core.outcome import interrupt_of

    code = EXIT_OK
    with interrupts.on_signals():
        try:
            for chunk, is_set in _chunks(files, _is_set):
                if interrupts.received() is not None:
                    break
                if is_set:
                    for path in chunk:
                        if interrupts.received() is not None:
                            break
                        report = _run_set(
                            engine, path, output, xlsx, jobs, scheduler, force, overrides
                        )
                        code = max(code, _print_report(report))
                else:
                    code = max(code, _run_cases(engine, chunk, output, xlsx, jobs or 1, overrides))
        except (interrupts.Interrupted, SystemError) as stop:
            # outside a solve (files are written whole or not at all); a compiled kernel
            # wraps the signal it met in a SystemError
            if interrupt_of(stop) is None:
                raise
    signum = interrupts.received()
    if signum is None:
        return code
    typer.echo(
        f"loads: interrupted by {interrupts.signal_name(signum)}: the runs finished before "
        "stay valid; a run stopped while solving is saved with status 'interrupted' and its "
        "rows so far; no further run was started",
        err=True,
    )
    return interrupts.exit_code(signum)


def _overrides(texts: list[str]) -> tuple[Any, ...]:
    """The `--set` options read (`loadcases.inputs.overrides.Override`); exit 2 if one
    cannot be read."""
    from loadcases.inputs.overrides import OverrideError, parse_overrides

    try:
        return parse_overrides(texts)
    except OverrideError as error:
        raise fail(str(error)) from None


def _kind(path: Path) -> str | None:
    """The kind of a file, None when it cannot be told (the runner reports why)."""
    from loadcases.inputs.kinds import file_kind

    try:
        return file_kind(path)
    except InputError:
        return None


def _is_set(path: Path) -> bool:
    return _kind(path) == "set"


def _preflight(files: list[Path], output: Path, scheduler: str | None) -> None:
    """Exit 2 before solving when `-o` cannot take results, two case files share a
    `case:` name or the `--scheduler` of a set cannot be reached."""
    from loadcases.inputs.preflight import duplicate_case_names, output_folder_problem

    problem = output_folder_problem(output)
    if problem is not None:
        raise fail(f"-o {output}: {problem}")
    if scheduler and any(_is_set(path) for path in files):
        from loadcases.sets.executors import scheduler_problem

        problem = scheduler_problem(scheduler)
        if problem is not None:
            raise fail(f"--scheduler {scheduler}: {problem}")
    clashes = duplicate_case_names([path for path in files if _kind(path) == "case"])
    if clashes:
        print_diagnostics(clashes, err=True)
        raise typer.Exit(EXIT_INPUT)


def _chunks(files: list[Path], is_set: Callable[[Path], bool]) -> list[tuple[list[Path], bool]]:
    """Consecutive files of one kind (sets / other files), in input order."""
    chunks: list[tuple[list[Path], bool]] = []
    for path in files:
        kind = is_set(path)
        if chunks and chunks[-1][1] == kind:
            chunks[-1][0].append(path)
        else:
            chunks.append(([path], kind))
    return chunks


def _run_set(
    engine: Engine,
    path: Path,
    output: Path,
    xlsx: bool,
    jobs: int | None,
    scheduler: str | None,
    force: bool,
    overrides: tuple[Any, ...],
) -> FileReport:
    from cli.set_runner import run_set_file

    return run_set_file(
        path,
        run_set=engine.run_set,
        output_dir=output,
        xlsx=xlsx,
        jobs=jobs,
        scheduler=scheduler,
        force=force,
        show_progress=sys.stderr.isatty(),
        what_if=overrides,
    )


def _run_cases(
    engine: Engine,
    files: list[Path],
    output: Path,
    xlsx: bool,
    jobs: int,
    overrides: tuple[Any, ...] = (),
) -> int:
    """Case and mechanism files, as `loads run` always ran them; the worst exit status."""
    bars: dict[Path, ProgressBar] = {}
    show_progress = jobs == 1 and sys.stderr.isatty()
    code = EXIT_OK
    for report in run_all(
        files,
        engine=engine,
        output_dir=output,
        xlsx=xlsx,
        jobs=jobs,
        what_if=overrides,
        progress_for=lambda path: (
            bars.setdefault(path, ProgressBar(path.name)) if show_progress else None
        ),
    ):
        if report.file in bars:
            bars.pop(report.file).close()
        code = max(code, _print_report(report))
    return code


def _print_report(report: FileReport) -> int:
    """Print the status lines (or diagnostics) of one file; return its exit status."""
    if report.diagnostics:
        print_diagnostics(report.diagnostics, err=True)
        return EXIT_INPUT
    if report.refused is not None:
        typer.echo(error_line(report.refused), err=True)
        return EXIT_FAILED
    for note in report.notes:
        typer.echo(note)
    for line in report.runs:
        typer.echo(status_line(line.name, line.status, line.steps, line.cpu_seconds, line.where))
        if line.status != "ok":
            typer.echo(f"  {visible(line.message)}")  # hidden characters shown as escapes
        for diagnostic in line.warnings:  # as `loads validate` prints it: file:line:col
            typer.echo(indent(diagnostic.format(), "  "))
        for warning in line.solver_warnings:
            typer.echo(f"  warning: {visible(warning)}")
    for text in report.footer:
        typer.echo(text)
    if report.input_errors:
        return EXIT_INPUT
    return EXIT_FAILED if report.failed else EXIT_OK


@app.command()
@guarded
def validate(
    ctx: typer.Context,
    files: Annotated[
        list[Path],
        typer.Argument(metavar="FILE", help="The mechanism, case or set files to check."),
    ],
    what_if: WhatIf = None,
) -> int:
    """Check files without solving them. Each problem is printed as
    `file:line:col: error: key: message`, and each good file as `file: ok`. With `--set`,
    the case and set files are checked as `loads run --set` would run them."""
    _require_files(files)
    check_file = engine_of(ctx).check_file
    overrides = _overrides(what_if or [])
    options = {"what_if": overrides} if overrides else {}
    found, ok_files = [], []
    for path in files:
        diagnostics = check_file(path, **options)
        found.extend(diagnostics)
        if not any(d.severity == "error" for d in diagnostics):
            ok_files.append(path)
    print_diagnostics(found, err=False)
    for path in ok_files:
        typer.echo(f"{path}: ok")
    return EXIT_OK if len(ok_files) == len(files) else EXIT_INPUT


@app.command()
@guarded
def schema() -> int:
    """Print the JSON Schema of the mechanism, case and set files.

    To have an editor check a file as you type (VS Code with the YAML extension, or any
    editor with the YAML language server), save the schema once with
    `loads schema > loads.schema.json` and make this the first line of each YAML file:
    `# yaml-language-server: $schema=loads.schema.json` (the path is relative to the YAML
    file). Unknown keys, wrong types and missing keys are then marked as you type, and
    each key shows its description; `loads validate` still makes the checks a schema
    cannot (names, units, expressions, degrees of freedom)."""
    from loadcases.schema import json_schema

    typer.echo(json.dumps(json_schema(), indent=2))
    return EXIT_OK


@app.command()
@guarded
def envelope(
    dirs: Annotated[
        list[Path],
        typer.Argument(metavar="DIR", help="The folders of saved results, searched recursively."),
    ],
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="FILE",
            help="Write the sizing workbook (FILE.xlsx) or a CSV file (FILE.csv). Without "
            "it the envelope is printed as CSV.",
        ),
    ] = None,
    set_file: Annotated[
        Path | None,
        typer.Option(
            "--set", metavar="SET_FILE", help="Take the factors and allowables from this set file."
        ),
    ] = None,
) -> int:
    """Make the envelope of every result column across saved results: max and min, the
    governing run and time, the abscissa, concurrent values and margins. Failed runs are
    left out."""
    from loadcases.report import envelope as env
    from loadcases.report.saved_report import saved_report

    if output is not None and output.suffix.lower() not in (".xlsx", ".csv"):
        raise fail(f"{output}: output must end in .xlsx or .csv")
    for directory in dirs:
        if not directory.is_dir():
            raise fail(f"{directory}: no such folder")
    if set_file is not None:
        _require_files([set_file])
    try:
        report = saved_report(dirs, set_path=set_file)
    except InputError as error:  # a saved file that is not what `loads run` writes
        raise invalid_input(error.diagnostics) from None
    print_diagnostics(report.warnings, err=True)
    if not report.records:
        raise fail("no results (NAME.csv with a 'time' column) under " + ", ".join(map(str, dirs)))
    for record in report.records:
        if not record.ok:
            typer.echo(f"loads: note: {record.name} failed; left out of the envelope", err=True)
    if output is None:
        typer.echo(env.envelope_csv_text(report.rows), nl=False)
        return EXIT_OK
    try:
        if output.suffix.lower() == ".xlsx":
            from loadcases.report.workbook import write_workbook

            title = set_file.stem if set_file else ", ".join(map(str, dirs))
            write_workbook(report.workbook_data(title, set_file), output)
        else:
            env.write_envelope_csv(report.rows, output)
    except OSError as error:  # disk full, permissions: written whole or not at all
        raise not_written(output, error) from None
    typer.echo(f"envelope of {len(report.runs)} runs, {len(report.rows)} columns -> {output}")
    return EXIT_OK


@app.command()
@guarded
def bench(
    quick: Annotated[
        bool, typer.Option("--quick", help="Run a short subset of the suite.")
    ] = False,
    door: Annotated[
        bool,
        typer.Option(
            "--door",
            help="Time the door's whole load-case set instead (benchmarks/door_set.py).",
        ),
    ] = False,
    startup: Annotated[
        bool,
        typer.Option(
            "--startup",
            help="Time `loads --help` and `loads validate` of a door case instead "
            "(benchmarks/startup.py).",
        ),
    ] = False,
    campaign: Annotated[
        bool,
        typer.Option(
            "--campaign",
            help="Time a 200-variant sweep of the slider-crank in `loads run -j 2` against "
            "Exudyn with 2 processes instead (benchmarks/campaign.py).",
        ),
    ] = False,
    scaling: Annotated[
        bool,
        typer.Option(
            "--scaling",
            help="Time an N-link chain (N = 5 to 100) in both codes instead: time per step "
            "and per simulated second against N, a log-log PNG (benchmarks/scaling.py).",
        ),
    ] = False,
    kinds: Annotated[
        bool,
        typer.Option(
            "--kinds",
            help="Run the suite on the models of other kinds instead: a ball rattling in "
            "its socket, flaps latching by events, a four-bar with springs and friction, a "
            "hydraulic actuator (benchmarks/kinds/); then Kane's flexible spin-up beam and a "
            "flexible slider-crank against Exudyn's reduced FFRF body "
            "(benchmarks/flexible_compare.py).",
        ),
    ] = False,
) -> int:
    """Run the benchmark suite against Exudyn (with --kinds on contact, event, friction
    and hydraulic models), or with --door time the door's load-case set, with --startup
    the command's start-up, with --campaign a large sweep against Exudyn, with --scaling
    the cost against the number of bodies. It needs a source checkout
    (benchmarks/suite.py)."""
    suite = _find_bench_suite()
    if suite is None:
        raise fail(
            "benchmarks/suite.py not found: `loads bench` needs a source checkout "
            "(run it from the repository root)"
        )
    chosen = {"scaling": scaling, "campaign": campaign, "startup": startup, "door_set": door}
    module = next((name for name, on in chosen.items() if on), "suite")
    namespace = _load_bench_module(suite.with_name(f"{module}.py"))
    entry = namespace.get("main")
    if not callable(entry):
        raise fail(f"{suite.with_name(module + '.py')}: no main(argv) function")
    argv = ["--quick"] if quick and module == "suite" else []
    if kinds and module == "suite":
        argv.append("--kinds")
    result = entry(argv)
    return int(result or 0)


def _load_bench_module(path: Path) -> dict[str, Any]:
    """Execute a benchmark module; as `benchmarks.<name>` when `benchmarks/` is a package
    (so its relative imports work), with the checkout root first on `sys.path`."""
    added = [str(path.parent.parent), str(path.parent)]
    sys.path[:0] = added
    try:
        if (path.parent / "__init__.py").is_file():
            return runpy.run_module(f"{path.parent.name}.{path.stem}", run_name="loads_bench")
        return runpy.run_path(str(path), run_name="loads_bench")
    finally:
        for entry in added:
            sys.path.remove(entry)


def _find_bench_suite() -> Path | None:
    """benchmarks/suite.py next to this package (editable install) or in the current folder."""
    candidates = (Path(__file__).resolve().parents[1], Path.cwd())
    return next(
        (
            c / "benchmarks" / "suite.py"
            for c in candidates
            if (c / "benchmarks" / "suite.py").is_file()
        ),
        None,
    )


from cli import plot_cmd  # noqa: E402  (plot and new: registered through `guarded`)

app.command("plot")(guarded(plot_cmd.plot))
app.command("new")(guarded(plot_cmd.new))

from cli import accuracy_cmd, compare_cmd, draw_cmd  # noqa: E402  (through `guarded`)

app.command("draw")(guarded(draw_cmd.draw))
app.command("compare")(guarded(compare_cmd.compare))
app.command("accuracy")(guarded(accuracy_cmd.accuracy))

from cli import tune_cmd  # noqa: E402  (tune: parameter for a target frequency, via `guarded`)

app.command("tune")(guarded(tune_cmd.tune))

from cli import converge_cmd  # noqa: E402  (converge: a parameter's convergence study, via `guarded`)

app.command("converge")(guarded(converge_cmd.converge))

from cli import flex_cmd  # noqa: E402  (flex check: an imported flexible component, via `guarded`)

flex_app = typer.Typer(
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Flexible components imported from FE files (stiffness and mass).",
)
flex_app.command("check")(guarded(flex_cmd.check))
app.add_typer(flex_app, name="flex")


def main() -> None:
    """Console entry point `loads`."""
    try:
        app()
    except SystemExit as stop:
        from loadcases.foundation import interrupts

        if interrupts.received() is None:
            raise
        # Interrupted: every file is written and every worker gone. CPython 3.11's process
        # pools' exit hook can still write to a wake-up pipe its shut-down pool has closed
        # and print that OSError as a traceback; the exit hooks have nothing left to do.
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(stop.code if isinstance(stop.code, int) else EXIT_FAILED)
    except Exception as exc:  # failures outside any command (e.g. while importing)
        if os.environ.get(DEBUG_ENV) == "1":
            raise
        print(_internal_error_text(exc), file=sys.stderr)
        sys.exit(EXIT_FAILED)
    finally:
        # The interpreter's exit collects garbage over every object still alive: the ~80,000
        # that pydantic, pint and numpy build at import cost `loads validate` about 0.2 s of
        # its 0.9 s there (measured on the 2-core VM). Frozen objects are left out of those
        # collections; the process returns their memory. Nothing of loads relies on the
        # exit's collection: its files are closed by `with`, its pools shut down by it.
        gc.freeze()


if __name__ == "__main__":
    main()
