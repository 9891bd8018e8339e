"""Matrix Market files (https://math.nist.gov/MatrixMarket/formats.html) of real matrices:
`coordinate` (sparse: `I J VALUE` a line) or `array` (dense, column by column), of field
`real`, `double` or `integer`, symmetry `general`, `symmetric` or `skew-symmetric`. Complex,
pattern and hermitian matrices are refused (stiffness and mass are real numbers).

The size line is checked against the input limits and against what the rest of the file
can hold before anything is allocated; each entry that cannot be read is an error naming
its line."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.bounds import file_size_problem, shape_limit_problem, terms_problem
from loadcases.flexible.values import FileFormatError

__all__ = ["read_matrix_market"]

_FIELDS = ("real", "double", "integer")
_SYMMETRIES = ("general", "symmetric", "skew-symmetric")
_INT64 = 2**63 - 1


def _banner(line: str) -> tuple[str, str, str]:
    """(layout, field, symmetry) of the `%%MatrixMarket matrix ...` first line."""
    words = line.lower().split()
    if len(words) != 5 or words[0] != "%%matrixmarket" or words[1] != "matrix":
        raise FileFormatError(
            "expected '%%MatrixMarket matrix coordinate|array real|integer general|symmetric'",
            1,
        )
    layout, field, symmetry = words[2:]
    if layout not in ("coordinate", "array"):
        raise FileFormatError(f"layout '{layout}': expected coordinate or array", 1)
    if field not in _FIELDS:
        raise FileFormatError(
            f"field '{field}': expected real or integer (stiffness and mass are real numbers)", 1
        )
    if symmetry not in _SYMMETRIES:
        raise FileFormatError(
            f"symmetry '{symmetry}': expected general, symmetric or skew-symmetric", 1
        )
    return layout, field, symmetry


def _number(text: str, integer: bool, line: int) -> float:
    """A finite entry; integers within int64 for the integer field."""
    try:
        value = int(text) if integer else float(text)
    except ValueError:
        kind = "an integer" if integer else "a real number"
        raise FileFormatError(f"expected {kind}, got '{text[:40]}'", line) from None
    if integer and abs(value) > _INT64:
        raise FileFormatError(f"integer '{text[:40]}' beyond the 64-bit range", line)
    if not math.isfinite(value):
        raise FileFormatError(f"expected a finite number, got '{text[:40]}'", line)
    return float(value)


def _index(text: str, size: int, what: str, line: int) -> int:
    """A 1-based row or column index, returned 0-based."""
    if not (text.isascii() and text.isdigit()) or not 1 <= int(text) <= size:
        raise FileFormatError(f"{what} '{text[:40]}': expected 1-{size}", line)
    return int(text) - 1


def read_matrix_market(path: Path) -> sp.csr_matrix:
    """The real matrix of a Matrix Market file; FileFormatError (with its line) if the
    file is not one, declares more than the limits or its own length allow, or holds a
    complex, non-finite or malformed entry."""
    too_large = file_size_problem(path)
    if too_large is not None:
        raise FileFormatError(too_large)
    try:
        lines = Path(path).read_text(encoding="ascii").splitlines()
    except UnicodeDecodeError:
        raise FileFormatError("not ASCII text: not a Matrix Market file") from None
    if not lines:
        raise FileFormatError("empty file: not a Matrix Market file")
    layout, field, symmetry = _banner(lines[0])
    body = [
        (number, line.split())
        for number, line in enumerate(lines[1:], start=2)
        if line.strip() and not line.lstrip().startswith("%")
    ]
    if not body:
        raise FileFormatError("no size line", len(lines))
    number, size = body[0]
    wanted = 3 if layout == "coordinate" else 2
    if len(size) != wanted or not all(s.isascii() and s.isdigit() for s in size):
        raise FileFormatError(f"size line: expected {wanted} non-negative integers", number)
    rows, cols = int(size[0]), int(size[1])
    problem = shape_limit_problem(rows, cols)
    declared = int(size[2]) if layout == "coordinate" else _array_values(rows, cols, symmetry)
    if problem is None:
        what = "entries" if layout == "coordinate" else "values"
        problem = terms_problem(declared, len(body) - 1, what)
    if problem is not None:
        raise FileFormatError(f"size line: {problem}", number)
    entries = body[1:]
    if len(entries) != declared:
        raise FileFormatError(
            f"{declared} entries declared on the size line, {len(entries)} given", number
        )
    integer = field == "integer"
    if layout == "array":
        return _array(entries, rows, cols, integer, symmetry)
    return _coordinate(entries, rows, cols, integer, symmetry)


def _coordinate(entries: list, rows: int, cols: int, integer: bool, symmetry: str) -> sp.csr_matrix:
    i, j, v = (np.empty(len(entries), dtype=t) for t in (np.int64, np.int64, float))
    for k, (line, cells) in enumerate(entries):
        if len(cells) != 3:
            raise FileFormatError(f"expected 'row column value', got {len(cells)} items", line)
        i[k] = _index(cells[0], rows, "row", line)
        j[k] = _index(cells[1], cols, "column", line)
        v[k] = _number(cells[2], integer, line)
    return _coordinate_matrix(i, j, v, rows, cols, symmetry)


def _array_values(rows: int, cols: int, symmetry: str) -> int:
    """Values of an array: all, or the lower triangle column by column (with its diagonal
    when symmetric, without when skew-symmetric)."""
    if symmetry == "general":
        return rows * cols
    n = min(rows, cols)
    return n * (n + 1) // 2 if symmetry == "symmetric" else n * (n - 1) // 2


def _array(entries: list, rows: int, cols: int, integer: bool, symmetry: str) -> sp.csr_matrix:
    values = np.empty(len(entries))
    for k, (line, cells) in enumerate(entries):
        if len(cells) != 1:
            raise FileFormatError(f"expected one value, got {len(cells)} items", line)
        values[k] = _number(cells[0], integer, line)
    if symmetry == "general":
        return sp.csr_matrix(values.reshape((cols, rows)).T)
    if rows != cols:
        raise FileFormatError(f"a {symmetry} array of {rows} x {cols}: expected square", 2)
    i, j = np.tril_indices(rows, 0 if symmetry == "symmetric" else -1)
    order = np.lexsort((i, j))  # column by column
    return _coordinate_matrix(i[order], j[order], values, rows, cols, symmetry)


def _coordinate_matrix(
    i: np.ndarray, j: np.ndarray, v: np.ndarray, rows: int, cols: int, symmetry: str
) -> sp.csr_matrix:
    """The CSR matrix of triplets, the other triangle added when (skew-)symmetric."""
    if symmetry != "general":
        off = i != j
        sign = 1.0 if symmetry == "symmetric" else -1.0
        i, j, v = np.r_[i, j[off]], np.r_[j, i[off]], np.r_[v, sign * v[off]]
    return sp.csr_matrix(sp.coo_matrix((v, (i, j)), shape=(rows, cols)))
