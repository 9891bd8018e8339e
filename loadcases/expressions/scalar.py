"""Trees to fast Python closures `f(t, state) -> float`.

The tree is walked once here; each node becomes one closure that calls its children's
closures, with constant operands captured as plain floats (a sub-tree shared by several
parents, as in derivatives, becomes one closure). Math errors are raised as
ExpressionError at the offset of the operation that failed.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from operator import methodcaller

from .errors import ExpressionError
from .functions import FUNCTIONS, INTERNAL, step
from .nodes import Call, Measure, Node, Num, Op, Table, Time, once

__all__ = ["Scalar", "build_scalar"]

Scalar = Callable[[float, object], float]

_ARITHMETIC = {"+": operator.add, "-": operator.sub, "*": operator.mul}
_COMPARE = {
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
    "==": operator.eq,
    "!=": operator.ne,
}


_Built = dict[int, tuple[Node, Scalar]]


def build_scalar(node: Node, built: _Built | None = None) -> Scalar:
    """The closure computing `node` at (t, state); `built` holds the closures made so far
    in this build, by node id."""
    memo: _Built = {} if built is None else built
    return once(memo, node, lambda n: _scalar(n, memo))


def _scalar(node: Node, built: _Built) -> Scalar:
    """`build_scalar` of one node (its operands through `build_scalar`, once each)."""
    if isinstance(node, Num):
        value = node.value
        fn: Scalar = lambda t, s: value  # noqa: E731
    elif isinstance(node, Time):
        fn = lambda t, s: t  # noqa: E731
    elif isinstance(node, Op):
        fn = _op(node, built)
    elif isinstance(node, Call):
        fn = _step(node, built) if node.func == "step" else _call(node, built)
    elif isinstance(node, Measure):
        fn = _measure(node)
    elif isinstance(node, Table):
        fn = _table(node, built)
    else:
        raise TypeError(f"cannot compile node {node!r}; names must be resolved first")
    return fn


def _math_error(name: str, offset: int, error: Exception) -> ExpressionError:
    if isinstance(error, OverflowError):
        return ExpressionError(f"overflow in {name!r}", offset)
    return ExpressionError(f"math domain error in {name!r}", offset)


def _op(node: Op, built: _Built) -> Scalar:
    if node.op in ("neg", "not"):
        fa = build_scalar(node.args[0], built)
        if node.op == "neg":
            return lambda t, s: -fa(t, s)
        return lambda t, s: 1.0 if fa(t, s) == 0.0 else 0.0
    if node.op in _ARITHMETIC:
        return _arithmetic(_ARITHMETIC[node.op], node, built)
    fa, fb = build_scalar(node.args[0], built), build_scalar(node.args[1], built)
    if node.op in _COMPARE:
        cmp = _COMPARE[node.op]
        return lambda t, s: 1.0 if cmp(fa(t, s), fb(t, s)) else 0.0
    if node.op == "and":
        return lambda t, s: 1.0 if fa(t, s) != 0.0 and fb(t, s) != 0.0 else 0.0
    if node.op == "or":
        return lambda t, s: 1.0 if fa(t, s) != 0.0 or fb(t, s) != 0.0 else 0.0
    if node.op == "/":
        return _divide(fa, fb, node.offset)
    if node.op == "**":
        return _power(fa, fb, node.offset)
    raise TypeError(f"unknown operator {node.op!r}")


def _arithmetic(op: Callable[[float, float], float], node: Op, built: _Built) -> Scalar:
    a, b = node.args
    if isinstance(a, Num):
        ca, fb = a.value, build_scalar(b, built)
        return lambda t, s: op(ca, fb(t, s))
    if isinstance(b, Num):
        fa, cb = build_scalar(a, built), b.value
        return lambda t, s: op(fa(t, s), cb)
    fa, fb = build_scalar(a, built), build_scalar(b, built)
    return lambda t, s: op(fa(t, s), fb(t, s))


def _divide(fa: Scalar, fb: Scalar, offset: int) -> Scalar:
    def divide(t: float, s: object) -> float:
        a, b = fa(t, s), fb(t, s)
        if b == 0.0:
            raise ExpressionError("division by zero", offset)
        return a / b

    return divide


def _power(fa: Scalar, fb: Scalar, offset: int) -> Scalar:
    def power(t: float, s: object) -> float:
        a, b = fa(t, s), fb(t, s)
        try:
            return math.pow(a, b)
        except (ValueError, OverflowError) as error:
            raise _math_error("**", offset, error) from None

    return power


def _call(node: Call, built: _Built) -> Scalar:
    spec = FUNCTIONS.get(node.func) or INTERNAL[node.func]
    f, args = spec.scalar, [build_scalar(a, built) for a in node.args]
    if len(args) == 1:
        (fa,) = args
        if not spec.guarded:
            return lambda t, s: f(fa(t, s))
        name, offset = node.func, node.offset

        def guarded(t: float, s: object) -> float:
            a = fa(t, s)
            try:
                return f(a)
            except (ValueError, OverflowError) as error:
                raise _math_error(name, offset, error) from None

        return guarded
    if len(args) == 2:
        fa, fb = args
        return lambda t, s: f(fa(t, s), fb(t, s))
    return lambda t, s: f(*[g(t, s) for g in args])


def _step(node: Call, built: _Built) -> Scalar:
    x, *rest = node.args
    numbers = [a.value for a in rest if isinstance(a, Num)]
    if len(numbers) != len(rest):
        fs = [build_scalar(a, built) for a in node.args]
        return lambda t, s: step(*[g(t, s) for g in fs])
    x0, h0, x1, h1 = numbers
    inv, dh = 1.0 / (x1 - x0), h1 - h0
    fx = build_scalar(x, built)

    def cubic(t: float, s: object) -> float:
        v = fx(t, s)
        if v <= x0:
            return h0
        if v >= x1:
            return h1
        u = (v - x0) * inv
        return h0 + dh * u * u * (3.0 - 2.0 * u)

    return cubic


def _measure(node: Measure) -> Scalar:
    get, label, offset = methodcaller(node.kind, *node.names), node.label(), node.offset

    def measure(t: float, s: object) -> float:
        if s is None:
            raise ExpressionError(f"{label} needs the mechanism state", offset)
        return get(s)

    return measure


def _table(node: Table, built: _Built) -> Scalar:
    fn, fa = node.fn, build_scalar(node.args[0], built)
    if fn is None:
        raise TypeError(f"table {node.name!r} is not resolved")
    return lambda t, s: float(fn(fa(t, s)))
