"""`loads draw`: pictures of a mechanism during a run of a case or of a set (PNG, GIF, or an
interactive 3-D HTML page).

Returns its exit status (0 success, 1 the run failed part-way: the pictures show what was
computed, 2 invalid input or usage); `cli.app` registers it through its `guarded` wrapper.
The work is done by `loadcases.draw.trajectory` (trajectory), `loadcases.draw.render`
(pictures) and `loadcases.draw.page` (the HTML page).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from cli.render import error_line, fail, print_diagnostics
from loadcases.foundation.clip import visible

if TYPE_CHECKING:
    from loadcases.inputs.loader import CaseFile

__all__ = ["draw"]

EXIT_OK, EXIT_FAILED, EXIT_INPUT = 0, 1, 2


def _case_to_draw(path: Path, run: str | None) -> tuple[CaseFile, str | None]:
    """The case to draw and the name of the drawing (None: the case's own name): the case
    file, or run `run` of a set file; exit 2 on a wrong or missing `--run`."""
    from loadcases.inputs.kinds import file_kind
    from loadcases.inputs.loader import load_case
    from loadcases.schema.errors import did_you_mean
    from loadcases.sets.specs import case_of_run

    if file_kind(path) != "set":
        if run is not None:
            raise fail(f"--run {run}: {path} is not a set file; --run picks a run of a set")
        return load_case(path), None
    found = case_of_run(path, run or "")
    if isinstance(found, list):
        problem = f"has no run '{run}'" if run is not None else "is a set: choose a run with --run"
        typer.echo(error_line(f"{path} {problem}; its runs are:"), err=True)
        for name in found:
            typer.echo(f"  {name}", err=True)
        hint = did_you_mean(run, found) if run is not None else None
        if hint:
            typer.echo(f"hint: {hint}", err=True)
        raise typer.Exit(EXIT_INPUT)
    return found, run


def _joints_to_load(forces: str | None, cf: CaseFile) -> list[str]:
    """The joints named by `--forces` (comma-separated); exit 2 on an unknown one."""
    from loadcases.draw.trajectory import skeleton_of
    from loadcases.schema.errors import did_you_mean

    if forces is None:
        return []
    if cf.case.analysis.type == "modes":
        raise fail("--forces: a modes analysis computes no reaction forces")
    names = [n.strip() for n in forces.split(",") if n.strip()]
    known = list(skeleton_of(cf.mechanism).joints)
    for name in names:
        if name not in known:
            hint = did_you_mean(name, known)
            raise fail(
                f"--forces: the mechanism has no joint '{name}' with a point"
                f"{f' ({hint})' if hint else ''}; its joints are {', '.join(known)}"
            )
    return list(dict.fromkeys(names))


def _usage_problem(at: list[float] | None, view: str, html: bool, forces: str | None) -> str:
    """What is wrong with the combination of options, or ''."""
    from loadcases.draw.page import plotly_missing
    from loadcases.draw.render import VIEWS

    if view not in VIEWS:
        return f"--view {view}: use one of {', '.join(VIEWS)}"
    if forces is not None and not html:
        return "--forces draws arrows in the HTML page: add --html"
    if html and at:
        return "--at chooses the times of PNG pictures; the HTML page has a time slider instead"
    return (plotly_missing() or "") if html else ""


def draw(
    case: Annotated[
        Path,
        typer.Argument(
            metavar="FILE",
            help="The case file (*.case.yaml) to solve and draw, or a set file (*.set.yaml) "
            "with --run.",
        ),
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
            "mechanism spreads most. In the HTML page, the plane the camera first looks at.",
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
    # `\\[` in help texts: typer reads [...] as rich markup and would drop it
    html: Annotated[
        bool,
        typer.Option(
            "--html",
            help="Write an interactive 3-D view of the run, NAME.html, instead of the PNG "
            "pictures: drag to turn it, scroll to zoom, move the time slider or press Play. "
            "The page holds everything it needs and opens without a network. It needs the "
            "optional plotly package: pip install 'loads\\[html]'.",
        ),
    ] = False,
    forces: Annotated[
        str | None,
        typer.Option(
            "--forces",
            metavar="JOINTS",
            help="With --html, draw the reaction force of these joints (names separated by "
            "commas, e.g. pivot,hinge) as arrows at the joint: the force on the joint's first "
            "body from its second, the length proportional to the magnitude.",
        ),
    ] = None,
    run: Annotated[
        str | None,
        typer.Option(
            "--run",
            metavar="NAME",
            help="The run of a set file to draw, named as loads run names it "
            "(e.g. opening\\[angle=1.2]). A wrong name lists the runs of the set.",
        ),
    ] = None,
) -> int:
    """Solve a case, or one run of a set, and draw its mechanism (bodies, joints, springs,
    wires and contacts) as PNG pictures or as an interactive 3-D page."""
    from loadcases.draw.trajectory import solve_trajectory
    from loadcases.foundation.diagnostics import InputError

    if not case.is_file():
        raise fail(f"{case}: no such file")
    problem = _usage_problem(at, view, html, forces)
    if problem:
        raise fail(problem)
    try:
        cf, name = _case_to_draw(case, run)
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    traj = solve_trajectory(cf, forces=_joints_to_load(forces, cf), name=name)
    for warning in traj.branch_warnings:
        typer.echo(f"{case}: warning: {visible(warning)}", err=True)
    if len(traj.time) == 0:
        message = visible(traj.message)
        typer.echo(f"{case}: the run failed before its first output: {message}", err=True)
        return EXIT_FAILED
    for line in _write(traj, at, view, output, gif=gif, html=html):
        typer.echo(line)
    if traj.status != "ok":
        message = visible(traj.message)
        typer.echo(f"{case}: the run failed: {message} (pictures up to the failure)", err=True)
        return EXIT_FAILED
    return EXIT_OK


def _write(traj, at: list[float] | None, view: str, output: Path, *, gif: bool, html: bool):
    """Write the pictures asked for; yields a `wrote ...` line for each."""
    from loadcases.draw.page import write_html
    from loadcases.draw.render import write_animation, write_pngs

    if html:
        yield f"wrote {write_html(traj, output, view=view)}"
    else:
        # the first, middle and last rows: one picture of a static case's single row
        times = at or sorted({float(traj.time[k]) for k in (0, len(traj.time) // 2, -1)})
        for path in write_pngs(traj, times, output, view=view):
            yield f"wrote {path}"
    if gif:
        files, what = write_animation(traj, output, view=view)
        yield f"wrote {what}: {files[0]}{' ...' if len(files) > 1 else ''}"
