"""The format readers behind a header: Matrix Market, NASTRAN OP4 and NASTRAN DMIG, each
turning the files the header names into a `RawModel` (file units), or None with the
problems recorded on the header."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.bulk import BulkData, DmigMatrix, read_bulk
from loadcases.flexible.header import Header
from loadcases.flexible.market import read_matrix_market
from loadcases.flexible.nodes import NodeTable, read_dofs, read_nodes, six_per_node
from loadcases.flexible.op4 import Op4Matrix, read_op4
from loadcases.flexible.raw import RawModel
from loadcases.flexible.values import FileFormatError

__all__ = ["dmig_source", "matrix_market_source", "op4_source"]

MATRICES = ("stiffness", "mass")


def _node_table(header: Header) -> tuple[NodeTable | None, np.ndarray | None, list[Path]]:
    """The header's node table and DOF table (None when not given) and the files read."""
    nodes_path = header.named_file(("nodes",), header.data.get("nodes"))
    table = read_nodes(header, nodes_path) if nodes_path is not None else None
    read = [nodes_path] if nodes_path is not None else []
    dofs = None
    if "dofs" in header.data:
        dofs_path = header.named_file(("dofs",), header.data["dofs"])
        if dofs_path is not None:
            dofs, read = read_dofs(header, dofs_path), [*read, dofs_path]
    return table, dofs, read


def _raw(
    matrices: list[Any], files: list[Path], table: NodeTable, dofs: Any, **extra: Any
) -> RawModel:
    """The RawModel of (matrix, file) pairs for stiffness and mass on the node table (six
    DOF per node unless a DOF map is given)."""
    dof_map = dofs if dofs is not None else six_per_node(table.ids)
    return RawModel(
        sp.csr_matrix(matrices[0][0], dtype=float),
        sp.csr_matrix(matrices[1][0], dtype=float),
        np.asarray(dof_map, dtype=np.int64).reshape(-1, 2),
        table.ids,
        table.coordinates,
        matrices[0][1],
        matrices[1][1],
        node_names=table.names,
        files=files,
        **extra,
    )


def matrix_market_source(header: Header) -> RawModel | None:
    """`stiffness` and `mass` Matrix Market files, `nodes` (and `dofs`) tables."""
    matrices = []
    for name in MATRICES:
        path = header.named_file((name,), header.data.get(name))
        if path is None:
            continue
        try:
            matrices.append((read_matrix_market(path), path))
        except FileFormatError as error:
            header.in_file(path, error.message, line=error.line)
        except OSError as error:
            header.in_file(path, f"cannot read: {error}")
    table, dofs, read = _node_table(header)
    if header.errors or table is None or len(matrices) != 2:
        return None
    return _raw(matrices, [matrices[0][1], matrices[1][1], *read], table, dofs)


def _matrix_ref(header: Header, key: str) -> tuple[Path | None, str | None]:
    """(file, matrix name or None) of `"stiffness": "FILE"` or `{"file": F, "matrix": N}`."""
    ref = header.data.get(key)
    if isinstance(ref, dict):
        unknown = [k for k in ref if k not in ("file", "matrix")]
        for k in unknown:
            header.problem((key, k), f"unknown key '{k}' (use file, matrix)")
        name = ref.get("matrix")
        if name is not None and not isinstance(name, str):
            header.problem((key, "matrix"), "expected the name of a matrix, like KAA")
            name = None
        return header.named_file((key, "file"), ref.get("file")), name
    return header.named_file((key,), ref), None


def _pick(header: Header, key: str, path: Path, found: dict[str, Any], name: str | None) -> Any:
    """The matrix `name` of a file (the only one when no name is given), None if absent."""
    names = ", ".join(found) or "none"
    if name is None:
        if len(found) == 1:
            return next(iter(found.values()))
        header.problem(
            (key,),
            f"{path.name} holds the matrices {names}: name one",
            hint=(f'"{key}": {{"file": "{path.name}", "matrix": "NAME"}}'),
        )
        return None
    if name.upper() not in found:
        header.problem((key, "matrix"), f"{path.name} has no matrix {name} (it holds {names})")
        return None
    return found[name.upper()]


def op4_source(header: Header) -> RawModel | None:
    """`stiffness` and `mass` matrices of OP4 files, `nodes` (and `dofs`) tables."""
    files: dict[Path, dict[str, Op4Matrix]] = {}
    matrices = []
    for key in MATRICES:
        path, name = _matrix_ref(header, key)
        if path is None:
            continue
        if path not in files:
            try:
                files[path] = read_op4(path)
            except (FileFormatError, OSError) as error:
                header.in_file(path, str(error), line=getattr(error, "line", 0))
                continue
        picked = _pick(header, key, path, files[path], name)
        if picked is not None:
            matrices.append((picked.matrix, path))
    table, dofs, read = _node_table(header)
    if header.errors or table is None or len(matrices) != 2:
        return None
    return _raw(matrices, [*files, *read], table, dofs)


def _dmig_matrix(matrix: DmigMatrix, index: dict[tuple[int, int], int]) -> sp.csr_matrix:
    """The DMIG terms on the DOF order `index`; IFO 6 mirrored (a term given in both
    triangles must agree: FileFormatError)."""
    terms = dict(matrix.terms)
    if matrix.form == 6:
        for (row, col), value in matrix.terms.items():
            mirror = terms.get((col, row))
            if mirror is not None and row != col and abs(mirror - value) > 1e-9 * abs(value):
                raise FileFormatError(
                    f"DMIG {matrix.name}: symmetric (IFO 6) but terms {row},{col} and "
                    f"{col},{row} differ ({value:g}, {mirror:g})",
                    matrix.line,
                )
            terms[(col, row)] = value
    rows = [index[r] for r, _ in terms]
    cols = [index[c] for _, c in terms]
    n = len(index)
    return sp.csr_matrix(sp.coo_matrix((list(terms.values()), (rows, cols)), shape=(n, n)))


def dmig_source(header: Header) -> RawModel | None:
    """`stiffness` and `mass` DMIG matrices; nodes from GRID entries (or a `nodes` table),
    interface from ASET/ASET1, PARAM,WTMASS, all read from the named files and `bulk`."""
    refs = [(key, *_matrix_ref(header, key)) for key in MATRICES]
    extra = header.data.get("bulk", [])
    if not isinstance(extra, list):
        header.problem(("bulk",), "expected a list of bulk-data file names")
        extra = []
    others = [header.named_file(("bulk", i), name) for i, name in enumerate(extra)]
    paths = [p for p in [*(r[1] for r in refs), *others] if p is not None]
    if header.errors:
        return None
    try:
        bulk = read_bulk(paths)
    except FileFormatError as error:
        header.in_file(error.file or paths[0], error.message, line=error.line)
        return None
    except OSError as error:
        header.in_file(paths[0], f"cannot read: {error}")
        return None
    picked = [_pick(header, key, path, bulk.matrices, name) for key, path, name in refs if path]
    if header.errors or None in picked:
        return None
    return _dmig_model(header, bulk, refs, picked, paths)


def _dmig_model(
    header: Header, bulk: BulkData, refs: list[Any], picked: list[DmigMatrix], paths: list[Path]
) -> RawModel | None:
    dofs = sorted({d for m in picked for pair in m.terms for d in pair} | set(bulk.aset))
    index = {dof: i for i, dof in enumerate(dofs)}
    try:
        stiffness, mass = (_dmig_matrix(m, index) for m in picked)
    except FileFormatError as error:
        header.in_file(refs[0][1], error.message, line=error.line)
        return None
    grids = sorted({grid for grid, _ in dofs})
    table, _, read = _node_table(header) if "nodes" in header.data else (None, None, [])
    if table is None:
        missing = [g for g in grids if g not in bulk.grids]
        if missing:
            shown = ", ".join(map(str, missing[:10]))
            header.problem(
                ("nodes",),
                f"no GRID entry for grids {shown} of the matrices",
                hint="add the GRID entries (bulk: [...]) or a nodes table",
            )
            return None
        table = NodeTable(
            np.array(grids, dtype=np.int64),
            np.array([bulk.grids[g][0] for g in grids], dtype=float),
            {},
        )
    pairs = [(stiffness, refs[0][1]), (mass, refs[1][1])]
    interface = sorted({grid for grid, _ in bulk.aset})
    return _raw(pairs, [*paths, *read], table, dofs, interface=interface, wtmass=bulk.wtmass)
