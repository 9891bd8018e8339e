"""`loads plot` (PNG plots of saved results) and `loads new` (case skeletons).

Each command returns its exit status (0 success, 2 invalid input or usage); `cli.app`
registers them through its `guarded` wrapper. The work is done by `loadcases.report.plots` and
`loadcases.inputs.scaffold`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, invalid_input
from cli.units_option import SET_OPTION, UNITS_OPTION, report_units
from loadcases.foundation.diagnostics import InputError

__all__ = ["new", "plot"]

EXIT_OK = 0


def plot(
    results: Annotated[
        list[Path],
        typer.Argument(
            metavar="RESULTS",
            help="NAME.csv or NAME.summary.json files, or folders of results (searched "
            "recursively). Several runs are overlaid.",
        ),
    ],
    columns: Annotated[
        list[str] | None,
        typer.Option(
            "--columns",
            "-c",
            metavar="COLUMNS",
            help="The columns to plot: a request name (all its components) or a pattern such "
            "as 'hinge_*.fy'. Repeat the option or separate the names with commas. By "
            "default every column is plotted.",
        ),
    ] = None,
    x: Annotated[
        str,
        typer.Option(
            "--x",
            metavar="COLUMN",
            help="The abscissa: 'time' or a result column such as crank_angle.value.",
        ),
    ] = "time",
    output: Annotated[
        Path, typer.Option("-o", "--output", metavar="DIR", help="The folder of the PNG files.")
    ] = Path("plots"),
    units: UNITS_OPTION = None,
    set_file: SET_OPTION = None,
    polar: Annotated[
        list[str] | None,
        typer.Option(
            "--polar",
            metavar="REQUEST",
            help="Instead of time plots, draw the polar plots and wear map of this `polar` "
            "request of a clearance joint (for example --polar polar), per run and overlaid "
            "across the runs of a sweep. Repeat the option for several requests.",
        ),
    ] = None,
) -> int:
    """Write PNG plots of requests against time or another column, one file per request
    (with --polar: the polar plots and wear maps of clearance joints); values in SI, or in
    the units of --units / a set's report.units."""
    from loadcases.report import plots

    missing = [path for path in results if not path.exists()]
    if missing:
        raise fail("; ".join(f"{path}: no such file or folder" for path in missing))
    files = plots.find_result_csvs(results)
    if not files:
        raise fail(
            "no results (NAME.csv next to NAME.summary.json) under " + ", ".join(map(str, results))
        )
    patterns = [p.strip() for item in columns or [] for p in item.split(",") if p.strip()]
    if polar:
        return _polar(files, polar, output)
    report = report_units(set_file, units or [])
    try:
        runs = [report.run(plots.load_saved_run(path)) for path in files]
        shown = {k: v for run in reversed(runs) for k, v in run.units.items()}
        written = plots.plot_runs(
            [run.as_run() for run in runs], patterns or None, x=x, units=shown, out_dir=output
        )
    except InputError as error:  # a saved file that is not what `loads run` writes
        raise invalid_input(error.diagnostics) from None
    except ValueError as error:
        raise fail(str(error)) from None
    typer.echo(
        f"{len(written)} plots of {len(runs)} run{'s' if len(runs) != 1 else ''} -> {output}"
    )
    return EXIT_OK


def _polar(files: list[Path], requests: list[str], output: Path) -> int:
    """`loads plot --polar REQ`: polar plots and wear maps of the runs in `files`."""
    from loadcases.report import plots
    from loadcases.report.polar_plots import write_runs_polar_plots

    try:
        runs = [plots.load_saved_run(path) for path in files]
        written = write_runs_polar_plots(runs, output, requests)
    except InputError as error:
        raise invalid_input(error.diagnostics) from None
    except ValueError as error:
        raise fail(str(error)) from None
    typer.echo(
        f"{len(written)} polar plots and wear maps of {len(runs)} "
        f"run{'s' if len(runs) != 1 else ''} -> {output}"
    )
    return EXIT_OK


def new(
    kind: Annotated[
        str,
        typer.Argument(
            metavar="KIND",
            help="The kind of case: blank (a generic case to start from) or a load-case "
            "family: lifting, jamming, opening, opened, jettison, deployment or rod-end.",
        ),
    ],
    name: Annotated[
        str, typer.Argument(metavar="NAME", help="The case name; the file is NAME.case.yaml.")
    ],
    output: Annotated[
        Path, typer.Option("-o", "--output", metavar="DIR", help="The folder of the new file.")
    ] = Path("."),
) -> int:
    """Write a commented case skeleton that runs as it is: a blank case or one of a
    load-case family. An existing file is never overwritten."""
    from loadcases.inputs import scaffold

    try:
        path = scaffold.write_skeleton(kind, name, output)
    except (ValueError, FileExistsError) as error:
        raise fail(str(error)) from None
    typer.echo(
        f"{path}: {kind} case skeleton ({scaffold.SKELETONS[kind].summary}); "
        f"check it with `loads validate {path}`"
    )
    return EXIT_OK
