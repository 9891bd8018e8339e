"""The JSON header of an imported flexible component: its keys with their place in the file,
the files it names (inside its folder tree) and the problems found, as diagnostics.

JSON has no positions in the standard library; a key's line and column are those of its
first occurrence as a key (`"name":`) after its parent's, which is exact for the flat
headers of docs/flexible-bodies-import.md.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.foundation.clip import describe_character, hidden_character
from loadcases.foundation.diagnostics import Diagnostic, InputError, Severity
from loadcases.foundation.limits import MAX_YAML_DEPTH, local_path_problem

__all__ = ["FORMATS", "HEADER_KEYS", "Header", "KeyPath", "load_header"]

KeyPath = tuple[str | int, ...]
FORMATS = ("npz", "matrix-market", "op4", "dmig")
HEADER_KEYS = (
    "format",
    "description",
    "units",
    "stiffness",
    "mass",
    "nodes",
    "dofs",
    "interface",
    "node_names",
    "wtmass",
    "bulk",
)
MAX_HEADER_BYTES = 10_000_000  # a header is a few lines; this refuses a matrix by mistake
_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')


def _key_text(path: KeyPath) -> str:
    """`("units", "length")` -> `units.length`; `("interface", 2)` -> `interface[2]`."""
    text = ""
    for key in path:
        text += f"[{key}]" if isinstance(key, int) else (f".{key}" if text else key)
    return text


@dataclass
class Header:
    """One header file being read: its text, data and every problem found so far."""

    path: Path
    text: str
    data: dict[str, Any]
    problems: list[Diagnostic] = field(default_factory=list)

    def where(self, path: KeyPath) -> tuple[int, int]:
        """1-based (line, column) of the key at `path` (its parent's if it is absent)."""
        start = 0
        for key in path:
            if isinstance(key, int):
                continue
            pattern = re.compile(re.escape(json.dumps(key)) + r"\s*:")
            match = pattern.search(self.text, start)
            if match is None:
                break
            start = match.start()
        if start == 0:
            return (1, 1)
        line_start = self.text.rfind("\n", 0, start) + 1
        return self.text.count("\n", 0, start) + 1, start - line_start + 1

    def problem(
        self,
        path: KeyPath,
        message: str,
        *,
        hint: str | None = None,
        severity: Severity = "error",
    ) -> None:
        """Record a problem at the key `path` of the header."""
        line, column = self.where(path)
        self.problems.append(
            Diagnostic(str(self.path), line, column, _key_text(path), message, severity, hint)
        )

    def in_file(self, path: Path | str, message: str, *, line: int = 0, key: str = "") -> None:
        """Record a problem of another file the header names (a matrix or node table)."""
        self.problems.append(Diagnostic(str(path), line, 1 if line else 0, key, message))

    def warn(self, path: KeyPath, message: str, *, hint: str | None = None) -> None:
        self.problem(path, message, hint=hint, severity="warning")

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.problems if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.problems if d.severity == "warning"]

    def stop_if_errors(self) -> None:
        """Raise InputError with every problem found if any is an error."""
        if self.errors:
            raise InputError(list(self.problems))

    def named_file(self, path: KeyPath, name: Any) -> Path | None:
        """The file `name` (relative to the header's folder, staying inside it) given at
        `path`, or None with a problem if it is not a usable file name."""
        if not isinstance(name, str) or not name.strip():
            self.problem(path, f"expected a file name, got {json.dumps(name)[:80]}")
            return None
        hidden = hidden_character(name)
        if hidden is not None:
            self.problem(path, f"{describe_character(hidden)} in a file name")
            return None
        folder = self.path.parent
        reason = local_path_problem(name.strip(), folder, "the header file")
        if reason is not None:
            self.problem(path, reason)
            return None
        found = folder / name.strip()
        if not found.is_file():
            self.problem(path, f"file not found: {found}")
            return None
        return found


def load_header(path: Path) -> Header:
    """The header at `path` read as a JSON object with only known keys and a known
    `format`; InputError (naming file, line, column and key) otherwise."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_HEADER_BYTES:
            raise _error(path, f"larger than {MAX_HEADER_BYTES:,} bytes: not a header")
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as error:
        raise _error(path, f"cannot read the header: {error}") from None
    deep = _too_deep(text)
    if deep is not None:
        line, column = deep
        raise _error(path, f"nested more than {MAX_YAML_DEPTH} levels deep", line, column)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise _error(path, f"not valid JSON: {error.msg}", error.lineno, error.colno) from None
    if not isinstance(data, dict):
        raise _error(path, "expected a JSON object (keys format, units, ...)", 1, 1)
    header = Header(path, text, data)
    for key in data:
        if key not in HEADER_KEYS:
            header.problem((key,), f"unknown key '{key}'", hint=f"keys: {', '.join(HEADER_KEYS)}")
    kind = data.get("format")
    if kind not in FORMATS:
        got = "missing" if kind is None else f"got {json.dumps(kind)}"
        header.problem(("format",), f"format: one of {', '.join(FORMATS)} ({got})")
    header.stop_if_errors()
    return header


def _too_deep(text: str) -> tuple[int, int] | None:
    """(line, column) where the JSON text opens its (MAX_YAML_DEPTH + 1)th nested level,
    or None: checked before the parser, whose recursion it would exhaust."""
    blanked = _STRING.sub(lambda m: '""'.ljust(len(m.group(0))), text)
    opens = np.frombuffer(blanked.encode("utf-32-le"), dtype=np.uint32)
    steps = np.isin(opens, (ord("["), ord("{"))).astype(np.int64)
    steps -= np.isin(opens, (ord("]"), ord("}")))
    deep = np.flatnonzero(np.cumsum(steps) > MAX_YAML_DEPTH)
    if deep.size == 0:
        return None
    at = int(deep[0])
    line_start = text.rfind("\n", 0, at) + 1
    return text.count("\n", 0, at) + 1, at - line_start + 1


def _error(path: Path, message: str, line: int = 0, column: int = 0) -> InputError:
    return InputError([Diagnostic(str(path), line, column, "", message)])
