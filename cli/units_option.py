"""The `--units KIND=UNIT` and `--set SET_FILE` options of `loads plot` and `loads compare`:
the units in which a command shows values (a set's `report.units`, then `--units`)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from cli.render import fail, print_diagnostics

if TYPE_CHECKING:
    from loadcases.report.units import ReportUnits

__all__ = ["SET_OPTION", "UNITS_OPTION", "report_units"]

UNITS_OPTION = Annotated[
    list[str] | None,
    typer.Option(
        "--units",
        metavar="KIND=UNIT",
        help="Show a kind of quantity in a unit, e.g. --units force=kN,angle=deg (kinds as in "
        "a set's report.units). Repeat the option or separate with commas.",
    ),
]
SET_OPTION = Annotated[
    Path | None,
    typer.Option(
        "--set",
        metavar="SET_FILE",
        help="Show the values in this set file's report.units (--units wins over it).",
    ),
]


def report_units(set_file: Path | None, texts: list[str]) -> ReportUnits:
    """The units a command shows: the set file's `report.units`, then `--units` texts;
    exit 2 (with the file's diagnostics) for a set file or a unit that cannot be read."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_set
    from loadcases.report.units import ReportUnits

    given = [t.strip() for item in texts for t in item.split(",") if t.strip()]
    if set_file is not None:
        try:
            model = load_set(set_file).model
        except InputError as error:
            print_diagnostics(error.diagnostics, err=True)
            raise typer.Exit(2) from None
        if model.report is not None:
            given = [f"{k}={v}" for k, v in model.report.units.given().items()] + given
    try:
        return ReportUnits.parse(given)
    except ValueError as error:
        raise fail(str(error)) from None
