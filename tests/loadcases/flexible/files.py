"""Hand-made import files for the tests: OP4 (ASCII and binary; dense, sparse and BIGMAT
layouts as NASTRAN's OUTPUT4 writes them), DMIG bulk data (small, large and free field),
node tables and headers. Written here from the format descriptions, independently of the
readers."""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any

import numpy as np


def header(folder: Path, name: str = "part", **keys: Any) -> Path:
    path = folder / f"{name}.json"
    path.write_text(json.dumps(keys, indent=2), encoding="utf-8")
    return path


def nastran_header(folder: Path, kind: str, file: str, names: tuple[str, str], **keys: Any) -> Path:
    """A header of format `kind` (op4, dmig) whose stiffness and mass are the matrices
    `names` of one file."""
    refs = [{"file": file, "matrix": name} for name in names]
    return header(folder, format=kind, stiffness=refs[0], mass=refs[1], **keys)


def nodes_csv(
    folder: Path, ids: list[int], x: np.ndarray, names: dict[int, str] | None = None
) -> Path:
    path = folder / "nodes.csv"
    rows = ["id,x,y,z,name"] + [
        f"{n},{float(xi)!r},0,0,{(names or {}).get(n, '')}" for n, xi in zip(ids, x)
    ]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def _strings(column: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """(first row 1-based, values) of each run of consecutive non-zero rows."""
    rows = np.flatnonzero(column)
    runs: list[tuple[int, np.ndarray]] = []
    for row in rows:
        if runs and runs[-1][0] + len(runs[-1][1]) - 1 == row:
            runs[-1] = (runs[-1][0], np.append(runs[-1][1], column[row]))
        else:
            runs.append((row + 1, np.array([column[row]])))
    return runs


def _columns(matrix: np.ndarray) -> Any:
    """(index, column, first non-zero row 0-based, values from it to the last non-zero)
    of every column with a non-zero term."""
    for c in range(matrix.shape[1]):
        nz = np.flatnonzero(matrix[:, c])
        if nz.size:
            yield c, matrix[:, c], nz[0], matrix[nz[0] : nz[-1] + 1, c]


def _ascii_values(values: np.ndarray, per_line: int, width: int, digits: int) -> str:
    cells = [f"{v:{width}.{digits}E}" for v in values]
    return "".join("".join(cells[i : i + per_line]) + "\n" for i in range(0, len(cells), per_line))


def op4_ascii(
    matrices: dict[str, np.ndarray], layout: str, per_line: int = 3, width: int = 23
) -> str:
    """An ASCII OP4 file of real double matrices; layout dense, sparse or bigmat."""
    digits = width - 7
    text = ""
    for name, matrix in matrices.items():
        rows, cols = matrix.shape
        nrow = -rows if layout == "bigmat" else rows
        text += f"{cols:8}{nrow:8}{6:8}{2:8}{name:8}1P,{per_line}E{width}.{digits}\n"
        for c, column, first_row, values in _columns(matrix):
            if layout == "dense":
                text += f"{c + 1:8}{first_row + 1:8}{len(values):8}\n"
                text += _ascii_values(values, per_line, width, digits)
                continue
            runs = _strings(column)
            head = 2 if layout == "bigmat" else 1
            nw = sum(head + 2 * len(v) for _, v in runs)
            text += f"{c + 1:8}{0:8}{nw:8}\n"
            for first, values in runs:
                words = 2 * len(values)
                if layout == "bigmat":
                    text += f"{words + 1:8}{first:8}\n"
                else:
                    text += f"{first + 65536 * (words + 1):12}\n"
                text += _ascii_values(values, per_line, width, digits)
        text += f"{cols + 1:8}{1:8}{1:8}\n" + _ascii_values(
            np.array([1.0]), per_line, width, digits
        )
    return text


def _record(order: str, payload: bytes) -> bytes:
    size = struct.pack(order + "i", len(payload))
    return size + payload + size


def op4_binary(matrices: dict[str, np.ndarray], layout: str, order: str = "<") -> bytes:
    """A binary OP4 file (4-byte words) of real double matrices."""
    data = b""
    for name, matrix in matrices.items():
        rows, cols = matrix.shape
        nrow = -rows if layout == "bigmat" else rows
        data += _record(order, struct.pack(order + "4i8s", cols, nrow, 6, 2, f"{name:8}".encode()))
        for c, column, first_row, values in _columns(matrix):
            if layout == "dense":
                body = struct.pack(order + "3i", c + 1, first_row + 1, 2 * len(values))
                data += _record(order, body + values.astype(order + "f8").tobytes())
                continue
            body = b""
            for first, values in _strings(column):
                words = 2 * len(values)
                if layout == "bigmat":
                    body += struct.pack(order + "2i", words + 1, first)
                else:
                    body += struct.pack(order + "i", first + 65536 * (words + 1))
                body += values.astype(order + "f8").tobytes()
            data += _record(order, struct.pack(order + "3i", c + 1, 0, len(body) // 4) + body)
        data += _record(
            order, struct.pack(order + "3i", cols + 1, 1, 2) + struct.pack(order + "d", 1.0)
        )
    return data


def _nastran(value: float, width: int = 8) -> str:
    """A real in at most `width` characters, exact for the test's short numbers (1.+6)."""
    text = repr(float(value))
    if len(text) <= width:
        return text
    mantissa, exponent = f"{value:.6e}".split("e")
    return f"{mantissa.rstrip('0')}{int(exponent):+d}"


def _line(fields: list[str], style: str) -> str:
    if style == "free":
        return ",".join(fields) + "\n"
    return "".join(f"{f:<8}" for f in fields).rstrip() + "\n"


def dmig(name: str, matrix: np.ndarray, grids: list[int], style: str) -> str:
    """DMIG entries (IFO 6, upper triangle, real double) of a matrix on six DOF per grid;
    style small, large or free."""
    dofs = [(g, c) for g in grids for c in range(1, 7)]
    if style == "large":
        lines = [
            f"{'DMIG*':8}{name:16}{'0':>16}{'6':>16}{'2':>16}\n",
            f"{'*':8}{'0':>16}{'':16}{'':16}{len(dofs):>16}\n",
        ]
    else:
        lines = [_line(["DMIG", name, "0", "6", "2", "0", "", "", str(len(dofs))], style)]
    for j, (gj, cj) in enumerate(dofs):
        terms = [(dofs[i], matrix[i, j]) for i in range(j + 1) if matrix[i, j] != 0.0]
        if not terms:
            continue
        if style == "large":
            lines.append(f"{'DMIG*':8}{name:16}{gj:>16}{cj:>16}\n")
            lines += [f"{'*':8}{g:>16}{c:>16}{_nastran(v, 16):>16}\n" for (g, c), v in terms]
            continue
        cells = [[str(g), str(c), _nastran(v), ""] for (g, c), v in terms]
        lines.append(_line(["DMIG", name, str(gj), str(cj), "", *cells[0]], style))
        for k in range(1, len(cells), 2):
            lines.append(
                _line(["+", *(field for cell in cells[k : k + 2] for field in cell)], style)
            )
    return "".join(lines)
