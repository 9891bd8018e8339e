"""NASTRAN OUTPUT4 (OP4) matrices, ASCII and binary, dense and sparse (non-BIGMAT and BIGMAT
strings): real single and double precision. Complex matrices are refused (stiffness and
mass are real).

Layout (as NASTRAN's OUTPUT4 writes it; checked against NASTRAN-written samples):
- a matrix header `NCOL NROW FORM TYPE NAME` (ASCII: 4I8, A8, then the number format such
  as `1P,3E23.16`); NROW < 0 marks BIGMAT; TYPE 1 real single, 2 real double;
- one record per non-zero column: `ICOL IROW NW` then the values. IROW > 0: dense, the
  values of rows IROW, IROW+1, ...; IROW = 0: sparse, strings of consecutive rows, each
  headed by one word `IS = IROW + 65536 (L + 1)` (non-BIGMAT) or two words `L + 1, IROW`
  (BIGMAT), L the number of words of its values (a double takes two 4-byte words);
- a last record with ICOL = NCOL + 1 and one dummy value.
Binary files are Fortran sequential records (4-byte length before and after each), of
either byte order; 8-byte-word files (record length 48 for the header) are read too.
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.bounds import file_size_problem, shape_limit_problem, terms_problem
from loadcases.flexible.values import FileFormatError, nastran_real

__all__ = ["Op4Matrix", "read_op4"]

_FORMAT = re.compile(r"(\d+)\s*[EDGF]\s*(\d+)\.(\d+)", re.IGNORECASE)
_INTEGER = re.compile(r"^\s*[-+]?\d+$")
_INTEGERS = re.compile(r"^\s*[-+]?\d+(\s+[-+]?\d+)*\s*$")
_DUMMY = re.compile(r"^[\s\d.EeDd+-]*[.EeDd][\s\d.EeDd+-]*$")  # real numbers only
_REAL_TYPES = {1: "single", 2: "double"}


@dataclass(frozen=True)
class Op4Matrix:
    """One matrix of an OP4 file: its NASTRAN form (1 square, 2 rectangular, 6 symmetric...)
    and its terms."""

    name: str
    form: int
    matrix: sp.csr_matrix


class _Terms:
    """Row, column and value lists of one matrix being read."""

    def __init__(self, name: str, rows: int, cols: int) -> None:
        self.name, self.shape = name, (rows, cols)
        self.rows: list[np.ndarray] = []
        self.cols: list[np.ndarray] = []
        self.values: list[np.ndarray] = []

    def add(self, first_row: int, col: int, values: np.ndarray, where: str) -> None:
        """Values of rows first_row, first_row+1, ... (1-based) of column col (1-based)."""
        if not 1 <= col <= self.shape[1]:
            raise FileFormatError(
                f"{where}: matrix {self.name}: column {col} outside its {self.shape[1]} columns"
            )
        if first_row < 1 or first_row - 1 + len(values) > self.shape[0]:
            raise FileFormatError(
                f"{where}: matrix {self.name}: rows {first_row}-{first_row + len(values) - 1} "
                f"of column {col} outside its {self.shape[0]} rows"
            )
        self.rows.append(np.arange(first_row - 1, first_row - 1 + len(values)))
        self.cols.append(np.full(len(values), col - 1))
        self.values.append(np.asarray(values, dtype=float))

    def matrix(self) -> sp.csr_matrix:
        if not self.values:
            return sp.csr_matrix(self.shape)
        data = (np.concatenate(self.values), (np.concatenate(self.rows), np.concatenate(self.cols)))
        return sp.csr_matrix(sp.coo_matrix(data, shape=self.shape))


def read_op4(path: Path) -> dict[str, Op4Matrix]:
    """Every matrix of the OP4 file by its upper-case name (the first of a repeated name);
    FileFormatError (with the line or byte where it went wrong) if the file is not one."""
    too_large = file_size_problem(path)
    if too_large is not None:
        raise FileFormatError(too_large)
    data = Path(path).read_bytes()
    if len(data) >= 4 and _binary_layout(data) is not None:
        return _read_binary(data)
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise FileFormatError("neither an ASCII nor a binary OP4 file") from None
    return _read_ascii(text.splitlines())


# ---- ASCII -------------------------------------------------------------------------------


def _ints(line: str, count: int, number: int) -> list[int]:
    """The first `count` integers of an integer line (fixed I8 fields or blank-separated)."""
    parts = line.split()
    if len(parts) < count and _INTEGERS.match(line):  # I8 fields that fill their width
        parts = [line[k : k + 8] for k in range(0, 8 * count, 8)]
        parts = parts if all(_INTEGER.match(p) for p in parts) else line.split()
    if len(parts) < count or not _INTEGERS.match(line):
        raise FileFormatError(f"expected {count} integers, got '{line.strip()[:60]}'", number)
    return [int(p) for p in parts[:count]]


class _AsciiLines:
    """The lines of an ASCII OP4 file, read one after another."""

    def __init__(self, lines: list[str]) -> None:
        self.lines, self.at = lines, 0
        # characters from line i to the end: how many values the rest can hold (a line
        # holds ceil(len / width) cells at most)
        self.after = np.cumsum([len(line) for line in reversed(lines)])[::-1].tolist() + [0]

    def next(self) -> tuple[int, str]:
        while self.at < len(self.lines) and not self.lines[self.at].strip():
            self.at += 1
        if self.at >= len(self.lines):
            raise FileFormatError("file ends inside a matrix", len(self.lines))
        self.at += 1
        return self.at, self.lines[self.at - 1]

    def done(self) -> bool:
        return all(not line.strip() for line in self.lines[self.at :])

    def skip_dummy(self) -> None:
        """Pass the dummy value after the last column record, when there is one (a line
        that is neither integers nor the next matrix header, whose name has letters)."""
        at = self.at
        while at < len(self.lines) and not self.lines[at].strip():
            at += 1
        if at < len(self.lines) and _DUMMY.match(self.lines[at]):
            self.at = at + 1

    def values(self, count: int, width: int) -> np.ndarray:
        """`count` fixed-width numbers from the following lines (at most what they can
        hold, checked first)."""
        room = self.after[self.at] // width + len(self.lines) - self.at
        problem = terms_problem(count, room, "values")
        if problem is not None:
            raise FileFormatError(problem, self.at)
        found: list[float] = []
        while len(found) < count:
            number, line = self.next()
            if _INTEGERS.match(line):
                raise FileFormatError(f"expected {count - len(found)} more values", number)
            line = line.rstrip()
            for start in range(0, len(line), width):
                cell = line[start : start + width]
                if cell.strip():
                    found.append(nastran_real(cell, number))
        if len(found) != count:
            raise FileFormatError(f"expected {count} values, got {len(found)}", self.at)
        return np.array(found)


def _ascii_header(number: int, line: str) -> tuple[int, int, int, int, str, int]:
    """NCOL, NROW, FORM, TYPE, NAME and the width of a number, from a matrix header line."""
    try:
        ncol, nrow, form, kind = (int(line[i : i + 8]) for i in range(0, 32, 8))
    except ValueError:
        raise FileFormatError(
            f"expected a matrix header (4I8, name, format), got '{line.strip()[:60]}'", number
        ) from None
    name = line[32:40].strip().upper()
    match = _FORMAT.search(line[40:])
    if match is None or int(match.group(2)) < 1:
        raise FileFormatError(
            f"matrix {name}: no usable number format (like 1P,3E23.16: a width of at least 1)",
            number,
        )
    _check_sizes(name, ncol, nrow, number)
    return ncol, nrow, form, kind, name, int(match.group(2))


def _read_ascii(lines: list[str]) -> dict[str, Op4Matrix]:
    source = _AsciiLines(lines)
    found: dict[str, Op4Matrix] = {}
    while not source.done():
        number, line = source.next()
        ncol, nrow, form, kind, name, width = _ascii_header(number, line)
        _check_type(name, kind, number)
        terms = _Terms(name, abs(nrow), ncol)
        words = 1 if kind == 1 else 2
        while True:
            number, line = source.next()
            col, row, nw = _ints(line, 3, number)
            if col > ncol:
                source.skip_dummy()
                break
            if row > 0:  # dense: NW counts the values
                terms.add(row, col, source.values(nw, width), f"line {number}")
                continue
            bigmat = nrow < 0 or abs(nrow) >= 65536
            while nw > 0:
                number, line = source.next()
                first, size, used = _string_header(line, number, bigmat, words)
                terms.add(first, col, source.values(size // words, width), f"line {number}")
                nw -= used
        found.setdefault(name, Op4Matrix(name, form, terms.matrix()))
    return found


def _string_header(line: str, number: int, bigmat: bool, words: int) -> tuple[int, int, int]:
    """(first row, words of values, words used with the header) of a sparse string."""
    if bigmat:
        length, first = _ints(line, 2, number)
        size, used = length - 1, length + 1
    else:
        (packed,) = _ints(line, 1, number)
        size = (packed >> 16) - 1
        first, used = packed - ((size + 1) << 16), size + 1
    if size < words or size % words:
        raise FileFormatError(
            f"a sparse string of {size} words: expected a positive multiple of {words} "
            "(the words of one value)",
            number,
        )
    return first, size, used


def _check_sizes(name: str, ncol: int, nrow: int, where: int | str) -> None:
    """NCOL and |NROW| of a matrix header within the input limits (before any allocation);
    `where` a line number (ASCII) or a byte text (binary)."""
    problem = shape_limit_problem(abs(nrow), ncol)
    if problem is None:
        return
    if ncol < 1:
        problem = f"NCOL {ncol}: expected a positive number of columns"
    at = where if isinstance(where, int) else 0
    prefix = "" if isinstance(where, int) else f"{where}: "
    raise FileFormatError(f"{prefix}matrix {name}: {problem}", at)


def _check_type(name: str, kind: int, where: int) -> None:
    if kind not in _REAL_TYPES:
        what = "complex" if kind in (3, 4) else f"of unknown type {kind}"
        raise FileFormatError(f"matrix {name} is {what}: stiffness and mass are real", where)


# ---- binary ------------------------------------------------------------------------------


def _binary_layout(data: bytes) -> tuple[str, int] | None:
    """(byte order, integer size) if the file starts like a binary OP4 header record."""
    for order in "<>":
        (first,) = struct.unpack(order + "i", data[:4])
        if first in (24, 48):
            return order, 4 if first == 24 else 8
    return None


class _Records:
    """The Fortran records of a binary file."""

    def __init__(self, data: bytes, order: str) -> None:
        self.data, self.order, self.at, self.start = data, order, 0, 0

    def next(self, least: int = 0) -> bytes:
        """The next record (at least `least` bytes long); its offset in `self.start`."""
        start = self.start = self.at
        if start + 4 > len(self.data):
            raise FileFormatError(f"file ends inside a matrix (byte {start})")
        (size,) = struct.unpack(self.order + "i", self.data[start : start + 4])
        end = start + 4 + size
        if size < 0 or end + 4 > len(self.data):
            raise FileFormatError(f"record at byte {start}: truncated or not an OP4 file")
        (trailer,) = struct.unpack(self.order + "i", self.data[end : end + 4])
        if trailer != size:
            raise FileFormatError(f"record at byte {start}: length markers disagree")
        if size < least:
            raise FileFormatError(
                f"record at byte {start}: {size} bytes, expected at least {least}"
            )
        self.at = end + 4
        return self.data[start + 4 : end]

    def done(self) -> bool:
        return self.at >= len(self.data)


def _read_binary(data: bytes) -> dict[str, Op4Matrix]:
    layout = _binary_layout(data)
    assert layout is not None
    order, isize = layout
    letter = "i" if isize == 4 else "q"
    records = _Records(data, order)
    found: dict[str, Op4Matrix] = {}
    while not records.done():
        head = records.next(4 * isize)
        ncol, nrow, form, kind = struct.unpack(f"{order}4{letter}", head[: 4 * isize])
        name = head[4 * isize :].decode("ascii", "replace").strip(" \0").upper()
        where = f"record at byte {records.start}"
        try:
            _check_type(name, kind, 0)
        except FileFormatError as error:
            raise FileFormatError(f"{where}: {error.message}") from None
        _check_sizes(name, ncol, nrow, where)
        real = np.dtype(order + ("f4" if kind == 1 and isize == 4 else "f8"))
        words = real.itemsize // isize  # words of one value
        terms = _Terms(name, abs(nrow), ncol)
        bigmat = nrow < 0 or abs(nrow) >= 65536
        while True:
            body = records.next(3 * isize)
            col, row, nw = struct.unpack(f"{order}3{letter}", body[: 3 * isize])
            if col > ncol:
                break
            rest = body[3 * isize :]
            where = f"record at byte {records.start}"
            if row > 0:
                if nw < 0 or nw // words * real.itemsize > len(rest):
                    raise FileFormatError(
                        f"{where}: column {col} of {nw} words, but the record holds "
                        f"{len(rest) // isize} words of values"
                    )
                terms.add(row, col, np.frombuffer(rest, real, nw // words), where)
            else:
                _binary_strings(terms, rest, col, (order, isize, real, words, bigmat), where)
        found.setdefault(name, Op4Matrix(name, form, terms.matrix()))
    return found


def _binary_strings(
    terms: _Terms,
    rest: bytes,
    col: int,
    layout: tuple[str, int, np.dtype, int, bool],
    where: str,
) -> None:
    """The sparse strings of one binary column record (`where` its byte offset)."""
    order, isize, real, words, bigmat = layout
    letter = "i" if isize == 4 else "q"
    at = 0
    while at < len(rest):
        if at + (2 if bigmat else 1) * isize > len(rest):
            raise FileFormatError(f"{where}: column {col}: a string header runs past the record")
        if bigmat:
            length, first = struct.unpack(f"{order}2{letter}", rest[at : at + 2 * isize])
            size, at = length - 1, at + 2 * isize
        else:
            (packed,) = struct.unpack(f"{order}{letter}", rest[at : at + isize])
            size = (packed >> 16) - 1
            first, at = packed - ((size + 1) << 16), at + isize
        count = size // words
        if size < 0 or at + count * real.itemsize > len(rest):
            raise FileFormatError(
                f"{where}: matrix {terms.name}: column {col}: a string runs past its record"
            )
        terms.add(first, col, np.frombuffer(rest, real, count, at), where)
        at += count * real.itemsize
