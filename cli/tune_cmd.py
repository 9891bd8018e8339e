"""`loads tune`: the value of a case parameter that gives mode N a target frequency.

Returns its exit status (0 tuned, 1 no solution: no bracket or a run failed, 2 invalid input
or usage); `cli.app` registers it through its `guarded` wrapper. The work is done by
`loadcases.tune`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, print_diagnostics

__all__ = ["tune"]

EXIT_OK, EXIT_FAILED, EXIT_INPUT = 0, 1, 2


def tune(
    case: Annotated[
        Path,
        typer.Argument(metavar="CASE", help="A case file (*.case.yaml) with a modes analysis."),
    ],
    parameter: Annotated[
        str,
        typer.Option(
            "--parameter",
            metavar="NAME",
            help="The parameter to tune, of the case or of its mechanism.",
        ),
    ],
    mode: Annotated[
        int, typer.Option("--mode", metavar="N", help="The mode number; 1 is the lowest mode.")
    ],
    target: Annotated[
        str,
        typer.Option(
            "--target",
            metavar="FREQUENCY",
            help="The target frequency, e.g. '4.1672 Hz'; a bare number is in Hz.",
        ),
    ],
) -> int:
    """Find the value of a parameter that gives mode N the target frequency, by root
    finding on the case's modes analysis (as in latch-spring tuning)."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.foundation.units import UnitError, to_si
    from loadcases.studies.tune import TuneError, tune_parameter

    if not case.is_file():
        raise fail(f"{case}: no such file")
    try:
        hertz = to_si(target, "frequency")
    except UnitError as error:
        raise fail(f"--target {target}: {error}") from None
    if not hertz > 0:
        raise fail(f"--target {target}: the frequency must be positive")
    try:
        result = tune_parameter(case, parameter=parameter, mode=mode, target=hertz)
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    except TuneError as error:
        typer.echo(f"{case}: {parameter}: {error}", err=True)
        return EXIT_FAILED
    for k, (value, frequency) in enumerate(result.evaluations, start=1):
        typer.echo(f"  {k:3d}  {parameter} = {value:.10g}  mode {mode}: {frequency:.7f} Hz")
    typer.echo(
        f"{parameter} = {result.value:.10g} (SI) gives mode {mode} = "
        f"{result.frequency:.7f} Hz (target {hertz:.7g} Hz, "
        f"{result.iterations} evaluations)"
    )
    return EXIT_OK
