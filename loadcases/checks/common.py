"""Shared helpers of the semantic checks: name lookups and expression checks."""

from __future__ import annotations

import re
from collections.abc import Collection, Iterable

from loadcases.expressions import ExpressionError, parse
from loadcases.foundation.diagnostics import Diagnostic, Severity
from loadcases.foundation.units import RESERVED_NAMES, unit_constant
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = ["GROUND", "Names", "check_expression", "check_expressions", "unknown"]

GROUND = "ground"


class Names:
    """Known names of one mechanism (and case) by kind, for reference checks."""

    def __init__(self, **kinds: Collection[str]) -> None:
        self.kinds = {kind: set(names) for kind, names in kinds.items()}

    def get(self, kind: str) -> set[str]:
        """The names of `kind` (empty set if none)."""
        return self.kinds.get(kind, set())


def unknown(
    locator: Locator,
    path: KeyPath,
    what: str,
    name: str,
    known: Iterable[str],
    *,
    severity: Severity = "error",
    offset: int | None = None,
) -> Diagnostic:
    """`unknown body 'grund'` with a `did you mean 'ground'?` hint."""
    known = sorted(known)
    hint = did_you_mean(name, known)
    if hint is None and known and len(known) <= 12:
        hint = f"known {what} names: " + ", ".join(known)
    return locator.diagnostic(
        path, f"unknown {what} '{name}'", hint=hint, severity=severity, offset=offset
    )


def _offset(text: str, word: str) -> int | None:
    """0-based offset of the first whole-word `word` in `text`."""
    match = re.search(rf"(?<![A-Za-z0-9_]){re.escape(word)}(?![A-Za-z0-9_])", text)
    return match.start() if match else None


_MEASURE_KINDS = {
    "angle": "joints",
    "omega": "joints",
    "travel": "joints",
    "speed": "joints",
    "dist": "points",
    "x": "points",
    "y": "points",
    "z": "points",
    "vx": "points",
    "vy": "points",
    "vz": "points",
}
_SINGULAR = {"joints": "joint", "points": "point", "tables": "table"}


def check_expression(
    locator: Locator, path: KeyPath, text: str, names: Names, parameters: Collection[str]
) -> list[Diagnostic]:
    """Syntax errors and unknown identifiers, joints, points and tables of one expression."""
    try:
        expression = parse(text)
    except ExpressionError as error:
        return [
            locator.diagnostic(
                path, f"invalid expression: {error.message}", hint=error.hint, offset=error.offset
            )
        ]
    found = []
    for name in sorted(expression.names()):
        if name in parameters or name in RESERVED_NAMES or unit_constant(name) is not None:
            continue
        found.append(
            locator.diagnostic(
                path,
                f"unknown name '{name}' in expression",
                offset=_offset(text, name),
                hint=did_you_mean(name, [*parameters, "t", "pi"])
                or "use t, pi, a parameter, a unit name or a function",
            )
        )
    for kind, args in sorted(expression.measures()):
        collection = _MEASURE_KINDS.get(kind)
        if collection is None:
            continue
        for arg in args:
            if arg not in names.get(collection):
                found.append(
                    unknown(
                        locator,
                        path,
                        _SINGULAR[collection],
                        arg,
                        names.get(collection),
                        offset=_offset(text, arg),
                    )
                )
    for table in sorted(expression.tables()):
        if table not in names.get("tables"):
            found.append(
                unknown(
                    locator, path, "table", table, names.get("tables"), offset=_offset(text, table)
                )
            )
    return found


def check_expressions(
    locator: Locator,
    items: Iterable[tuple[KeyPath, str]],
    names: Names,
    parameters: Collection[str],
) -> list[Diagnostic]:
    """check_expression over (path, text) pairs."""
    return [
        d for path, text in items for d in check_expression(locator, path, text, names, parameters)
    ]
