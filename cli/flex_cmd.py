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
            "docs/flexible-bodies-import.md), or a mechanism file (*.mech.yaml) with --body.",
        ),
    ],
    body: Annotated[
        str | None,
        typer.Option(
            "--body",
            metavar="NAME",
            help="With a mechanism file: the flexible body (beam, grillage, plate or file).",
        ),
    ] = None,
    modes: Annotated[
        int,
        typer.Option(
            "--modes",
            metavar="N",
            help="How many free-free modes to print (the rigid-body modes included).",
        ),
    ] = 12,
    reduced: Annotated[
        str,
        typer.Option(
            "--reduced",
            metavar="N1,N2,...",
            help="Fixed-interface mode counts of the Craig-Bampton reductions whose "
            "frequencies are compared with the full model's ('' for none).",
        ),
    ] = "2,5,10",
) -> int:
    """Read an imported flexible component (neutral npz, Matrix Market, NASTRAN OP4 or DMIG)
    and print its nodes, DOF, mass, interface and first free-free frequencies."""
    import numpy as np
    from scipy.sparse.linalg import ArpackError

    from loadcases.flexible.summary import free_free_frequencies, mass_properties
    from loadcases.foundation.diagnostics import InputError

    if not file.is_file():
        raise fail(f"{file}: no such file")
    if modes < 1:
        raise fail(f"--modes {modes}: give at least 1")
    try:
        counts = [int(t) for t in reduced.split(",") if t.strip()]
    except ValueError:
        raise fail(f"--reduced {reduced}: give whole numbers, e.g. 2,5,10") from None
    if any(c < 0 for c in counts):
        raise fail(f"--reduced {reduced}: a count is 0 or more")
    try:
        if file.suffix in (".yaml", ".yml"):
            model, names = _mechanism_body(file, body)
        else:
            model, names = _imported(file)
    except InputError as error:
        print_diagnostics(error.diagnostics, err=True)
        return EXIT_INPUT
    complete = sum(int((model.dof_map[:, 0] == i).sum() == 6) for i in range(len(model.node_ids)))
    typer.echo(
        f"  nodes: {len(model.node_ids)} ({complete} with six DOF); DOF: {len(model.dof_map)}"
    )
    props = mass_properties(model)
    typer.echo(
        f"  mass: {_vector(props.mass)} kg (x, y, z); centre of mass: {_vector(props.centre)} m"
    )
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
    if counts:
        _print_reductions(model, counts, modes)
    return EXIT_OK


def _imported(file: Path):
    """The model of an imported component's header and its node names (index -> name),
    its description printed; InputError for its files."""
    from loadcases.flexible.read import read_fe_model

    imported = read_fe_model(file)
    print_diagnostics(imported.warnings, err=True)
    typer.echo(f"{file}: {imported.description or 'no description'}")
    typer.echo(f"  units: {imported.units}; WTMASS {imported.wtmass:g}; shown in SI")
    return imported.model, {index: name for name, index in imported.node_names.items()}


def _mechanism_body(file: Path, body: str | None):
    """The full FE model of a mechanism's flexible body and its interface names; InputError
    for the mechanism file, a usage error for a body that is not flexible."""
    from loadcases.build.flexible import flexible_fe_model
    from loadcases.inputs.loader import load_mechanism
    from loadcases.schema.mechanism import FlexibleBody

    mechanism = load_mechanism(file).model
    flexible = sorted(n for n, b in mechanism.bodies.items() if isinstance(b, FlexibleBody))
    chosen = mechanism.bodies.get(body) if body is not None else None
    if not isinstance(chosen, FlexibleBody):
        known = ", ".join(flexible) or "none"
        raise fail(f"{file}: give --body, one of its flexible bodies: {known}")
    try:
        named = flexible_fe_model(chosen.flexible, file.parent)
    except ValueError as error:
        raise fail(f"{file}: body {body}: {error}") from None
    typer.echo(f"{file}: flexible body {body}, its full FE model (before reduction)")
    typer.echo("  units: SI")
    return named.model, {index: name for name, index in named.nodes.items()}


def _cells(full: float, values: list) -> str:
    cells = []
    for value in values:
        if value is None:
            cells.append(f"{'-':>14} {'':>9}")
        else:
            cells.append(f"{value:14.9g} {100.0 * (value / full - 1.0):+8.4f}%")
    return "  ".join(cells)


def _print_reductions(model, counts: list[int], rows: int) -> None:
    """The seed's Tables 3-2 and 3-3 in form: the full model's frequencies beside each
    reduction's, with the relative difference."""
    from loadcases.flexible.reduction_table import reduction_frequencies
    from mechlib.flexible.craig_bampton import ReductionError

    try:
        table = reduction_frequencies(model, counts, rows)
    except ReductionError as error:
        typer.echo(f"  reduced models: none ({error})")
        return
    header = "  ".join(f"{f'{c} fixed-int.':>14} {'diff':>9}" for c in table.counts)
    for title, first, full, reduced in (
        ("free-free elastic modes", table.rigid + 1, table.full_free, table.reduced_free),
        ("fixed-interface modes (interface nodes held)", 1, table.full_held, table.reduced_held),
    ):
        typer.echo(f"  {title} (Hz), full FE model against Craig-Bampton reductions:")
        typer.echo(f"    {'mode':>4}  {'full FE':>14}  {header}")
        for k, value in enumerate(full):
            cells = [float(r[k]) if k < r.size else None for r in reduced]
            typer.echo(f"    {first + k:4d}  {value:14.9g}  {_cells(float(value), cells)}")
