"""`extends:` in a mechanism file: a base mechanism, then only what differs.

The base file's top-level keys come first. A section that is a mapping of named items in
both files (`bodies`, `joints`, `forces`, `parameters`, ...) is merged by name: an item the
derived file names replaces the base's item of that name whole (never merged key by key),
in the base's place; new items follow the base's, in the derived file's order. Any other
key the derived file gives (`name`, `gravity`, `plane`) replaces the base's. `remove:
[NAME, ...]` drops base items: a bare name from every section that holds it except
`parameters` (a parameter and a force may share a name), `SECTION.NAME` from that section
only. Both files use the same `units:` (the derived file may leave them out). A base may
extend another; a cycle is refused. Every merged item keeps the file, line and column it
was written at (`SourceTree.origins`), and the paths a base names (hardpoint tables,
imported FE models) stay relative to the base's own folder.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.foundation.limits import local_path_problem
from loadcases.yamlfiles.source import KeyPath, Locator, SourceTree, load_yaml

__all__ = ["EXTENDS_KEY", "REMOVE_KEY", "Extended", "resolve_extends"]

EXTENDS_KEY = "extends"
REMOVE_KEY = "remove"
_MAX_DEPTH = 16  # bases of bases: far more than any variant tree needs


class Extended:
    """A mechanism tree with its bases merged in: the tree, the bytes of every base file
    (for the input hash, nearest base first) and the problems found."""

    def __init__(self, tree: SourceTree) -> None:
        self.tree = tree
        self.contents: list[bytes] = []
        self.diagnostics: list[Diagnostic] = []


Prepare = Callable[[SourceTree], tuple[list[bytes], list[Diagnostic]]]


def resolve_extends(tree: SourceTree, prepare: Prepare, chain: tuple[str, ...] = ()) -> Extended:
    """`tree` with the base its `extends:` names merged in (recursively); a tree without
    `extends:` (or `remove:`) is returned as it is. `prepare` readies each base tree
    before the merge (its hardpoint table read in its own folder and units) and returns
    the bytes of the files it read and its problems."""
    out = Extended(tree)
    data = tree.data
    if not isinstance(data, dict) or (EXTENDS_KEY not in data and REMOVE_KEY not in data):
        return out
    here = Locator(tree)
    source = data.pop(EXTENDS_KEY, None)
    removals = data.pop(REMOVE_KEY, None)
    if source is None:
        out.diagnostics.append(here.diagnostic((REMOVE_KEY,), "remove: needs extends: a base"))
        return out
    base_path = _base_path(here, source, chain, out.diagnostics)
    if base_path is None:
        return out
    try:
        base_tree = load_yaml(base_path)
        base = resolve_extends(base_tree, prepare, (*chain, os.path.realpath(tree.file)))
    except InputError as error:
        out.diagnostics += error.diagnostics
        return out
    out.contents = [Path(base_path).read_bytes(), *base.contents]
    out.diagnostics += base.tree.diagnostics + base.diagnostics
    if not isinstance(base.tree.data, dict):
        out.diagnostics.append(here.diagnostic((EXTENDS_KEY,), f"{source}: not a mechanism"))
        return out
    tables, problems = prepare(base.tree)
    out.contents += tables
    out.diagnostics += problems
    _relocate_paths(base.tree, Path(base_path).parent, Path(tree.file).parent)
    out.tree = _merged(base.tree, tree, removals, out.diagnostics)
    return out


def _base_path(
    here: Locator, source: Any, chain: tuple[str, ...], found: list[Diagnostic]
) -> str | None:
    """The base file named by `extends:` (relative to this file's folder), or None after
    a problem at the key."""
    if not isinstance(source, str) or not source.strip():
        found.append(here.diagnostic((EXTENDS_KEY,), "extends: names a mechanism file"))
        return None
    folder = Path(os.path.dirname(here.tree.file) or ".")
    problem = local_path_problem(source.strip(), folder, "the mechanism")
    if problem is not None:
        found.append(here.diagnostic((EXTENDS_KEY,), problem))
        return None
    path = os.path.normpath(folder / source.strip())
    if not Path(path).is_file():
        found.append(here.diagnostic((EXTENDS_KEY,), f"base mechanism file not found: {path}"))
        return None
    real = os.path.realpath(path)
    if real in chain or real == os.path.realpath(here.tree.file) or len(chain) >= _MAX_DEPTH:
        loop = " -> ".join(Path(p).name for p in (*chain, here.tree.file, path))
        found.append(here.diagnostic((EXTENDS_KEY,), f"mechanism files extend in a cycle: {loop}"))
        return None
    return path


def _relocate_paths(base: SourceTree, base_folder: Path, folder: Path) -> None:
    """Imported FE models of the base named relative to the derived file's folder (a
    hardpoint table was read when the base was: its points are in the tree)."""
    if os.path.realpath(base_folder) == os.path.realpath(folder):
        return
    bodies = base.data.get("bodies")
    for body in bodies.values() if isinstance(bodies, dict) else ():
        flexible = body.get("flexible") if isinstance(body, dict) else None
        source = flexible.get("file") if isinstance(flexible, dict) else None
        if isinstance(source, dict) and isinstance(source.get("path"), str):
            target = os.path.join(base_folder, source["path"])
            source["path"] = os.path.relpath(target, folder).replace(os.sep, "/")


def _copy_positions(source: SourceTree, target: SourceTree, prefix: KeyPath) -> None:
    """Positions of every key under `prefix` copied from `source` into `target` (those
    `target` had there dropped), with the file each was written in."""
    size = len(prefix)

    def under(table: dict) -> dict:
        return {p: v for p, v in table.items() if p[:size] == prefix}

    for table in (target.keys, target.values, target.plain_booleans, target.origins):
        for path in under(table):
            del table[path]
    target.keys.update(under(source.keys))
    target.values.update(under(source.values))
    target.plain_booleans.update(under(source.plain_booleans))
    target.origins.update(under(source.origins))
    target.origins[prefix] = source.file_at(prefix)


def _merged(
    base: SourceTree, derived: SourceTree, removals: Any, found: list[Diagnostic]
) -> SourceTree:
    """The derived tree over the base (module docstring): a new tree, positions kept."""
    out = SourceTree(file=derived.file, data={}, diagnostics=list(derived.diagnostics))
    for key, value in base.data.items():
        out.data[key] = dict(value) if isinstance(value, dict) else value
        _copy_positions(base, out, (key,))
    _units_problem(base, derived, found)
    for key, value in derived.data.items():
        if key == "units" and key in out.data:
            continue  # the same units, or the problem reported above
        if isinstance(value, dict) and isinstance(out.data.get(key), dict):
            # base order with items replaced in place, new items last
            out.data[key] = {**out.data[key], **value}
            out.keys[(key,)] = derived.keys.get((key,), out.keys.get((key,), (1, 1)))
            for name in value:
                _copy_positions(derived, out, (key, name))
        else:
            out.data[key] = value
            _copy_positions(derived, out, (key,))
    _remove(out, derived, removals, found)
    return out


def _units_problem(base: SourceTree, derived: SourceTree, found: list[Diagnostic]) -> None:
    """The derived file states bare numbers in the base's units, or leaves `units:` out."""
    mine = derived.data.get("units")
    if mine is None or mine == base.data.get("units", {}):
        return
    found.append(
        Locator(derived).diagnostic(
            ("units",),
            f"units differ from those of the base {Path(base.file).name} "
            f"({base.data.get('units', {}) or 'SI'}): a file that extends another "
            "uses its units (leave `units:` out)",
        )
    )


def _remove(out: SourceTree, derived: SourceTree, removals: Any, found: list[Diagnostic]) -> None:
    """Drop the items `remove:` names from the merged data (errors at `remove[i]`)."""
    if removals is None:
        return
    here = Locator(derived)
    if not isinstance(removals, list):
        found.append(here.diagnostic((REMOVE_KEY,), "remove: a list of names"))
        return
    for index, name in enumerate(removals):
        where = (REMOVE_KEY, index)
        if not isinstance(name, str):
            found.append(here.diagnostic(where, "remove: names an item of the base"))
            continue
        section, _, item = name.rpartition(".")
        sections = [section] if section else [k for k in out.data if k != "parameters"]
        hits = [
            s
            for s in sections
            if s != "units" and isinstance(out.data.get(s), dict) and item in out.data[s]
        ]
        redefined = [
            s for s in hits if isinstance(derived.data.get(s), dict) and item in derived.data[s]
        ]
        if redefined:
            found.append(
                here.diagnostic(where, f"'{name}' is removed and defined again in {redefined[0]}")
            )
        elif not hits:
            found.append(here.diagnostic(where, f"no item '{name}' in the base to remove"))
        for s in hits:
            del out.data[s][item]
