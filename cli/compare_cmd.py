"""`loads compare OLD NEW`: the console table of two envelopes compared row by row."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, invalid_input, not_written, print_diagnostics
from cli.units_option import SET_OPTION, UNITS_OPTION, report_units
from loadcases.foundation.diagnostics import Diagnostic, InputError

__all__ = ["compare"]

_WIDTHS = (34, 8, 12, 12, 9, 12, 12, 9)


def _warn(warning: Diagnostic) -> None:
    """A warning of a saved file read (on stderr, as it is found)."""
    print_diagnostics([warning], err=True)


def _g(value: float | None) -> str:
    return "" if value is None else f"{value:.6g}"


def _pct(value: float | None) -> str:
    return "" if value is None else f"{100.0 * value:+.2f}%"


def _line(cells: tuple[str, ...]) -> str:
    return "  ".join(c[:w].ljust(w) for c, w in zip(cells, _WIDTHS)).rstrip()


def compare(
    old: Annotated[
        Path,
        typer.Argument(
            metavar="OLD",
            help="The old results: a set's result folder, its envelope.csv, or a folder of "
            "saved runs.",
        ),
    ],
    new: Annotated[Path, typer.Argument(metavar="NEW", help="The new results, given as OLD is.")],
    output: Annotated[
        Path | None,
        typer.Option(
            "-o",
            "--output",
            metavar="FILE",
            help="Also write the whole comparison to FILE, which ends in .csv or .xlsx.",
        ),
    ] = None,
    rows: Annotated[
        int,
        typer.Option(
            "--rows",
            metavar="N",
            help="The number of rows shown on the console, largest changes first.",
        ),
    ] = 40,
    units: UNITS_OPTION = None,
    set_file: SET_OPTION = None,
) -> int:
    """Compare two envelopes row by row. Each row shows the old and new max and min (SI, or
    the units of --units / a set's report.units), their difference in percent of the old
    peak of the row's request and the governing run of each; rows that are new or have
    vanished are listed too, changes at round-off level last but one, marked (noise). A
    CSV output stays SI; a workbook shows the units of the console."""
    from loadcases.report.compare import (
        STATUSES,
        compare_envelopes,
        in_report_units,
        read_envelope,
        write_compare,
    )

    if output is not None and output.suffix.lower() not in (".csv", ".xlsx"):
        raise fail(f"{output}: output must end in .csv or .xlsx")
    shown_units = report_units(set_file, units or [])
    try:
        si_table = compare_envelopes(read_envelope(old, _warn), read_envelope(new, _warn))
    except InputError as error:  # a saved file that is not what `loads` writes
        raise invalid_input(error.diagnostics) from None
    except ValueError as error:
        raise fail(str(error)) from None
    table = in_report_units(si_table, shown_units)
    typer.echo(
        _line(("column", "unit", "old max", "new max", "change", "old min", "new min", "change"))
    )
    for row in table[: max(rows, 0)]:
        typer.echo(
            _line(
                (
                    row.column,
                    row.unit,
                    _g(row.old_max),
                    _g(row.new_max),
                    _pct(row.max_change),
                    _g(row.old_min),
                    _g(row.new_min),
                    _pct(row.min_change),
                )
            )
            + ("" if row.status in ("changed", "same") else f"  ({row.status})")
        )
        if row.status == "changed" and (
            row.old_max_run != row.new_max_run or row.old_min_run != row.new_min_run
        ):
            typer.echo(
                f"    governing max: {row.old_max_run} -> {row.new_max_run}; "
                f"min: {row.old_min_run} -> {row.new_min_run}"
            )
    counts = {s: sum(r.status == s for r in table) for s in STATUSES}
    if not counts["noise"]:
        del counts["noise"]
    shown = min(len(table), max(rows, 0))
    more = f" ({len(table) - shown} more not shown)" if shown < len(table) else ""
    typer.echo(", ".join(f"{n} {s}" for s, n in counts.items()) + f" of {len(table)} rows" + more)
    if output is not None:
        written = si_table if output.suffix.lower() == ".csv" else table
        try:
            write_compare(written, output, old=str(old), new=str(new))
        except OSError as error:  # disk full, permissions: written whole or not at all
            raise not_written(output, error) from None
        typer.echo(f"-> {output}")
    return 0
