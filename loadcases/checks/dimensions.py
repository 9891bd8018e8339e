"""The dimensions of what expressions name, for their check at `validate`: parameters (by
the unit they are written with), unit names, tables (by the unit of their data) and
`effort(M)` (by the motion's joint); and tables whose items disagree in dimension."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from loadcases.expressions.dimensions import DimensionScope, Dims, same_dimension
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.units import (
    DIMENSIONS,
    SIValue,
    UnitError,
    describe_dimension,
    quantity_dimension,
    unit_dimension,
    vector_text_unit,
)
from loadcases.yamlfiles.source import Locator

__all__ = ["expression_scope", "sorted_dims", "table_dimension_problems"]


def expression_scope(
    parameters: Mapping[str, Mapping[str, float] | None],
    raw_tables: Any,
    raw_efforts: Mapping[str, str] | None = None,
) -> DimensionScope:
    """What the names of expressions mean for dimensions: each parameter's (None when written
    without a unit), then the unit names'; each table's x and y as written (`"[0, 30] deg"`,
    or the first item with a unit; None for bare numbers); `raw_efforts` the joint type of
    each motion (`effort(M)` is a torque on a revolute, a force on a prismatic)."""

    def name(word: str) -> Dims | None:
        if word in parameters:
            dims = parameters[word]
            return None if dims is None else sorted_dims(dims)
        return unit_dimension(word)

    tables = {}
    for table, raw in (raw_tables or {}).items() if isinstance(raw_tables, dict) else ():
        if isinstance(raw, dict):
            tables[str(table)] = (_written(raw.get("x")), _written(raw.get("y")))
    efforts = {
        motion: sorted_dims(DIMENSIONS[_EFFORTS[kind]])
        for motion, kind in (raw_efforts or {}).items()
        if kind in _EFFORTS
    }
    return DimensionScope(name, tables, parameters=frozenset(parameters), efforts=efforts)


def _written(values: Any) -> Dims | None:
    """The dimension a table's data is written in (its first item of known dimension), None
    if bare or unreadable."""
    return next((dims for _, dims in _item_dimensions(values)), None)


def _item_dimensions(values: Any) -> list[tuple[int, Dims]]:
    """(index, dimension) of each item of a table's `x` or `y` whose dimension is known: a
    text with a unit, a parameter written with one, or every item of `"[...] unit"`."""
    if isinstance(values, str):
        unit = vector_text_unit(values)
        dims = _text_dimension(f"1 {unit}") if unit else None
        return [] if dims is None else [(0, dims)]
    found = []
    for index, value in enumerate(values if isinstance(values, list) else []):
        if isinstance(value, SIValue):
            dims = None if value.dims is None else sorted_dims(value.dims)
        else:
            dims = _text_dimension(value) if isinstance(value, str) else None
        if dims is not None:
            found.append((index, dims))
    return found


def _text_dimension(text: str) -> Dims | None:
    try:
        return quantity_dimension(text)
    except UnitError:
        return None


def sorted_dims(dims: Mapping[str, float]) -> Dims:
    """A base dimensionality ({"[length]": 1}) as the expressions' `Dims`."""
    return tuple(sorted((k, float(v)) for k, v in dims.items() if v))


def table_dimension_problems(locator: Locator, raw_tables: Any) -> list[Diagnostic]:
    """An item of a table's `x` or `y` of another dimension than the first item of known
    dimension (`x: ["0 deg", "1 m"]`), at the item."""
    found = []
    for table, raw in (raw_tables or {}).items() if isinstance(raw_tables, dict) else ():
        for axis in ("x", "y"):
            items = _item_dimensions(raw.get(axis)) if isinstance(raw, dict) else []
            for index, dims in items[1:]:
                if not same_dimension(dims, items[0][1]):
                    found.append(
                        locator.diagnostic(
                            ("tables", table, axis, index),
                            f"expected {describe_dimension(dict(items[0][1]))} like item "
                            f"{items[0][0] + 1}, got {describe_dimension(dict(dims))}",
                        )
                    )
    return found


_EFFORTS = {"revolute": "torque", "prismatic": "force"}  # by the motion's joint type
