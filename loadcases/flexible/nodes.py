"""Node and DOF tables of an import (Matrix Market, OP4): small CSV files with a header row.

Nodes: columns `id, x, y, z` and optionally `name` (coordinates in the header's length
unit). DOFs: columns `node, component` (node id, component 1-6 = ux uy uz rx ry rz), one row
per matrix row in matrix order; without a DOF table every node carries its six DOF in node
order (NASTRAN's a-set order for whole grids sorted by id).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from loadcases.flexible.bounds import node_id_problem
from loadcases.flexible.header import Header
from loadcases.foundation.clip import describe_character, hidden_character

__all__ = ["NodeTable", "read_dofs", "read_nodes", "six_per_node"]

MAX_TABLE_BYTES = 200_000_000
_NODE_COLUMNS = ("id", "x", "y", "z")


@dataclass(frozen=True)
class NodeTable:
    """Node ids, coordinates (file length unit) and the names given in the table."""

    ids: np.ndarray
    coordinates: np.ndarray
    names: dict[str, int]  # name -> node id


def _rows(header: Header, path: Path) -> list[tuple[int, list[str]]] | None:
    """(line, cells) of every non-empty row of a CSV file, the header row first."""
    if path.stat().st_size > MAX_TABLE_BYTES:
        header.in_file(path, f"larger than {MAX_TABLE_BYTES:,} bytes")
        return None
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as error:
        header.in_file(path, f"not UTF-8 text ({error.reason})")
        return None
    rows = []
    reader = csv.reader(text.splitlines())
    try:
        for number, cells in enumerate(reader, start=1):
            if cells and any(c.strip() for c in cells):
                rows.append((number, [c.strip() for c in cells]))
    except csv.Error as error:
        header.in_file(path, f"not a CSV table: {error}", line=reader.line_num)
        return None
    if not rows:
        header.in_file(path, "empty file: expected a header row")
        return None
    return rows


def _columns(
    header: Header, path: Path, cells: list[str], wanted: tuple[str, ...]
) -> dict[str, int] | None:
    index = {name.lower(): i for i, name in enumerate(cells)}
    missing = [name for name in wanted if name not in index]
    if missing:
        header.in_file(path, f"missing column(s) {', '.join(missing)} in the header row", line=1)
        return None
    return index


def _short(header: Header, path: Path, line: int, cells: list[str], index: dict[str, int]) -> bool:
    """True (with a problem) if the row has fewer cells than the header row names."""
    if len(cells) > max(index.values()):
        return False
    header.in_file(path, f"expected {max(index.values()) + 1} cells, got {len(cells)}", line=line)
    return True


def _number(
    header: Header, path: Path, line: int, text: str, column: str, integer: bool
) -> float | None:
    try:
        if not text.isascii():  # Python reads Arabic-Indic and other digits as numbers
            raise ValueError(text)
        value = int(text) if integer else float(text)
    except ValueError:
        kind = "an integer" if integer else "a number"
        header.in_file(path, f"expected {kind}, got '{text[:40]}'", line=line, key=column)
        return None
    if not math.isfinite(value):
        header.in_file(path, f"expected a finite number, got '{text[:40]}'", line=line, key=column)
        return None
    wrong = node_id_problem(value) if column in ("id", "node") else None
    if wrong is not None:
        header.in_file(path, wrong, line=line, key=column)
        return None
    return value


def read_nodes(header: Header, path: Path) -> NodeTable | None:
    """The node table at `path`; None with problems if it cannot be read whole."""
    rows = _rows(header, path)
    if rows is None:
        return None
    index = _columns(header, path, rows[0][1], _NODE_COLUMNS)
    if index is None:
        return None
    ids: list[int] = []
    xyz: list[list[float]] = []
    names: dict[str, int] = {}
    seen: dict[int, int] = {}
    for line, cells in rows[1:]:
        if _short(header, path, line, cells, index):
            continue
        node = _number(header, path, line, cells[index["id"]], "id", integer=True)
        at = [_number(header, path, line, cells[index[a]], a, integer=False) for a in "xyz"]
        if node is None or None in at:
            continue
        if int(node) in seen:
            header.in_file(
                path, f"node {int(node)} given twice (first on line {seen[int(node)]})", line=line
            )
            continue
        seen[int(node)] = line
        ids.append(int(node))
        xyz.append([float(a) for a in at if a is not None])
        name = cells[index["name"]] if "name" in index else ""
        hidden = hidden_character(name)
        if hidden is not None:
            header.in_file(
                path, f"{describe_character(hidden)} in a node name", line=line, key="name"
            )
            continue
        if name:
            names[name] = int(node)
    if not ids:
        header.in_file(path, "no node rows")
        return None
    return NodeTable(np.array(ids, dtype=np.int64), np.array(xyz, dtype=float), names)


def read_dofs(header: Header, path: Path) -> np.ndarray | None:
    """(ndof, 2) node id and component 1-6 of every matrix row, from the DOF table."""
    rows = _rows(header, path)
    if rows is None:
        return None
    index = _columns(header, path, rows[0][1], ("node", "component"))
    if index is None:
        return None
    dofs = []
    for line, cells in rows[1:]:
        if _short(header, path, line, cells, index):
            continue
        node = _number(header, path, line, cells[index["node"]], "node", integer=True)
        comp = _number(header, path, line, cells[index["component"]], "component", integer=True)
        if node is None or comp is None:
            continue
        if not 1 <= comp <= 6:
            header.in_file(
                path, f"expected a component 1-6, got {int(comp)}", line=line, key="component"
            )
            continue
        dofs.append((int(node), int(comp)))
    return np.array(dofs, dtype=np.int64).reshape(-1, 2)


def six_per_node(ids: np.ndarray) -> np.ndarray:
    """(6n, 2) node id and component 1-6: every node's six DOF, in node order."""
    return np.column_stack([np.repeat(ids, 6), np.tile(np.arange(1, 7), len(ids))])
