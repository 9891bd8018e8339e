"""`Expression` (parsed text) and `CompiledExpression` (a fast callable of t and state)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from types import MappingProxyType

import numpy as np

from .derivative import differentiate
from .errors import ExpressionError
from .nodes import Measure, Name, Node, Num, Table, walk
from .parser import TOO_DEEP, parse_tree
from .resolve import Resolver, UnitLookup, fold, is_time_only
from .scalar import build_scalar
from .vector import Vector, build_vector

__all__ = ["CompiledExpression", "Expression", "parse"]

_EMPTY: Mapping = MappingProxyType({})


def parse(text: str) -> Expression:
    """Parse expression text; raises ExpressionError with `.message` and `.offset`."""
    return Expression(text, parse_tree(text))


class Expression:
    """A parsed expression: its `text`, tree, and the names, measures and tables it uses."""

    __slots__ = ("text", "tree")

    def __init__(self, text: str, tree: Node) -> None:
        self.text = text
        self.tree = tree

    def __repr__(self) -> str:
        return f"Expression({self.text!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Expression) and other.tree == self.tree

    def __hash__(self) -> int:
        return hash(self.tree)

    def names(self) -> set[str]:
        """Free identifiers: `t`, `pi`, parameters and units (not functions, not measure
        or table arguments)."""
        return {n.id for n in walk(self.tree) if isinstance(n, Name)}

    def measures(self) -> set[tuple[str, tuple[str, ...]]]:
        """State measures used, e.g. {('angle', ('hinge',)), ('dist', ('a', 'b'))}."""
        return {(n.kind, n.names) for n in walk(self.tree) if isinstance(n, Measure)}

    def tables(self) -> set[str]:
        """Names of the tables used."""
        return {n.name for n in walk(self.tree) if isinstance(n, Table)}

    def compile(
        self,
        parameters: Mapping[str, float] = _EMPTY,
        tables: Mapping[str, Callable[[float], float]] = _EMPTY,
        unit_lookup: UnitLookup | None = None,
    ) -> CompiledExpression:
        """Resolve names (t, parameters, pi, then units via `unit_lookup`, by default
        `loadcases.foundation.units.unit_constant`), fold constants and build the closure."""
        resolver = Resolver(parameters, tables, unit_lookup)
        try:
            tree = fold(resolver.resolve(self.tree))
            fn = build_scalar(tree)
        except ExpressionError as error:
            raise error.with_text(self.text) from None
        except RecursionError:
            raise ExpressionError(TOO_DEEP, 0, self.text) from None
        source = (self.text, resolver.constants, resolver.tables_used)
        return CompiledExpression(tree, fn, source, order=0)


def _rebuild(text: str, constants: dict, tables: dict, order: int) -> CompiledExpression:
    """Unpickle: compile the text again with the values it used, then differentiate."""
    compiled = parse(text).compile(constants, tables, unit_lookup=_no_units)
    for _ in range(order):
        compiled = compiled.derivative()
    return compiled


def _no_units(name: str) -> None:
    return None


class CompiledExpression:
    """`fn(t, state=None) -> float`; `time_only` ones also have `derivative()` (d/dt)
    and `evaluate_array(t)`. `is_constant` ones have their `value` (else None)."""

    __slots__ = (
        "_derivative",
        "_fn",
        "_source",
        "_vector",
        "is_constant",
        "order",
        "text",
        "time_only",
        "tree",
        "value",
    )

    def __init__(
        self,
        tree: Node,
        fn: Callable[[float, object], float],
        source: tuple[str, dict, dict],
        order: int,
    ) -> None:
        self._fn = fn
        self.tree = tree
        self.text, self.order, self._source = source[0], order, source
        self.time_only = is_time_only(tree)
        self.is_constant = isinstance(tree, Num)
        self.value: float | None = tree.value if isinstance(tree, Num) else None
        self._derivative: CompiledExpression | None = None
        self._vector: Vector | None = None

    def __call__(self, t: float, state: object = None) -> float:
        return self._fn(t, state)

    def __repr__(self) -> str:
        prefix = "d/dt " * self.order
        return f"CompiledExpression({prefix}{self.text!r})"

    def __reduce__(self) -> tuple:
        text, constants, tables = self._source
        return _rebuild, (text, constants, tables, self.order)

    def _require_time_only(self, what: str) -> None:
        if not self.time_only:
            measure = next(n for n in walk(self.tree) if isinstance(n, Measure))
            raise ExpressionError(
                f"{what} needs a time-only expression, not one using {measure.label()}",
                measure.offset,
                self.text,
            )

    def derivative(self) -> CompiledExpression:
        """The exact d/dt (time-only expressions; cached)."""
        self._require_time_only("derivative")
        if self._derivative is None:
            try:
                tree = fold(differentiate(self.tree))
                fn = build_scalar(tree)
            except ExpressionError as error:
                raise error.with_text(self.text) from None
            except RecursionError:
                raise ExpressionError(TOO_DEEP, 0, self.text) from None
            self._derivative = CompiledExpression(tree, fn, self._source, self.order + 1)
        return self._derivative

    def evaluate_array(self, t: np.ndarray) -> np.ndarray:
        """Values at an array of times (numpy; math errors give nan/inf, not exceptions)."""
        self._require_time_only("evaluate_array")
        if self._vector is None:
            self._vector = build_vector(self.tree)
        times = np.asarray(t, dtype=float)
        with np.errstate(all="ignore"):
            values = self._vector(times)
        return np.array(np.broadcast_to(values, times.shape), dtype=float)
