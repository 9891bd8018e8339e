"""`loads flex check FILE`: an imported flexible component read as a run would read it, and
what a user checks before using it: nodes, DOF, mass and centre of mass, the interface and
the first free-free frequencies.

Returns its exit status (0 read, 1 the eigen-solver failed on a model that passed the
import's checks, 2 invalid input); `cli.app` registers it through its
`guarded` wrapper. The work is done by `loadcases.flexible` (`read.read_fe_model`,
`summary`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.render import fail, print_diagnostics

__all__ = ["check"]

EXIT_OK, EXIT_SOLVER, EXIT_INPUT = 0, 1, 2
_COMPONENTS = "123456"


def _vector(values: object) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"  # type: ignore[attr-defined]


def check(
    file: Annotated[
        Path,
        typer.Argument(
            metavar="FILE",
            help="The JSON header of the component (NAME.json; see "
            "docs/flexible-bodies-import.md).",
        ),
    ],
    modes: Annotated[
        int,
        typer.Option(
            "--modes",
            metavar="N",
            help="How many free-free modes to print (the rigid-body modes included).",
        ),
    ] = 12,
) -> int:
    """Read an imported flexible component (neutral npz, Matrix Market, NASTRAN OP4 or DMIG)
    and print its nodes, DOF, mass, interface and first free-free frequencies."""
    import numpy as np
    from scipy.sparse.linalg import ArpackError

    from loadcases.flexible.read import read_fe_model
    from loadcases.flexible.summary import free_free_frequencies, mass_properties
    from loadcases.foundation.diagnostics import InputError

    if not file.is_file():
        raise fail(f"{file}: no such file")
    if modes < 1:
        raise fail(f"--modes {modes}: give at least 1")
    try:
        imported = read_fe_model(file)
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    print_diagnostics(imported.warnings, err=True)
    model = imported.model
    typer.echo(f"{file}: {imported.description or 'no description'}")
    typer.echo(f"  units: {imported.units}; WTMASS {imported.wtmass:g}; shown in SI")
    complete = sum(int((model.dof_map[:, 0] == i).sum() == 6) for i in range(len(model.node_ids)))
    typer.echo(
        f"  nodes: {len(model.node_ids)} ({complete} with six DOF); DOF: {len(model.dof_map)}"
    )
    props = mass_properties(model)
    typer.echo(
        f"  mass: {_vector(props.mass)} kg (x, y, z); centre of mass: {_vector(props.centre)} m"
    )
    names = {index: name for name, index in imported.node_names.items()}
    typer.echo(f"  interface: {len(model.interface)} nodes")
    for node in model.interface:
        label = f" ({names[node]})" if node in names else ""
        typer.echo(f"    {model.node_ids[node]}{label} at {_vector(model.coordinates[node])} m")
    try:
        hertz, rigid = free_free_frequencies(model, modes)
    except (np.linalg.LinAlgError, ArpackError) as error:  # the import checks passed
        typer.echo(f"{file}: error: the free-free eigenproblem failed: {error}", err=True)
        return EXIT_SOLVER
    typer.echo("  free-free frequencies (Hz):")
    for number, (value, is_rigid) in enumerate(zip(hertz, rigid), start=1):
        typer.echo(f"    {number:4d}  {value:.9g}{'  rigid-body' if is_rigid else ''}")
    return EXIT_OK
