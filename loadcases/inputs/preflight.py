"""Checks of a `loads run` command line before anything is solved: the output folder can
take results, and no two case files would write the same result files."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from loadcases.foundation.clip import clip
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.yamlfiles.source import load_yaml

__all__ = ["duplicate_case_names", "output_folder_problem"]


def output_folder_problem(folder: Path) -> str | None:
    """Why results cannot be written into `folder` (created if missing), or None: it is a
    file, it is under a file, or its nearest existing folder is not writable."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        return "is a file, not a folder"
    existing = folder
    while not existing.exists():
        if existing.parent == existing:
            break
        existing = existing.parent
    if existing != folder and not existing.is_dir():
        return f"{existing} is a file, not a folder"
    if not os.access(existing, os.W_OK | os.X_OK):
        return f"{existing} is not writable"
    return None


def duplicate_case_names(case_files: Iterable[Path]) -> list[Diagnostic]:
    """One diagnostic per case file whose `case:` name an earlier file already has (both
    would write `NAME.csv`). Files that cannot be read are left to their own run."""
    first: dict[str, Path] = {}
    found = []
    for path in case_files:
        try:
            tree = load_yaml(path)
        except InputError:
            continue
        name = tree.data.get("case") if isinstance(tree.data, dict) else None
        if not isinstance(name, str):
            continue
        if name in first:
            line, col = tree.value_position(("case",))
            found.append(
                Diagnostic(
                    str(path),
                    line,
                    col,
                    "case",
                    (
                        f"case name '{clip(name)}' is also the name in {first[name].name} (both "
                        f"would write {clip(name)}.csv)"
                    ),
                    hint="give each case file its own name",
                )
            )
        first.setdefault(name, Path(path))
    return found
