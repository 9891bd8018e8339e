"""Expression trees: a few immutable node types and simplifying constructors.

`offset` is the 0-based character offset in the expression text that an error about the
node points at (the operator of a binary operation, the name of a call).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from typing import TypeVar

__all__ = [
    "COMPARISONS",
    "LOGICAL",
    "Call",
    "Measure",
    "Name",
    "Node",
    "Num",
    "Op",
    "Table",
    "Time",
    "add",
    "call",
    "children",
    "div",
    "mul",
    "neg",
    "num",
    "once",
    "power",
    "sub",
    "walk",
    "with_children",
]

COMPARISONS = frozenset({"<", "<=", ">", ">=", "==", "!="})
LOGICAL = frozenset({"and", "or", "not"})


@dataclass(frozen=True, slots=True)
class Num:
    """A number (SI)."""

    value: float
    offset: int = 0


@dataclass(frozen=True, slots=True)
class Name:
    """A free identifier: `t`, `pi`, a parameter or a unit (resolved at compile time)."""

    id: str
    offset: int = 0


@dataclass(frozen=True, slots=True)
class Time:
    """The time `t` (s), after name resolution."""

    offset: int = 0


@dataclass(frozen=True, slots=True)
class Op:
    """An operator: `neg` and `not` take one argument, the others two."""

    op: str
    args: tuple[Node, ...]
    offset: int = 0


@dataclass(frozen=True, slots=True)
class Call:
    """A function of expressions: `sin(x)`, `step(x, x0, h0, x1, h1)`, internal `_smooth`."""

    func: str
    args: tuple[Node, ...]
    offset: int = 0


@dataclass(frozen=True, slots=True)
class Measure:
    """A state measure such as `angle(hinge)` or `dist(a, b)`; arguments are bare names."""

    kind: str
    names: tuple[str, ...]
    offset: int = 0

    def label(self) -> str:
        """Source-like text: `dist(a, b)`."""
        return f"{self.kind}({', '.join(self.names)})"


@dataclass(frozen=True, slots=True)
class Table:
    """`table(name, x)`; `fn` is the interpolating callable, set at compile time."""

    name: str
    args: tuple[Node, ...]
    offset: int = 0
    fn: Callable[[float], float] | None = field(default=None, compare=False)


Node = Num | Name | Time | Op | Call | Measure | Table


def children(node: Node) -> tuple[Node, ...]:
    """The sub-expressions of a node."""
    return getattr(node, "args", ())


def with_children(node: Node, args: tuple[Node, ...]) -> Node:
    """A copy of `node` with new sub-expressions (the node itself if they are the same)."""
    old = children(node)
    if len(args) == len(old) and all(a is b for a, b in zip(args, old)):
        return node
    if not isinstance(node, (Op, Call, Table)):
        raise ValueError(f"{type(node).__name__} has no sub-expressions")
    return replace(node, args=args)


def walk(node: Node) -> Iterator[Node]:
    """Every node of a tree, parents before children, left to right; a node shared by
    several parents (derivatives share sub-trees) once."""
    seen: set[int] = set()
    stack = [node]
    while stack:
        item = stack.pop()
        if id(item) in seen:
            continue
        seen.add(id(item))
        yield item
        stack.extend(reversed(children(item)))


# Simplifying constructors, used to build derivatives (identities with 0 and 1 only).
def num(value: float, offset: int = 0) -> Num:
    """A number node."""
    return Num(float(value), offset)


def _is(node: Node, value: float) -> bool:
    return isinstance(node, Num) and node.value == value


def neg(a: Node, offset: int = 0) -> Node:
    """-a."""
    if isinstance(a, Num):
        return num(-a.value, a.offset)
    if isinstance(a, Op) and a.op == "neg":
        return a.args[0]
    return Op("neg", (a,), offset)


def add(a: Node, b: Node, offset: int = 0) -> Node:
    """a + b."""
    if _is(a, 0.0):
        return b
    if _is(b, 0.0):
        return a
    return Op("+", (a, b), offset)


def sub(a: Node, b: Node, offset: int = 0) -> Node:
    """a - b."""
    if _is(b, 0.0):
        return a
    if _is(a, 0.0):
        return neg(b, offset)
    return Op("-", (a, b), offset)


def mul(a: Node, b: Node, offset: int = 0) -> Node:
    """a * b."""
    if _is(a, 0.0) or _is(b, 0.0):
        return num(0.0, offset)
    if _is(a, 1.0):
        return b
    if _is(b, 1.0):
        return a
    if _is(a, -1.0):
        return neg(b, offset)
    if _is(b, -1.0):
        return neg(a, offset)
    return Op("*", (a, b), offset)


def div(a: Node, b: Node, offset: int = 0) -> Node:
    """a / b."""
    if _is(a, 0.0):
        return num(0.0, offset)
    if _is(b, 1.0):
        return a
    return Op("/", (a, b), offset)


def power(a: Node, b: Node, offset: int = 0) -> Node:
    """a ** b."""
    if _is(b, 1.0):
        return a
    if _is(b, 0.0):
        return num(1.0, offset)
    return Op("**", (a, b), offset)


def call(func: str, *args: Node, offset: int = 0) -> Call:
    """func(args...)."""
    return Call(func, tuple(args), offset)


T = TypeVar("T")


def once(memo: dict[int, tuple[Node, T]], node: Node, make: Callable[[Node], T]) -> T:
    """`make(node)`, made once per node of a tree whose sub-trees may be shared (a
    derivative's): kept in `memo` by the node's id, with the node itself, so that the id
    stays its own while the memo lives."""
    known = memo.get(id(node))
    if known is not None:
        return known[1]
    made = make(node)
    memo[id(node)] = (node, made)
    return made
