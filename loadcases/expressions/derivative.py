"""Exact symbolic d/dt of time-only trees (chain rule through every function).

Piecewise functions differentiate piecewise: abs -> sign, sign and comparisons -> 0,
min/max -> the derivative of the selected argument, step -> the `_smooth` family.
Tables use their interpolator's `derivative()` when it has one, else central differences.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from .errors import ExpressionError
from .nodes import (
    Call,
    Measure,
    Node,
    Num,
    Op,
    Table,
    Time,
    add,
    call,
    div,
    mul,
    neg,
    num,
    once,
    power,
    sub,
)

__all__ = ["CentralDifference", "differentiate", "table_derivative"]

# Relative step of the central-difference fallback for tables: its error is ~ h^2 f'''
# and ~ eps / h^2 for a second derivative taken this way twice.
_FD_STEP = 1.0e-4


@dataclass(frozen=True)
class CentralDifference:
    """d fn / dx by central differences, for interpolators without `derivative()`."""

    fn: Callable[[float], float]

    def __call__(self, x: float) -> float:
        h = _FD_STEP * max(1.0, abs(x))
        return (float(self.fn(x + h)) - float(self.fn(x - h))) / (2.0 * h)

    def derivative(self) -> CentralDifference:
        """The next derivative, again by central differences."""
        return CentralDifference(self)


def table_derivative(fn: Callable[[float], float]) -> Callable[[float], float]:
    """The derivative of an interpolating callable."""
    method = getattr(fn, "derivative", None)
    return method() if callable(method) else CentralDifference(fn)


def differentiate(node: Node) -> Node:
    """d node / dt (not simplified beyond identities with 0 and 1; fold afterwards). A
    sub-tree met twice is differentiated once: the result shares it (as the tree shares
    its operands), so a derivative grows with the tree, not with its paths."""
    return _Derivative().of(node)


class _Derivative:
    """One differentiation: the derivative of each node met, by the node's id."""

    def __init__(self) -> None:
        self.done: dict[int, tuple[Node, Node]] = {}

    def of(self, node: Node) -> Node:
        return once(self.done, node, self._of)

    def _of(self, node: Node) -> Node:
        if isinstance(node, Num):
            result: Node = num(0.0, node.offset)
        elif isinstance(node, Time):
            result = num(1.0, node.offset)
        elif isinstance(node, Op):
            result = self.op(node)
        elif isinstance(node, Call):
            result = self.call(node)
        elif isinstance(node, Table):
            (x,) = node.args
            assert node.fn is not None, "tables are resolved before differentiation"
            slope = replace(node, name=node.name + "'", fn=table_derivative(node.fn))
            result = mul(slope, self.of(x), node.offset)
        elif isinstance(node, Measure):
            raise ExpressionError(
                f"cannot differentiate {node.label()} with respect to time", node.offset
            )
        else:
            raise TypeError(f"cannot differentiate {node!r}")
        return result

    def op(self, node: Op) -> Node:
        o = node.offset
        if node.op == "neg":
            return neg(self.of(node.args[0]), o)
        if node.op not in ("+", "-", "*", "/", "**"):
            return num(0.0, o)  # comparisons and logic are piecewise constant
        a, b = node.args
        da, db = self.of(a), self.of(b)
        if node.op == "+":
            return add(da, db, o)
        if node.op == "-":
            return sub(da, db, o)
        if node.op == "*":
            return add(mul(da, b, o), mul(a, db, o), o)
        if node.op == "/":
            return sub(div(da, b, o), div(mul(a, db, o), mul(b, b, o), o), o)
        if isinstance(b, Num):
            return mul(mul(b, power(a, num(b.value - 1.0), o), o), da, o)
        log_a = call("log", a, offset=o)
        return mul(node, add(mul(db, log_a, o), div(mul(b, da, o), a, o), o), o)

    def call(self, node: Call) -> Node:
        o, args = node.offset, node.args
        if node.func in _OUTER:
            (a,) = args
            return mul(_OUTER[node.func](a, node, o), self.of(a), o)
        if node.func == "atan2":
            y, x = args
            top = sub(mul(x, self.of(y), o), mul(y, self.of(x), o), o)
            return div(top, add(_square(x, o), _square(y, o), o), o)
        if node.func in ("min", "max"):
            select = "_minsel" if node.func == "min" else "_maxsel"
            return call(select, *args, *(self.of(a) for a in args), offset=o)
        if node.func in ("_minsel", "_maxsel"):
            n = len(args) // 2
            return call(node.func, *args[:n], *(self.of(a) for a in args[n:]), offset=o)
        if node.func == "step":
            return self.step(node)
        raise TypeError(f"no derivative rule for {node.func!r}")

    def step(self, node: Call) -> Node:
        """h0 + (h1 - h0) S(s), s = (x - x0) / (x1 - x0): differentiate that form."""
        o = node.offset
        x, x0, h0, x1, h1 = node.args
        s = div(sub(x, x0, o), sub(x1, x0, o), o)
        dh0, dh1 = self.of(h0), self.of(h1)
        level = mul(sub(dh1, dh0, o), call("_smooth", s, offset=o), o)
        ramp = mul(mul(sub(h1, h0, o), call("_dsmooth", s, offset=o), o), self.of(s), o)
        return add(add(dh0, level, o), ramp, o)


def _square(a: Node, o: int) -> Node:
    return power(a, num(2.0), o)


# d f(a) / da for the functions of one argument, as a tree in `a` (node is f(a)).
_OUTER: dict[str, Callable[[Node, Node, int], Node]] = {
    "sin": lambda a, f, o: call("cos", a, offset=o),
    "cos": lambda a, f, o: neg(call("sin", a, offset=o), o),
    "tan": lambda a, f, o: add(num(1.0), _square(f, o), o),
    "asin": lambda a, f, o: div(
        num(1.0), call("sqrt", sub(num(1.0), _square(a, o), o), offset=o), o
    ),
    "acos": lambda a, f, o: div(
        num(-1.0), call("sqrt", sub(num(1.0), _square(a, o), o), offset=o), o
    ),
    "atan": lambda a, f, o: div(num(1.0), add(num(1.0), _square(a, o), o), o),
    "sqrt": lambda a, f, o: div(num(0.5), f, o),
    "abs": lambda a, f, o: call("sign", a, offset=o),
    "sign": lambda a, f, o: num(0.0),
    "exp": lambda a, f, o: f,
    "log": lambda a, f, o: div(num(1.0), a, o),
    "_smooth": lambda a, f, o: call("_dsmooth", a, offset=o),
    "_dsmooth": lambda a, f, o: call("_d2smooth", a, offset=o),
    "_d2smooth": lambda a, f, o: call("_d3smooth", a, offset=o),
    "_d3smooth": lambda a, f, o: num(0.0),
}
