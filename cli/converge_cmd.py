"""`loads converge`: a case run at several values of one parameter (the mode count of its
flexible bodies), every request's peak tabulated against it, and where each converges.

Returns its exit status (0 studied, 1 a run failed, 2 invalid input or usage); `cli.app`
registers it through its `guarded` wrapper. The work is done by
`loadcases.studies.convergence` and `convergence_files`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, print_diagnostics

__all__ = ["converge", "tolerance_fraction"]

EXIT_OK, EXIT_FAILED, EXIT_INPUT = 0, 1, 2
_SHOWN = 3  # parameter values printed per quantity: the first, the one before last, the last


def tolerance_fraction(text: str) -> float:
    """`1 %` or `1%` -> 0.01; a bare number is a fraction (`0.01`). ValueError otherwise."""
    stripped = text.strip()
    percent = stripped.endswith("%")
    value = float(stripped.rstrip("%").strip()) / (100.0 if percent else 1.0)
    if not 0.0 < value < 1.0:
        raise ValueError("give a tolerance between 0 and 100 %")
    return value


def _print_table(study) -> None:
    typer.echo(
        f"{study.case}: {len(study.quantities)} quantities against {study.parameter} = "
        f"{', '.join(study.texts)} (tolerance {100 * study.tolerance:g} %)"
    )
    width = max((len(q.name) for q in study.quantities), default=8)
    for q in study.quantities:
        if q.noise:
            verdict = "round-off (~0)"
        elif q.converged_at is None:
            verdict = "NOT converged"
        else:
            verdict = f"converged at {study.parameter} = {study.texts[q.converged_at]}"
        values = "  ".join(f"{v:.6g}" for v in q.values)
        typer.echo(f"  {q.name:<{width}}  [{q.unit or '-'}]  {values}  {verdict}")
    for run in study.runs:
        state = "ok" if run.ok else f"FAILED: {run.message}"
        typer.echo(
            f"  run {study.parameter} = {run.text}: {run.steps} steps, "
            f"{run.cpu_seconds:.3g} s CPU, {state}"
        )


def converge(
    case: Annotated[Path, typer.Argument(metavar="CASE", help="A case file (*.case.yaml).")],
    parameter: Annotated[
        str,
        typer.Option(
            "--parameter",
            metavar="NAME",
            help="The parameter swept, of the case or its mechanism (e.g. the one that "
            "`fixed_interface_modes` names).",
        ),
    ],
    values: Annotated[
        str,
        typer.Option(
            "--values",
            metavar="V1,V2,...",
            help="Its values, increasing, comma-separated (a unit allowed: '100 Hz,200 Hz').",
        ),
    ],
    tolerance: Annotated[
        str,
        typer.Option("--tolerance", metavar="TOL", help="Relative tolerance, e.g. '1 %'."),
    ] = "1 %",
    columns: Annotated[
        str,
        typer.Option(
            "-c",
            "--columns",
            metavar="PATTERNS",
            help="Result columns studied, comma-separated glob patterns "
            "('latch_torque.*,sadm_force.f*'; a modes analysis: 'mode 1'); default all.",
        ),
    ] = "",
    output: Annotated[
        Path, typer.Option("-o", "--output", metavar="DIR", help="Folder of the table and plot.")
    ] = Path("results"),
) -> int:
    """Run a case at each value of a parameter (the number of fixed-interface modes), and
    tabulate and plot every request's peak (a modes analysis: every frequency) against it,
    saying from which value on each stays within the tolerance."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.preflight import output_folder_problem
    from loadcases.studies.convergence import run_study
    from loadcases.studies.convergence_files import write_convergence_files

    if not case.is_file():
        raise fail(f"{case}: no such file")
    try:
        fraction = tolerance_fraction(tolerance)
    except ValueError as error:
        raise fail(f"--tolerance {tolerance}: {error}") from None
    problem = output_folder_problem(output)
    if problem is not None:
        raise fail(f"-o {output}: {problem}")
    texts = [t.strip() for t in values.split(",") if t.strip()]

    def progress(text: str, outcome) -> None:
        s = outcome.solution
        typer.echo(
            f"  {parameter} = {text}: {s.status}, {s.stats.steps} steps, "
            f"{s.stats.cpu_seconds:.3g} s CPU",
            err=True,
        )

    try:
        study = run_study(
            case,
            parameter=parameter,
            texts=texts,
            tolerance=fraction,
            columns=[c.strip() for c in columns.split(",") if c.strip()],
            progress=progress,
        )
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    _print_table(study)
    for path in write_convergence_files(study, output):
        typer.echo(f"wrote {path}")
    return EXIT_FAILED if study.failed else EXIT_OK
