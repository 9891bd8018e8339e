"""`loads draw`: pictures of a mechanism during a run of a case (PNG, GIF).

Returns its exit status (0 success, 1 the run failed part-way: the pictures show what was
computed, 2 invalid input or usage); `cli.app` registers it through its `guarded` wrapper.
The work is done by `loadcases.draw.trajectory` (trajectory) and `loadcases.draw.render` (pictures).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, print_diagnostics

__all__ = ["draw"]

EXIT_OK, EXIT_FAILED, EXIT_INPUT = 0, 1, 2


def draw(
    case: Annotated[
        Path, typer.Argument(metavar="CASE", help="The case file (*.case.yaml) to solve and draw.")
    ],
    at: Annotated[
        list[float] | None,
        typer.Option(
            "--at",
            metavar="SECONDS",
            help="Draw a picture at this time (s); repeat the option for several. By default "
            "the pictures show the start, the middle and the end of the run.",
        ),
    ] = None,
    view: Annotated[
        str,
        typer.Option(
            "--view",
            metavar="PLANE",
            help="The projection plane: xy, yz, xz, or auto for the plane in which the "
            "mechanism spreads most.",
        ),
    ] = "auto",
    output: Annotated[
        Path, typer.Option("-o", "--output", metavar="DIR", help="The folder of the pictures.")
    ] = Path("pictures"),
    gif: Annotated[
        bool,
        typer.Option(
            "--gif",
            help="Also animate the run: a GIF when Pillow is installed, else numbered PNG frames.",
        ),
    ] = False,
) -> int:
    """Solve a case and draw its mechanism (bodies, joints, springs, wires and contacts)
    as PNG pictures."""
    from loadcases.diagnostics import InputError
    from loadcases.draw.render import VIEWS, write_animation, write_pngs
    from loadcases.draw.trajectory import trajectory_of_file

    if not case.is_file():
        raise fail(f"{case}: no such file")
    if view not in VIEWS:
        raise fail(f"--view {view}: use one of {', '.join(VIEWS)}")
    try:
        traj = trajectory_of_file(case)
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    if len(traj.time) == 0:
        typer.echo(f"{case}: the run failed before its first output: {traj.message}", err=True)
        return EXIT_FAILED
    times = (
        at
        if at
        else [float(traj.time[0]), float(traj.time[len(traj.time) // 2]), float(traj.time[-1])]
    )
    written = write_pngs(traj, times, output, view=view)
    for path in written:
        typer.echo(f"wrote {path}")
    if gif:
        files, what = write_animation(traj, output, view=view)
        typer.echo(f"wrote {what}: {files[0]}{' ...' if len(files) > 1 else ''}")
    if traj.status != "ok":
        typer.echo(f"{case}: the run failed: {traj.message} (pictures up to the failure)", err=True)
        return EXIT_FAILED
    return EXIT_OK
