"""Which kind of input file a path is (mechanism, case or set): decided here, and only here."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.yamlfiles.source import load_yaml

__all__ = ["KIND_HINT", "FileKind", "file_kind", "unknown_kind"]

FileKind = Literal["mechanism", "case", "set"]
SUFFIXES: dict[str, FileKind] = {
    ".mech.yaml": "mechanism",
    ".case.yaml": "case",
    ".set.yaml": "set",
    ".mech.yml": "mechanism",
    ".case.yml": "case",
    ".set.yml": "set",
}
KIND_HINT = "name it *.mech.yaml, *.case.yaml or *.set.yaml"
_MECHANISM_KEYS = {"bodies", "joints", "points", "forces"}


def file_kind(path: str | Path) -> FileKind | None:
    """ "mechanism", "case" or "set" from the suffix; a file without one of the suffixes is
    read and told by its top-level keys (None if they do not tell). Raises InputError if such
    a file cannot be read or parsed."""
    name = str(path).lower()
    for suffix, kind in SUFFIXES.items():
        if name.endswith(suffix):
            return kind
    return _kind_of_data(load_yaml(path).data)


def _kind_of_data(data: Any) -> FileKind | None:
    if isinstance(data, dict):
        if "case" in data:
            return "case"
        if "set" in data:
            return "set"
        if _MECHANISM_KEYS & set(data):
            return "mechanism"
    return None


def unknown_kind(path: str | Path) -> Diagnostic:
    """The diagnostic of a file whose kind cannot be told."""
    return Diagnostic(str(path), 1, 1, "", "cannot tell the file kind", hint=KIND_HINT)
