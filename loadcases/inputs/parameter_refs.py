"""Parameters named in numeric fields: `clearance: clearance` (a contact's clearance set by
a parameter, swept by a set) puts the parameter's SI value in place of its name before the
file is validated, and `stiffness: "E*A/L"` (an expression of parameters, units and `pi`)
its value. Never under keys that hold names (bodies, joints, types ...); under the keys of
expressions of time and state (a force's or motion's `value`, `command`) a name only.

The value put in place carries the parameter's dimension (`airspeed: 250 kg` is a mass), so
the field's own check refuses it where another dimension is expected; an expression's
dimension is inferred with its numbers as plain coefficients
(`loadcases.expressions.dimensions`). A text that names no known parameter is kept, with why
(`unknown parameter 'mu_trunion'` and a hint), for the loader to say if the field refuses it."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from loadcases.checks.dimensions import expression_scope
from loadcases.expressions import ExpressionError, parse
from loadcases.expressions.dimensions import infer_dimension
from loadcases.foundation.units import (
    RESERVED_NAMES,
    SIValue,
    UnitError,
    quantity_dimension,
    to_si,
    unit_constant,
)
from loadcases.schema.errors import did_you_mean

__all__ = ["ParameterRef", "Unresolved", "parameter_values", "put_parameters"]

# Keys whose string values are names or words, never numbers.
_NAME_KEYS = frozenset(
    {
        "name",
        "case",
        "set",
        "mechanism",
        "body",
        "bodies",
        "point",
        "points",
        "joint",
        "joints",
        "frame",
        "type",
        "shape",
        "force",
        "motion",
        "contact",
        "law",
        "interpolation",
        "extrapolate",
        "model",
        "then",
        "when",
        "expression",
        "abscissa",
        "loads",
        "units",
        "unit",
        "effects",
        "cases",
        "report",
        "redundant",
        "integrator",
        "quantity",
        "activate",
        "deactivate",
        "release",
        "lock",
        "template",
        "output",
        "requests",
    }
)


def parameter_values(
    *sections: Any,
    file_units: Mapping[str, str] | None = None,
    overrides: Mapping[str, float] | None = None,
    earlier: Mapping[str, SIValue] | None = None,
) -> dict[str, SIValue]:
    """SI values of `earlier` (another file's), then of the raw `parameters:` mappings given
    (later ones override), then of `overrides`, each with its dimension when written with a
    unit (a bare number keeps the dimension of the value it overrides); values that cannot
    be read are left to the validation."""
    values: dict[str, SIValue] = dict(earlier or {})
    for section in sections:
        for name, raw in (section or {}).items() if isinstance(section, dict) else ():
            try:
                si = to_si(raw, "any", file_units)
                dims = quantity_dimension(raw) if isinstance(raw, str) else None
            except (UnitError, KeyError):
                continue
            written = _dict(dims)
            values[str(name)] = SIValue(
                si, _or_earlier(written, values, str(name)), _described(str(name), raw)
            )
    for name, value in (overrides or {}).items():
        shown = getattr(value, "source", "") or _described(name, float(value))
        given = _or_earlier(getattr(value, "dims", None), values, name)
        values[name] = SIValue(float(value), given, shown)
    return values


def _or_earlier(
    dims: Mapping[str, float] | None, values: Mapping[str, SIValue], name: str
) -> Mapping[str, float] | None:
    """`dims`, or when not known (a bare number) those of the value `name` overrides."""
    if dims is None and name in values:
        return values[name].dims
    return dims


def _dict(dims: Any) -> dict[str, float] | None:
    return None if dims is None else dict(dims)


def _described(name: str, raw: Any) -> str:
    return f"parameter '{name}' = '{raw}'" if isinstance(raw, str) else f"parameter '{name}'"


ParameterRef = tuple[tuple[str, ...], str]  # (key path of the field, parameter name)


@dataclass(frozen=True)
class Unresolved:
    """A text in a numeric-looking field that names no known parameter: why, and a hint."""

    message: str
    hint: str | None = None


Located = tuple[str | int, ...]  # a key path with list indices, as diagnostics name it
# Keys whose texts are expressions of time and state: a parameter name is put in place,
# a longer expression is compiled with the run.
_STATE_EXPRESSION_KEYS = frozenset({"value", "command"})


def put_parameters(
    data: Any,
    values: Mapping[str, float],
    prefix: tuple[str, ...] = (),
    unresolved: dict[Located, Unresolved] | None = None,
) -> set[ParameterRef]:
    """Replace, in place, scalar values equal to a parameter name, or constant expressions
    of parameters, by their SI value; returns each field so set as (key path after
    `prefix`, parameter name), so that a set can tell whether the field belongs to the part
    of the mechanism a case uses. Texts that name unknown parameters go to `unresolved`
    (key path with list indices, after `prefix`). The `parameters:` section is left alone."""
    used: set[ParameterRef] = set()
    missing: dict[Located, Unresolved] = {} if unresolved is None else unresolved

    def walk(node: Any, path: tuple[str, ...], located: Located) -> Any:
        key = path[-1] if path else None
        if isinstance(node, dict):
            for k in list(node):
                if k != "parameters":
                    node[k] = walk(node[k], path + (str(k),), located + (str(k),))
            return node
        if isinstance(node, list):
            for i, item in enumerate(node):
                node[i] = walk(item, path, located + (i,))
            return node
        if not isinstance(node, str) or key in _NAME_KEYS:
            return node
        name = node.strip()
        if name in values:
            used.add((path, name))
            value = values[name]
            return SIValue(value, getattr(value, "dims", None), getattr(value, "source", ""))
        if key in _STATE_EXPRESSION_KEYS and path[-3:-2] in (("forces",), ("motions",)):
            return node
        return _constant_expression(node, values, path, located, used, missing)

    walk(data, prefix, ())
    return used


def _constant_expression(
    text: str,
    values: Mapping[str, float],
    path: tuple[str, ...],
    located: Located,
    used: set[ParameterRef],
    missing: dict[Located, Unresolved],
) -> Any:
    """The SIValue of `text` if it is a constant expression of parameters (`"E*A/L"`), else
    `text` (noted in `missing` when it names no known parameter)."""
    try:
        to_si(text, "any")
        return text  # a number or a quantity text: the field converts it
    except UnitError:
        pass
    try:
        expression = parse(text)
    except ExpressionError:
        return text
    names = expression.names()
    unknown = sorted(n for n in names if n not in values and n != "pi" and unit_constant(n) is None)
    if unknown or expression.measures() or expression.tables() or "t" in names:
        if unknown and not (expression.measures() or expression.tables()):
            close = did_you_mean(unknown[0], [n for n in values if n not in RESERVED_NAMES])
            # a lone word like no parameter (`mass: on`) is left to the field's own message
            if close is not None or names != {unknown[0]}:
                missing[located] = Unresolved(f"unknown parameter '{unknown[0]}'", close)
        return text
    if not names & set(values):
        return text  # units only ("2*mm"): not a parameter's business
    return _evaluated(text, expression, values, path, located, used, missing)


def _evaluated(
    text: str,
    expression: Any,
    values: Mapping[str, float],
    path: tuple[str, ...],
    located: Located,
    used: set[ParameterRef],
    missing: dict[Located, Unresolved],
) -> Any:
    """The SIValue of the constant expression `expression` with its inferred dimension."""

    dimensions = {name: getattr(value, "dims", None) for name, value in values.items()}
    scope = replace(expression_scope(dimensions, None), coefficients=True)
    try:
        compiled = expression.compile(values)
        dims = infer_dimension(expression.tree, scope)
    except ExpressionError as error:
        missing[located] = Unresolved(f"invalid expression '{text}': {error.message}")
        return text
    if compiled.value is None:
        return text
    used.update((path, n) for n in expression.names() if n in values)
    return SIValue(compiled.value, _dict(dims), f"'{text.strip()}'")
