"""`loads accuracy CASE`: the work-precision study of a dynamic case."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, invalid_input
from loadcases.foundation.accuracy_target import DEFAULT_ACCURACY, target_problem

__all__ = ["accuracy"]

_HEADER = (
    "integrator",
    "tolerance",
    "status",
    "CPU (s)",
    "steps",
    "rejected",
    "error (of peak)",
    "worst column",
)


def _numbers(text: str, option: str) -> list[float]:
    """The tolerances of `option`, each in [MIN_TOLERANCE, 1) (exit 2 otherwise)."""
    from loadcases.foundation.limits import MIN_TOLERANCE

    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise fail(f"{option}: '{text[:80]}' is not a comma-separated list of numbers") from None
    if not values or any(not (MIN_TOLERANCE <= v < 1.0) for v in values):
        raise fail(
            f"{option}: each tolerance must lie between {MIN_TOLERANCE:g} and 1 (got '{text[:80]}')"
        )
    return values


def _settings_problem(
    output: Path, repeats: int, ladder: list[float], reference: float | None
) -> str | None:
    """What makes `-o`, `--repeats` or `--reference-tolerance` unusable, or None."""
    from loadcases.foundation.limits import MAX_REPEATS, MIN_TOLERANCE
    from loadcases.inputs.preflight import output_folder_problem

    problem = output_folder_problem(output)
    if problem is not None:
        return f"-o {output}: {problem}"
    if not 1 <= repeats <= MAX_REPEATS:
        return f"--repeats: {repeats} must be a whole number from 1 to {MAX_REPEATS}"
    if reference is not None and not MIN_TOLERANCE <= reference < min(ladder):
        return (
            f"--reference-tolerance must be at least {MIN_TOLERANCE:g} and tighter than "
            "every tolerance studied"
        )
    return None


def _row(cells: tuple[object, ...]) -> str:
    widths = (18, 10, 7, 9, 8, 9, 16, 30)
    return "  ".join(str(c)[:w].ljust(w) for c, w in zip(cells, widths)).rstrip()


def accuracy(
    case: Annotated[
        Path, typer.Argument(metavar="CASE", help="A case file with a dynamic analysis.")
    ],
    output: Annotated[
        Path,
        typer.Option(
            "-o",
            "--output",
            metavar="DIR",
            help="The folder for the table, the diagram and the workbook.",
        ),
    ] = Path("results"),
    target: Annotated[
        float,
        typer.Option(
            "--target",
            metavar="FRACTION",
            help="The error wanted, as a fraction of each request's peak.",
        ),
    ] = DEFAULT_ACCURACY,
    tolerances: Annotated[
        str,
        typer.Option(
            "--tolerances", metavar="LIST", help="The tolerances to try, separated by commas."
        ),
    ] = "1e-3,1e-4,1e-5,1e-6,1e-7",
    integrators: Annotated[
        str,
        typer.Option(
            "--integrators",
            metavar="LIST",
            help="The integrators to study, separated by commas: generalized-alpha, radau.",
        ),
    ] = "generalized-alpha,radau",
    repeats: Annotated[
        int,
        typer.Option(
            "--repeats",
            metavar="N",
            help="The number of runs per setting; the CPU time is their median.",
        ),
    ] = 3,
    reference_tolerance: Annotated[
        float | None,
        typer.Option(
            "--reference-tolerance",
            metavar="TOLERANCE",
            help="The tolerance of the reference runs. By default it is the tightest "
            "tolerance studied divided by 100.",
        ),
    ] = None,
) -> int:
    """Work-precision study: solve the case on a ladder of tolerances with each integrator,
    measure every request's error against a much tighter run of the other integrator, and
    recommend the cheapest setting that meets the target. Writes NAME.accuracy.csv,
    NAME.accuracy-columns.csv, NAME.accuracy.png and NAME.accuracy.xlsx."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_case
    from loadcases.studies.accuracy import (
        INTEGRATORS,
        ReferenceFailure,
        accuracy_study,
        check_study,
    )
    from loadcases.studies.accuracy_files import recommendation_text, write_accuracy_files

    if not case.is_file():
        raise fail(f"{case}: no such file")
    methods = [m.strip() for m in integrators.split(",") if m.strip()]
    unknown = [m for m in methods if m not in INTEGRATORS]
    if unknown or not methods:
        raise fail(
            f"--integrators: unknown '{', '.join(unknown)[:80]}' (choose from "
            f"{', '.join(INTEGRATORS)})"
        )
    problem = target_problem(target)
    if problem is not None:
        raise fail(f"--target: {problem}")
    ladder = _numbers(tolerances, "--tolerances")
    problem = _settings_problem(output, repeats, ladder, reference_tolerance)
    if problem is not None:
        raise fail(problem)
    try:
        cf = load_case(case)
        check_study(cf, methods)  # an input error exits before the table starts
    except InputError as error:
        raise invalid_input(error.diagnostics) from None
    typer.echo(_row(_HEADER))

    def show(result) -> None:
        column, worst = result.worst()
        typer.echo(
            _row(
                (
                    result.setting.integrator,
                    f"{result.setting.tolerance:g}",
                    result.status,
                    f"{result.cpu_seconds:.3g}",
                    result.stats.get("steps"),
                    result.stats.get("rejected_steps"),
                    f"{worst:.3g}",
                    column,
                )
            )
        )

    try:
        study = accuracy_study(
            cf,
            tolerances=ladder,
            integrators=methods,
            target=target,
            repeats=repeats,
            progress=show,
            reference_tolerance=reference_tolerance,
        )
    except InputError as error:  # a model the engine refuses when it is solved
        raise invalid_input(error.diagnostics) from None
    except ReferenceFailure as failure:  # nothing to measure against: a solver failure
        raise fail(f"{case}: {failure}", code=1) from None
    for note in study.notes:
        typer.echo(f"note: {note}")
    typer.echo(recommendation_text(study))
    for path in write_accuracy_files(study, output):
        typer.echo(f"-> {path}")
    return 0
