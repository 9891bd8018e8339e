"""`loads tune`: the value of a case parameter that gives mode N a target frequency, or a
hinge line a target torque margin.

Returns its exit status (0 tuned, 1 no solution: no bracket or a run failed, 2 invalid input
or usage); `cli.app` registers it through its `guarded` wrapper. The work is done by
`loadcases.studies.tune`.
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
        typer.Argument(
            metavar="CASE",
            help="A case file (*.case.yaml): a modes analysis (--mode) or a case with "
            "torque_margin: (--margin).",
        ),
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
        int | None,
        typer.Option("--mode", metavar="N", help="The mode number; 1 is the lowest mode."),
    ] = None,
    margin: Annotated[
        str | None,
        typer.Option(
            "--margin",
            metavar="HL",
            help="A hinge line of the case's torque_margin: tune its minimum torque margin.",
        ),
    ] = None,
    target: Annotated[
        str | None,
        typer.Option(
            "--target",
            metavar="VALUE",
            help="With --mode the target frequency, e.g. '4.1672 Hz' (a bare number is in "
            "Hz); with --margin the target TM (default: the case's required ratio).",
        ),
    ] = None,
    restart: Annotated[
        bool, typer.Option("--restart", help="With --margin: tune the restart TM instead.")
    ] = False,
) -> int:
    """Find the value of a parameter that gives mode N the target frequency (latch-spring
    tuning) or a hinge line the target torque margin (deployment-spring stiffness or
    wind-up), by root finding on the case's analysis."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.studies.tune import TuneError

    if not case.is_file():
        raise fail(f"{case}: no such file")
    if (mode is None) == (margin is None):
        raise fail("give --mode N (a frequency) or --margin HL (a torque margin), one of them")
    try:
        if margin is not None:
            result = _tune_margin(case, parameter, margin, target, restart)
        else:
            assert mode is not None
            result = _tune_mode(case, parameter, mode, target)
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    except TuneError as error:
        typer.echo(f"{case}: {parameter}: {error}", err=True)
        return EXIT_FAILED
    _print_result(result, restart)
    return EXIT_OK


def _tune_mode(case: Path, parameter: str, mode: int, target: str | None):
    from loadcases.foundation.units import UnitError, to_si
    from loadcases.studies.tune import tune_parameter

    if target is None:
        raise fail("--mode needs --target FREQUENCY, e.g. --target '4.1672 Hz'")
    try:
        hertz = to_si(target, "frequency")
    except UnitError as error:
        raise fail(f"--target {target}: {error}") from None
    if not hertz > 0:
        raise fail(f"--target {target}: the frequency must be positive")
    return tune_parameter(case, parameter=parameter, mode=mode, target=hertz)


def _tune_margin(case: Path, parameter: str, line: str, target: str | None, restart: bool):
    from loadcases.studies.tune import tune_margin

    ratio = None
    if target is not None:
        try:
            ratio = float(target)
        except ValueError:
            raise fail(f"--target {target}: with --margin give a ratio, e.g. 2") from None
        if not ratio > 0:
            raise fail(f"--target {target}: the torque margin must be positive")
    return tune_margin(case, parameter=parameter, hinge_line=line, target=ratio, restart=restart)


def _print_result(result, restart: bool) -> None:
    if result.hinge_line is not None:
        what = f"{'restart ' if restart else ''}TM {result.hinge_line}"
        unit, shown = "", ".7g"
    else:
        what, unit, shown = f"mode {result.mode}", " Hz", ".7f"
    for k, (value, achieved) in enumerate(result.evaluations, start=1):
        typer.echo(f"  {k:3d}  {result.parameter} = {value:.10g}  {what}: {achieved:{shown}}{unit}")
    typer.echo(
        f"{result.parameter} = {result.value:.12g} (SI) gives {what} = "
        f"{result.achieved:{shown}}{unit} (target {result.target:.7g}{unit}, "
        f"{result.iterations} evaluations)"
    )
