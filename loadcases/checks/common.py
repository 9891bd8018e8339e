"""Shared helpers of the semantic checks: name lookups and expression checks."""

from __future__ import annotations

import re
from collections.abc import Collection, Iterable, Mapping
from dataclasses import replace
from typing import Any

from loadcases.checks.dimensions import sorted_dims
from loadcases.expressions import ExpressionError, parse
from loadcases.expressions.dimensions import (
    DimensionScope,
    infer_dimension,
    same_dimension,
    without_angle,
)
from loadcases.foundation.diagnostics import Diagnostic, Severity
from loadcases.foundation.units import (
    DIMENSIONS,
    RESERVED_NAMES,
    describe_dimension,
    unit_constant,
)
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = [
    "GROUND",
    "Expected",
    "Names",
    "check_expression",
    "check_expressions",
    "unknown",
]

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


Expected = tuple[str, Severity]  # the dimension of a result (a name of DIMENSIONS), and
# how a result of another known dimension is reported


def _dimension_problems(
    locator: Locator,
    path: KeyPath,
    expression: Any,
    scope: DimensionScope,
    expected: Expected | None,
) -> list[Diagnostic]:
    """The dimension error of one expression (two known dimensions that disagree), or the
    problem of a result of another dimension than `expected`, if any."""
    try:
        dims = infer_dimension(expression.tree, scope)
    except ExpressionError as error:
        return [locator.diagnostic(path, error.message, offset=error.offset)]
    if expected is None:
        return []
    dimension, severity = expected
    want = tuple(sorted((k, float(v)) for k, v in DIMENSIONS[dimension].items()))
    if dims is None:
        return _plain_number_warning(locator, path, expression, scope, dimension)
    if same_dimension(dims, want) or not without_angle(dims):
        return []  # a plain number (`exp(100*t)`, `cos(angle(j))`) is SI of what is expected
    return [
        locator.diagnostic(
            path,
            f"expected {describe_dimension(DIMENSIONS[dimension])}, got "
            f"{describe_dimension(dict(dims))}",
            severity=severity,
            hint=None
            if severity == "error"
            else f"it is taken as {describe_dimension(DIMENSIONS[dimension])} in SI; write "
            "the units that make it one (`crank_speed * t` with crank_speed in deg/s)",
        )
    ]


def _plain_number_warning(
    locator: Locator, path: KeyPath, expression: Any, scope: DimensionScope, dimension: str
) -> list[Diagnostic]:
    """A warning when an expression of parameters with units has no known dimension only
    because its numbers may carry units, and read with plain numbers gives another one than
    expected (`-0.5*rho*airspeed^2*cda` with `airspeed: 250 kg`)."""
    if not any(scope.names(name) for name in expression.names() & scope.parameters):
        return []
    try:
        plain = infer_dimension(expression.tree, replace(scope, coefficients=True))
    except ExpressionError:
        return []
    want = DIMENSIONS[dimension]
    if plain is None or same_dimension(plain, sorted_dims(want)) or not without_angle(plain):
        return []
    return [
        locator.diagnostic(
            path,
            f"with its numbers as plain coefficients this gives "
            f"{describe_dimension(dict(plain))}, where {describe_dimension(want)} is expected",
            severity="warning",
            hint="a parameter may have the wrong unit; or a number carries one (9.81 for "
            "m/s^2): write it with its unit (9.81*m/s^2) to have the formula checked",
        )
    ]


def check_expression(
    locator: Locator,
    path: KeyPath,
    text: str,
    names: Names,
    parameters: Collection[str],
    scope: DimensionScope | None = None,
    expected: Expected | None = None,
) -> list[Diagnostic]:
    """Syntax errors and unknown identifiers, joints, points and tables of one expression;
    then, given a `scope`, its dimensions (`expected`: the result's, and the severity of
    another)."""
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
    if scope is not None and not found:
        found += _dimension_problems(locator, path, expression, scope, expected)
    return found


def check_expressions(
    locator: Locator,
    items: Iterable[tuple[KeyPath, str]],
    names: Names,
    parameters: Collection[str],
    scope: DimensionScope | None = None,
    expected: Mapping[KeyPath, Expected] | None = None,
) -> list[Diagnostic]:
    """check_expression over (path, text) pairs; `expected` the result dimension by path."""
    return [
        d
        for path, text in items
        for d in check_expression(
            locator, path, text, names, parameters, scope, (expected or {}).get(path)
        )
    ]
