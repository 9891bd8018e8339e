"""`read_fe_model(header.json)`: an imported flexible component as a checked `FEModel` in SI
units, whatever its format (neutral npz, Matrix Market, NASTRAN OP4 or DMIG).

Every problem is an `InputError` whose diagnostics name the file (the header, a matrix or
a node table), the line and key where known, and what is wrong; warnings (weight units
suspected, an unchecked mass matrix) come back with the result.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from loadcases.flexible import checks, solvable
from loadcases.flexible.bounds import node_id_problem
from loadcases.flexible.header import Header, load_header
from loadcases.flexible.neutral import npz_source
from loadcases.flexible.raw import RawModel
from loadcases.flexible.scales import Scales, read_scales, to_si_matrix
from loadcases.flexible.sources import dmig_source, matrix_market_source, op4_source
from loadcases.foundation.clip import describe_character, hidden_character, visible
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.limits import MAX_NODE_DISTANCE, MAX_NODE_ID
from mechlib.flexible.fe_model import FEModel

__all__ = ["FEImport", "read_fe_model"]

SOURCES: dict[str, Callable[[Header], RawModel | None]] = {
    "npz": npz_source,
    "matrix-market": matrix_market_source,
    "op4": op4_source,
    "dmig": dmig_source,
}
NASTRAN = ("op4", "dmig")
_WEIGHT_FORCES = ("lbf", "kip", "kipf", "ozf", "pdl", "poundal", "pound_force")


@dataclass(frozen=True)
class FEImport:
    """An imported component: its model (SI), description, node names (name -> node
    index), the units and WTMASS factor applied, every file read (header first: what a
    run's input hash must cover) and the warnings found."""

    model: FEModel
    description: str
    node_names: dict[str, int]
    units: str
    wtmass: float
    files: tuple[Path, ...]
    warnings: tuple[Diagnostic, ...]

    def node(self, ref: int | str) -> int:
        """Index of a node given by its id or name; KeyError if there is none."""
        if isinstance(ref, str):
            return self.node_names[ref]
        hits = np.flatnonzero(self.model.node_ids == ref)
        if hits.size == 0:
            raise KeyError(f"no node {ref}")
        return int(hits[0])


_READ: dict[Path, tuple[tuple, FEImport]] = {}  # header -> (stamps of its files, import)
_KEEP = 4  # imports remembered: a run reads its model twice (input hash, then build)


def _stamps(files: tuple[Path, ...]) -> tuple:
    """(name, modification time ns, size) of each file: what says it is unchanged."""
    return tuple((str(f), f.stat().st_mtime_ns, f.stat().st_size) for f in files)


def read_fe_model(path: Path) -> FEImport:
    """The component described by the JSON header at `path`, checked and in SI units;
    InputError with every problem found otherwise. Read once while none of its files
    changes (the loader hashes the files, the build reduces the model)."""
    key = Path(path).resolve()
    seen = _READ.get(key)
    if seen is not None:
        try:
            if _stamps(seen[1].files) == seen[0]:
                return seen[1]
        except OSError:
            pass
    imported = _read(Path(path))
    _READ.pop(key, None)
    if len(_READ) >= _KEEP:
        _READ.pop(next(iter(_READ)))
    _READ[key] = (_stamps(imported.files), imported)
    return imported


def _read(path: Path) -> FEImport:
    """read_fe_model without the memory."""
    header = load_header(path)
    scales = read_scales(header)
    raw = SOURCES[header.data["format"]](header)
    header.stop_if_errors()
    assert raw is not None and scales is not None
    model, names, wtmass = _model(header, raw, scales)
    header.stop_if_errors()
    assert model is not None
    description = header.data.get("description", "")
    return FEImport(
        model,
        description if isinstance(description, str) else json.dumps(description),
        names,
        scales.text(),
        wtmass,
        (header.path, *dict.fromkeys(raw.files)),
        tuple(header.warnings),
    )


def _dof_rows(header: Header, raw: RawModel, index: dict[int, int]) -> np.ndarray | None:
    """(ndof, 2) node index and component 0-5 of the raw DOF map; None with problems."""
    dofs = np.asarray(raw.dofs, dtype=np.int64).reshape(-1, 2)
    unknown = sorted({int(n) for n in dofs[:, 0] if int(n) not in index})
    where = raw.stiffness_file
    if unknown:
        shown = ", ".join(map(str, unknown[:10]))
        header.in_file(where, f"the DOF map names nodes without coordinates: {shown}")
    if np.any((dofs[:, 1] < 1) | (dofs[:, 1] > 6)):
        header.in_file(where, "the DOF map has components outside 1-6")
    if len({(int(a), int(b)) for a, b in dofs}) != len(dofs):
        header.in_file(where, "the DOF map names a DOF twice")
    if header.errors:
        return None
    return np.column_stack([[index[int(n)] for n in dofs[:, 0]], dofs[:, 1] - 1]).astype(np.int64)


def _wtmass(header: Header, raw: RawModel, scales: Scales) -> float:
    """The factor on the mass matrix as written: the header's `wtmass` (NASTRAN formats),
    else 1. PARAM,WTMASS found in bulk data is not applied, with a warning: NASTRAN applies
    it when it generates element masses, so the MAA/MGG it writes (OUTPUT4, the EXTOUT DMIG
    punch) already hold it, and DMIG mass input (M2GG) is not scaled by it. Without either,
    imperial force units warn that the masses may be weights."""
    given = header.data.get("wtmass")
    kind = header.data["format"]
    if given is not None:
        if kind not in NASTRAN:
            header.problem(("wtmass",), f"wtmass is for NASTRAN files (op4, dmig), not {kind}")
        elif isinstance(given, bool) or not isinstance(given, (int, float)) or not given > 0:
            header.problem(("wtmass",), f"expected a positive number, got {json.dumps(given)}")
        else:
            return float(given)
        return 1.0
    if raw.wtmass is not None and raw.wtmass[0] != 1.0:
        value, file, line = raw.wtmass
        header.warn(
            ("wtmass",),
            f"PARAM,WTMASS,{value:g} ({file} line {line}) is not applied: the mass matrices "
            "NASTRAN writes already hold it and DMIG mass input is not scaled by it",
            hint=f'if the mass matrix as written is in weight units, give "wtmass": {value:g}',
        )
        return 1.0
    names = dict(scales.names)
    if kind in NASTRAN and names.get("force", "").lower() in _WEIGHT_FORCES:
        header.warn(
            ("units", "force"),
            f"no wtmass: the masses are taken in {names['force']}*{names.get('time', 's')}^2/"
            f"{names['length']} (consistent units, as NASTRAN writes MAA/MGG)",
            hint='if the mass matrix as written is in weight units (lbm), give "wtmass": '
            "0.00259 (1/386.09)",
        )
    return 1.0


def _model(
    header: Header, raw: RawModel, scales: Scales
) -> tuple[FEModel | None, dict[str, int], float]:
    """The checked FEModel (SI), node names and WTMASS; problems recorded on the header."""
    ids = np.asarray(raw.node_ids, dtype=np.int64)
    _check_nodes(header, raw, ids)
    if header.errors:
        return None, {}, 1.0
    index = {int(n): i for i, n in enumerate(ids)}
    if len(index) != len(ids):
        header.in_file(raw.stiffness_file, "a node id is given twice")
        return None, {}, 1.0
    dof_map = _dof_rows(header, raw, index)
    if dof_map is None:
        return None, {}, 1.0
    for matrix, path, what in (
        (raw.stiffness, raw.stiffness_file, "the stiffness matrix"),
        (raw.mass, raw.mass_file, "the mass matrix"),
    ):
        problem = checks.shape_problem(matrix, len(dof_map), what)
        if problem is not None:
            header.in_file(path, problem)
    wtmass = _wtmass(header, raw, scales)
    if header.errors:
        return None, {}, wtmass
    rotational = dof_map[:, 1] >= 3
    # a finite file value may overflow once scaled (1e308 in mm): _check_si reports it
    with np.errstate(over="ignore", invalid="ignore"):
        stiffness = to_si_matrix(raw.stiffness, rotational, scales, "stiffness")
        mass = to_si_matrix(raw.mass, rotational, scales, "mass") * wtmass
        coordinates = np.asarray(raw.coordinates, dtype=float) * scales.length
    _check_si(header, raw, (stiffness, mass, coordinates), scales)
    if header.errors:
        return None, {}, wtmass
    _check_matrices(header, raw, stiffness, mass)
    names = _names(header, raw, index)
    interface = _interface(header, raw, index, names, dof_map)
    if header.errors or interface is None:
        return None, names, wtmass
    model = FEModel(ids, coordinates, dof_map, stiffness, mass, interface)
    _check_solvable(header, raw, model)
    return (None if header.errors else model), names, wtmass


def _check_nodes(header: Header, raw: RawModel, ids: np.ndarray) -> None:
    """Node ids in range and finite coordinates, whatever the format read them."""
    where = raw.files[-1] if raw.files else raw.stiffness_file
    bad = np.flatnonzero((ids < 1) | (ids > MAX_NODE_ID))
    if bad.size:
        header.in_file(where, f"node {node_id_problem(int(ids[bad[0]]))}")
    xyz = np.asarray(raw.coordinates, dtype=float)
    if xyz.shape != (len(ids), 3):
        header.in_file(where, f"coordinates: expected ({len(ids)}, 3), got {xyz.shape}")
    elif not np.all(np.isfinite(xyz)):
        row = int(np.flatnonzero(~np.all(np.isfinite(xyz), axis=1))[0])
        header.in_file(
            where, f"coordinates of node {int(ids[row])}: expected finite numbers, got {xyz[row]}"
        )


def _check_si(header: Header, raw: RawModel, arrays: tuple, scales: Scales) -> None:
    """The matrices and coordinates still finite once in SI (units such as `1e300 m`
    scale finite file values beyond float range), and the nodes within MAX_NODE_DISTANCE
    of the origin."""
    stiffness, mass, coordinates = arrays
    for values, path, what in (
        (stiffness.data, raw.stiffness_file, "the stiffness matrix"),
        (mass.data, raw.mass_file, "the mass matrix"),
        (coordinates, raw.files[-1] if raw.files else raw.stiffness_file, "the coordinates"),
    ):
        if not np.all(np.isfinite(values)):
            header.problem(
                ("units",),
                f"{what} of {path.name} overflow once in SI (units {scales.text()}): "
                "check the units",
            )
            return
    far = np.flatnonzero(np.max(np.abs(coordinates), axis=1, initial=0.0) > MAX_NODE_DISTANCE)
    if far.size:
        node, distance = int(raw.node_ids[far[0]]), np.max(np.abs(coordinates[far[0]]))
        header.in_file(
            raw.files[-1] if raw.files else raw.stiffness_file,
            f"node {node} is {distance:.3g} m from the origin, "
            f"beyond {MAX_NODE_DISTANCE:g} m (a mechanism part): check the coordinates and "
            "the units of the header",
        )


def _check_matrices(header: Header, raw: RawModel, stiffness: object, mass: object) -> None:
    """Symmetry, diagonals and (mass) semi-definiteness, as problems of the matrix files."""
    for matrix, path, what in (
        (stiffness, raw.stiffness_file, "the stiffness matrix"),
        (mass, raw.mass_file, "the mass matrix"),
    ):
        for problem in (
            checks.symmetry_problem(matrix, what),
            checks.diagonal_problem(matrix, raw.dofs, what),
        ):
            if problem is not None:
                header.in_file(path, problem)
    if header.errors:
        return
    for matrix, path, what, quantity in (
        (mass, raw.mass_file, "the mass matrix", "mass or inertia"),
        (stiffness, raw.stiffness_file, "the stiffness matrix", "stiffness"),
    ):
        try:
            problem = checks.definiteness_problem(matrix, what, quantity)
        except (ArithmeticError, ValueError, RuntimeError) as error:  # off-diagonal pivots
            key = "mass" if matrix is mass else "stiffness"
            header.warn((key,), f"{what} could not be checked for definiteness: {error}")
            continue
        if problem is not None:
            header.in_file(path, problem)


def _check_solvable(header: Header, raw: RawModel, model: FEModel) -> None:
    """What the eigen-solvers after the import need (`solvable`), as problems of the
    matrix files: six rigid-body modes, K and M definite with the interface held, mass on
    the translations of a part's scale."""
    for path, problem in (
        (raw.stiffness_file, solvable.rigid_body_problem(model)),
        (raw.mass_file, solvable.translation_mass_problem(model)),
    ):
        if problem is not None:
            header.in_file(path, problem)
    if header.errors:
        return
    for matrix, path, what in (
        (model.stiffness, raw.stiffness_file, "the stiffness matrix"),
        (model.mass, raw.mass_file, "the mass matrix"),
    ):
        problem = solvable.interior_problem(model, matrix, what)
        if problem is not None:
            header.in_file(path, problem)
    if not header.errors:
        problem = solvable.elastic_mass_problem(model)
        if problem is not None:
            header.in_file(raw.mass_file, problem)


def _names(header: Header, raw: RawModel, index: dict[int, int]) -> dict[str, int]:
    """Node names (name -> node index): the node table's, then the header's `node_names`."""
    given = header.data.get("node_names", {})
    if not isinstance(given, dict):
        header.problem(("node_names",), 'expected {"name": node id, ...}')
        given = {}
    names: dict[str, int] = {}
    for name, node in [*raw.node_names.items(), *given.items()]:
        hidden = hidden_character(name)
        if hidden is not None:
            header.problem(
                ("node_names",),
                f"{describe_character(hidden)} in the node name '{visible(name)[:40]}'",
            )
            continue
        if isinstance(node, bool) or not isinstance(node, int) or node not in index:
            header.problem(("node_names", name), f"'{name}': no node {json.dumps(node)}")
            continue
        names[name] = index[node]
    return names


def _interface(
    header: Header, raw: RawModel, index: dict[int, int], names: dict[str, int], dofs: np.ndarray
) -> tuple[int, ...] | None:
    """Node indices of the interface (header ids or names, else the files' ASET grids),
    each carrying six DOF; None with problems."""
    given = header.data.get("interface", raw.interface)
    if not isinstance(given, list):
        header.problem(("interface",), "expected a list of node ids or names")
        return None
    found: list[int] = []
    for i, ref in enumerate(given):
        wrong = None if isinstance(ref, str) else node_id_problem(ref)
        if wrong is not None:
            header.problem(("interface", i), f"{wrong} or a node name")
            continue
        node = names.get(ref) if isinstance(ref, str) else index.get(ref)
        if node is None:
            header.problem(("interface", i), f"no node {json.dumps(ref)}")
            continue
        carried = int(np.count_nonzero(dofs[:, 0] == node))
        if carried != 6:
            header.problem(
                ("interface", i),
                f"interface node {json.dumps(ref)} carries {carried} DOF: an interface node "
                "needs all six (ux uy uz rx ry rz)",
            )
            continue
        if node not in found:
            found.append(node)
    return None if header.errors else tuple(found)
