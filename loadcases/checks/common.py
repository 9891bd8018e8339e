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
    Dims,
    infer_dimension,
    same_dimension,
    without_angle,
)
from loadcases.foundation.diagnostics import Diagnostic, Severity
from loadcases.foundation.units import (
    DIMENSIONS,
    RESERVED_NAMES,
    UnitError,
    describe_dimension,
    quantity_dimension,
    si_unit_text,
    unit_constant,
)
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import KeyPath, Locator, format_key

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
        return _plain_number_problems(locator, path, expression, scope, dimension)
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


_PROBE = "[parameter]"  # a base dimension standing for one parameter's, to find its power


def _plain_number_problems(
    locator: Locator, path: KeyPath, expression: Any, scope: DimensionScope, dimension: str
) -> list[Diagnostic]:
    """The problem of an expression of parameters with units that has no known dimension only
    because its numbers may carry units, read once more with plain numbers
    (`-0.5*rho*airspeed^2*cda` with `airspeed: 250 kg`).

    A number may carry a unit an engineer writes (9.81 in m/s^2, 1000 in N/s): when the
    factor missing to the expected dimension is such a named dimension, a warning. When it
    is not (kg^-2*m^2/s^2 for the drag above), no one number explains the formula: an error,
    at the parameter whose unit does when exactly one does (`airspeed` as a velocity), else
    at the expression."""
    used = sorted(name for name in expression.names() & scope.parameters if scope.names(name))
    if not used:
        return []
    plain_scope = replace(scope, coefficients=True)
    try:
        plain = infer_dimension(expression.tree, plain_scope)
    except ExpressionError:
        return []
    want = sorted_dims(DIMENSIONS[dimension])
    if plain is None or same_dimension(plain, want) or not without_angle(plain):
        return []
    message = (
        f"with its numbers as plain coefficients this gives "
        f"{describe_dimension(dict(plain))}, where {describe_dimension(dict(want))} is expected"
    )
    if _named(_quotient(want, plain)):
        return [
            locator.diagnostic(
                path,
                message,
                severity="warning",
                hint="a parameter may have the wrong unit; or a number carries one (9.81 for "
                "m/s^2): write it with its unit (9.81*m/s^2) to have the formula checked",
            )
        ]
    declared = locator.data.get("parameters") if isinstance(locator.data, dict) else None
    if any(_overridden(declared, name, scope) for name in used):
        return []  # a case, set or --set value of another dimension: an error at its own key
    suspects = {
        name: needed
        for name in used
        if (needed := _needed_dimension(expression, plain_scope, name, want)) is not None
    }
    if len(suspects) == 1 and isinstance(declared, dict):
        name, needed = next(iter(suspects.items()))
        if name in declared:
            have = scope.names(name) or ()
            where = format_key((*locator.prefix, *path))
            return [
                locator.diagnostic(
                    ("parameters", name),
                    f"'{name}' is {describe_dimension(dict(have))}, but "
                    f"{where} needs {describe_dimension(dict(needed))} "
                    f"({si_unit_text(dict(needed))}): {message}",
                    hint=f"write '{name}' in a unit of {describe_dimension(dict(needed))}",
                )
            ]
    return [
        locator.diagnostic(
            path,
            message,
            hint="a parameter has the wrong unit, or a number carries one: write it with its "
            "unit (9.81*m/s^2) to have the formula checked",
        )
    ]


def _overridden(declared: Any, name: str, scope: DimensionScope) -> bool:
    """Whether parameter `name` has another dimension in `scope` than as written in this
    file's `parameters` (a case, a set or `--set` gave it another)."""
    text = declared.get(name) if isinstance(declared, dict) else None
    if not isinstance(text, str):
        return False
    try:
        written = quantity_dimension(text)
    except UnitError:
        return False
    have = scope.names(name)
    return written is not None and have is not None and not same_dimension(written, have)


def _quotient(a: Dims, b: Dims) -> Dims:
    """`a / b`, the power of the radian aside."""
    powers = dict(without_angle(a))
    for base, power in without_angle(b):
        powers[base] = powers.get(base, 0.0) - power
    return tuple(sorted((k, v) for k, v in powers.items() if abs(v) > 1e-12))


def _named(dims: Dims) -> bool:
    """Whether `dims` is a dimension with a name (a force, an acceleration, ...), the kind a
    number written without its unit may carry; a plain number is not."""
    return bool(dims) and any(
        same_dimension(dims, sorted_dims(known)) for known in DIMENSIONS.values() if known
    )


def _needed_dimension(expression: Any, scope: DimensionScope, name: str, want: Dims) -> Dims | None:
    """The named dimension parameter `name` would need for the expression (numbers plain) to
    be of dimension `want`, other parameters as declared; None if no named one does."""

    def probed(word: str) -> Dims | None:
        return ((_PROBE, 1.0),) if word == name else scope.names(word)

    try:
        dims = infer_dimension(expression.tree, replace(scope, names=probed))
    except ExpressionError:
        return None
    if dims is None:
        return None
    power = dict(dims).pop(_PROBE, 0.0)
    rest = tuple(pair for pair in dims if pair[0] != _PROBE)
    if abs(power) < 1e-12:
        return None
    needed = tuple(sorted((k, v / power) for k, v in _quotient(want, rest)))
    return needed if _named(needed) else None


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
