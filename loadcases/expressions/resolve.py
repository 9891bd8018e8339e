"""Compile-time passes: resolve names and tables, then fold constant sub-expressions."""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

from .errors import ExpressionError
from .nodes import (
    Call,
    Measure,
    Name,
    Node,
    Num,
    Op,
    Table,
    Time,
    children,
    once,
    walk,
    with_children,
)
from .scalar import build_scalar

__all__ = ["Resolver", "fold", "is_time_only"]

UnitLookup = Callable[[str], "float | None"]


def _default_unit_lookup(name: str) -> float | None:
    from ..foundation.units import (
        unit_constant,  # imported lazily: only expressions with units need it
    )

    return unit_constant(name)


@dataclass
class Resolver:
    """Turns `t` into Time, other names into numbers and attaches table callables.

    Order of lookup for a name: `t` (time, reserved), `parameters`, `pi`, units.
    `constants` and `tables_used` record what was used (to rebuild after pickling).
    """

    parameters: Mapping[str, float]
    tables: Mapping[str, Callable[[float], float]]
    unit_lookup: UnitLookup | None = None
    constants: dict[str, float] = field(default_factory=dict)
    tables_used: dict[str, Callable[[float], float]] = field(default_factory=dict)

    def resolve(self, node: Node) -> Node:
        """A copy of the tree without Name nodes; ExpressionError for unknown names."""
        if isinstance(node, Name):
            return self.name(node)
        args = tuple(self.resolve(child) for child in children(node))
        node = with_children(node, args)
        if isinstance(node, Table):
            if node.name not in self.tables:
                hint = _suggest(node.name, list(self.tables))
                raise ExpressionError(f"unknown table {node.name!r}", node.offset, hint=hint)
            self.tables_used[node.name] = self.tables[node.name]
            node = replace(node, fn=self.tables[node.name])
        return node

    def name(self, node: Name) -> Node:
        if node.id == "t":
            return Time(node.offset)
        value = self.lookup(node.id)
        if value is None:
            hint = _suggest(node.id, [*self.parameters, "t", "pi"])
            raise ExpressionError(f"unknown name {node.id!r}", node.offset, hint=hint)
        self.constants[node.id] = value
        return Num(value, node.offset)

    def lookup(self, name: str) -> float | None:
        if name in self.parameters:
            return float(self.parameters[name])
        if name == "pi":
            return math.pi
        lookup = self.unit_lookup or _default_unit_lookup
        value = lookup(name)
        return None if value is None else float(value)


def _suggest(word: str, choices: list[str]) -> str | None:
    close = difflib.get_close_matches(word, choices, n=1)
    return f"did you mean {close[0]!r}?" if close else None


def fold(node: Node) -> Node:
    """The tree with every constant operation or function replaced by its value; a product
    with a constant factor 0 is 0 whatever the other factor (a switch parameter set to 0
    turns a load off entirely: `pressure_on * ...`). A sub-tree shared by several parents
    (a derivative's) is folded once and stays shared."""
    return _fold(node, {})


def _fold(node: Node, done: dict[int, tuple[Node, Node]]) -> Node:
    return once(done, node, lambda n: _fold_node(n, done))


def _fold_node(node: Node, done: dict[int, tuple[Node, Node]]) -> Node:
    args = []
    for child in children(node):  # a loop, not a generator: one frame less per level
        args.append(_fold(child, done))
    node = with_children(node, tuple(args))
    if isinstance(node, Call) and node.func == "step":
        _check_step(node)
    if isinstance(node, Op) and node.op == "/" and _is_zero(node.args[1]):
        raise ExpressionError("division by zero", node.offset)
    if isinstance(node, (Op, Call)) and all(isinstance(a, Num) for a in node.args):
        return Num(_constant(node), node.offset)
    if (
        isinstance(node, Op)
        and node.op == "*"
        and any(isinstance(a, Num) and a.value == 0.0 for a in node.args)
    ):
        return Num(0.0, node.offset)
    return node


def _is_zero(node: Node) -> bool:
    return isinstance(node, Num) and node.value == 0.0


def _constant(node: Op | Call) -> float:
    """The value of an operation on constants; ExpressionError if it is not finite."""
    value = build_scalar(node)(0.0, None)
    if not math.isfinite(value):
        name = node.op if isinstance(node, Op) else node.func
        raise ExpressionError(f"overflow in {name!r}", node.offset)
    return value


def _check_step(node: Call) -> None:
    x0, x1 = node.args[1], node.args[3]
    if isinstance(x0, Num) and isinstance(x1, Num) and not x1.value > x0.value:
        raise ExpressionError("step needs x0 < x1", node.offset)


def is_time_only(node: Node) -> bool:
    """Whether the tree depends on time alone (no state measures)."""
    return not any(isinstance(n, Measure) for n in walk(node))
