"""Tabulated element laws: force (N) vs deflection (m), torque (N*m) vs angle (rad).

`TableLaw` wraps a `mechlib.model.tables.Table` for `Spring.law` / `TorsionSpring.law` / `Seal.law`:
a value outside a table that does not extrapolate becomes a `SolverFailure` naming the
element. Its exact `integral` gives those elements their potential energy.
"""

from __future__ import annotations

from mechlib.core.outcome import SolverFailure
from mechlib.model.tables import Table, TableRangeError

__all__ = ["TableLaw"]


class TableLaw:
    """law(x) = table(x) for element `element` (x and the result in the table's SI units)."""

    compiled = True  # its table is a law the compiled elements evaluate (Table.packed)

    def __init__(self, table: Table, element: str):
        self.table, self.element = table, element

    def __call__(self, x: float) -> float:
        try:
            return self.table(x)
        except TableRangeError as exc:
            raise SolverFailure(
                f"force element '{self.element}': {exc}", where=(self.element,)
            ) from None

    def integral(self, a: float, b: float) -> float:
        """The exact integral of the law over [a, b] (J for a force vs m or a torque vs rad:
        the work the element's potential stores), mechlib.model.tables.Table.integral."""
        try:
            return self.table.integral(a, b)
        except TableRangeError as exc:
            raise SolverFailure(
                f"force element '{self.element}': {exc}", where=(self.element,)
            ) from None
