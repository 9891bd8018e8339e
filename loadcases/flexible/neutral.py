"""The neutral flexible-component format of loads: `NAME.npz` (arrays) beside `NAME.json`
(header: format "npz", units, interface, node names, description). See
docs/flexible-bodies-import.md.

`NAME.npz` holds `node_ids` (n,) int, `coordinates` (n, 3) in the header's length unit,
`dof_map` (ndof, 2) int (node id, component 1-6 = ux uy uz rx ry rz), and for `stiffness`
and `mass` the CSR arrays `<m>_data`, `<m>_indices`, `<m>_indptr`, `<m>_shape`.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.bounds import file_size_problem, shape_limit_problem, terms_problem
from loadcases.flexible.header import Header
from loadcases.flexible.raw import RawModel
from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.foundation.limits import MAX_FE_FILE_BYTES, local_path_problem
from mechlib.flexible.fe_model import FEModel

__all__ = ["MATRICES", "npz_source", "write_neutral"]

MATRICES = ("stiffness", "mass")
_CSR_PARTS = ("data", "indices", "indptr", "shape")
_SI_UNITS = {"length": "m", "mass": "kg", "force": "N", "time": "s"}


def _csr(arrays: Any, name: str) -> sp.csr_matrix:
    """The CSR matrix `name` of the npz arrays; ValueError saying what is wrong."""
    missing = [f"{name}_{part}" for part in _CSR_PARTS if f"{name}_{part}" not in arrays]
    if missing:
        raise ValueError(f"missing arrays {', '.join(missing)}")
    given = np.asarray(arrays[f"{name}_shape"])
    if given.dtype.kind not in "iu" or given.size != 2:
        raise ValueError(f"{name}_shape: expected 2 integers, got {given.dtype} {given.shape}")
    shape = (int(given.ravel()[0]), int(given.ravel()[1]))
    problem = shape_limit_problem(*shape)
    if problem is not None:
        raise ValueError(f"{name}_shape: {problem}")
    data = np.asarray(arrays[f"{name}_data"])
    too_many = terms_problem(data.size, data.size, "terms")
    if too_many is not None:
        raise ValueError(f"{name}_data: {too_many}")
    if data.dtype.kind not in "fiu":
        kind = "complex numbers" if data.dtype.kind == "c" else f"type {data.dtype}"
        raise ValueError(f"{name}_data: {kind}: expected real numbers")
    indices, indptr = (np.asarray(arrays[f"{name}_{part}"]) for part in ("indices", "indptr"))
    for part, index in (("indices", indices), ("indptr", indptr)):
        if index.ndim != 1 or index.dtype.kind not in "iu":  # scipy would cast 2.5 or 2+1j
            raise ValueError(
                f"{name}_{part}: expected integers (n,), got {index.dtype} {index.shape}"
            )
    matrix = sp.csr_matrix((data.astype(float), indices, indptr), shape=shape)
    matrix.check_format(full_check=True)
    return matrix


def _node_arrays(arrays: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """node_ids, coordinates and dof_map checked for shape and type; ValueError."""
    for key in ("node_ids", "coordinates", "dof_map"):
        if key not in arrays:
            raise ValueError(f"missing array {key}")
    ids, xyz, dofs = (np.asarray(arrays[k]) for k in ("node_ids", "coordinates", "dof_map"))
    if ids.ndim != 1 or ids.dtype.kind not in "iu":
        raise ValueError(f"node_ids: expected integers (n,), got {ids.dtype} {ids.shape}")
    if xyz.shape != (len(ids), 3) or xyz.dtype.kind not in "fiu":
        raise ValueError(
            f"coordinates: expected real numbers ({len(ids)}, 3), got {xyz.dtype} {xyz.shape}"
        )
    if dofs.ndim != 2 or dofs.shape[1] != 2 or dofs.dtype.kind not in "iu":
        raise ValueError(f"dof_map: expected integers (ndof, 2), got {dofs.dtype} {dofs.shape}")
    return ids.astype(np.int64), xyz.astype(float), dofs.astype(np.int64)


def _check_members(path: Path) -> None:
    """The npz file and each array it holds within MAX_FE_FILE_BYTES once unpacked, read
    from the zip directory before anything is unpacked; ValueError otherwise."""
    too_large = file_size_problem(path)
    if too_large is not None:
        raise ValueError(too_large)
    with zipfile.ZipFile(path) as archive:
        unpacked = sum(member.file_size for member in archive.infolist())
    if unpacked > MAX_FE_FILE_BYTES:
        raise ValueError(
            f"its arrays unpack to {unpacked:,} bytes: at most {MAX_FE_FILE_BYTES:,} "
            "(the input limit of one file)"
        )


def npz_source(header: Header) -> RawModel | None:
    """The arrays of `NAME.npz` beside the header `NAME.json`; None with a problem naming
    the npz file if they cannot be read."""
    path = header.path.with_suffix(".npz")
    outside = local_path_problem(path.name, header.path.parent, "the header file")
    if outside is not None:
        header.problem(("format",), f"format npz: the arrays file {outside}")
        return None
    if not path.is_file():
        header.problem(("format",), f"format npz: the arrays file {path} is missing")
        return None
    try:
        _check_members(path)
        with np.load(path, allow_pickle=False) as arrays:
            ids, xyz, dofs = _node_arrays(arrays)
            stiffness, mass = (_csr(arrays, name) for name in MATRICES)
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as error:
        header.in_file(path, f"not a loads flexible-component npz: {error}")
        return None
    return RawModel(stiffness, mass, dofs, ids, xyz, path, path, files=[path])


def write_neutral(
    path: Path,
    model: FEModel,
    *,
    description: str = "",
    node_names: dict[str, int] | None = None,
) -> tuple[Path, Path]:
    """Write `model` (SI) as `NAME.json` + `NAME.npz` (each whole or not at all); `path` is
    NAME.json (or NAME); `node_names` maps names to node indices. Returns both paths."""
    header_path = Path(path).with_suffix(".json")
    arrays: dict[str, Any] = {
        "node_ids": np.asarray(model.node_ids, dtype=np.int64),
        "coordinates": np.asarray(model.coordinates, dtype=float),
        "dof_map": np.column_stack(
            [model.node_ids[model.dof_map[:, 0]], model.dof_map[:, 1] + 1]
        ).astype(np.int64),
    }
    for name, matrix in zip(MATRICES, (model.stiffness, model.mass)):
        csr = sp.csr_matrix(matrix, dtype=float)
        csr.sort_indices()
        for part in _CSR_PARTS:
            arrays[f"{name}_{part}"] = np.asarray(getattr(csr, part), dtype=None)
    arrays_path = header_path.with_suffix(".npz")
    with atomic_path(arrays_path) as tmp, open(tmp, "wb") as stream:
        np.savez_compressed(stream, **arrays)
    header = {
        "format": "npz",
        "description": description,
        "units": _SI_UNITS,
        "interface": [int(model.node_ids[i]) for i in model.interface],
        "node_names": {k: int(model.node_ids[i]) for k, i in (node_names or {}).items()},
    }
    atomic_write_text(header_path, json.dumps(header, indent=2) + "\n")
    return header_path, arrays_path
