"""Parameters named in numeric fields: `clearance: clearance` (a contact's clearance set by
a parameter, swept by a set) puts the parameter's SI value in place of its name before the
file is validated. Only scalar values that are exactly a parameter's name count, and never
under keys that hold names (bodies, joints, types ...)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from loadcases.foundation.units import SIValue, UnitError, to_si

__all__ = ["ParameterRef", "parameter_values", "put_parameters"]

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
) -> dict[str, float]:
    """SI values of the raw `parameters:` mappings given (later ones override), then of
    `overrides`; values that cannot be read are left to the validation to report."""
    values: dict[str, float] = {}
    for section in sections:
        for name, raw in (section or {}).items() if isinstance(section, dict) else ():
            try:
                values[str(name)] = to_si(raw, "any", file_units)
            except (UnitError, KeyError):
                continue
    values.update(overrides or {})
    return values


ParameterRef = tuple[tuple[str, ...], str]  # (key path of the field, parameter name)


def put_parameters(
    data: Any, values: Mapping[str, float], prefix: tuple[str, ...] = ()
) -> set[ParameterRef]:
    """Replace, in place, scalar values equal to a parameter name by its SI value; returns
    each field so set as (key path after `prefix`, parameter name), so that a set can tell
    whether the field belongs to the part of the mechanism a case uses. The `parameters:`
    section itself is left alone."""
    used: set[ParameterRef] = set()

    def walk(node: Any, path: tuple[str, ...]) -> Any:
        key = path[-1] if path else None
        if isinstance(node, dict):
            for k in list(node):
                if k != "parameters":
                    node[k] = walk(node[k], path + (str(k),))
            return node
        if isinstance(node, list):
            for i, item in enumerate(node):
                node[i] = walk(item, path)
            return node
        if isinstance(node, str) and key not in _NAME_KEYS and node.strip() in values:
            used.add((path, node.strip()))
            return SIValue(values[node.strip()])
        return node

    walk(data, prefix)
    return used
