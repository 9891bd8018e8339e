"""Time-only trees to numpy closures `f(t_array) -> array` (for plots).

Math errors give nan or inf here (numpy semantics), not exceptions.
"""

from __future__ import annotations

import operator
from collections.abc import Callable

import numpy as np

from .functions import FUNCTIONS, INTERNAL
from .nodes import Call, Node, Num, Op, Table, Time, once

__all__ = ["Vector", "build_vector"]

Vector = Callable[[np.ndarray], "np.ndarray | float"]

_BINARY: dict[str, Callable] = {
    "+": operator.add,
    "-": operator.sub,
    "*": operator.mul,
    "/": np.divide,
    "**": np.float_power,
    "<": np.less,
    "<=": np.less_equal,
    ">": np.greater,
    ">=": np.greater_equal,
    "==": np.equal,
    "!=": np.not_equal,
    "and": lambda a, b: np.logical_and(a != 0.0, b != 0.0),
    "or": lambda a, b: np.logical_or(a != 0.0, b != 0.0),
}
_UNARY: dict[str, Callable] = {"neg": operator.neg, "not": lambda a: np.equal(a, 0.0)}


_Built = dict[int, tuple[Node, Vector]]


def build_vector(node: Node, built: _Built | None = None) -> Vector:
    """The closure computing a time-only `node` for an array of times; `built` holds the
    closures made so far in this build, by node id (a shared sub-tree becomes one)."""
    memo: _Built = {} if built is None else built
    return once(memo, node, lambda n: _build(n, memo))


def _build(node: Node, built: _Built) -> Vector:
    if isinstance(node, Num):
        value = node.value
        return lambda t: value
    if isinstance(node, Time):
        return lambda t: t
    if isinstance(node, Op):
        return _op(node, built)
    if isinstance(node, Call):
        spec = FUNCTIONS.get(node.func) or INTERNAL[node.func]
        f, args = spec.vector, [build_vector(a, built) for a in node.args]
        return lambda t: f(*[g(t) for g in args])
    if isinstance(node, Table):
        fn, fa = node.fn, build_vector(node.args[0], built)
        if fn is None:
            raise TypeError(f"table {node.name!r} is not resolved")
        each = np.vectorize(lambda x: float(fn(x)), otypes=[float])
        return lambda t: each(fa(t))
    raise TypeError(f"cannot vectorise node {node!r}")


def _op(node: Op, built: _Built) -> Vector:
    args = [build_vector(a, built) for a in node.args]
    if len(args) == 1:
        f1, (fa,) = _UNARY[node.op], args
        return lambda t: np.asarray(f1(fa(t)), dtype=float)
    f2, (fa, fb) = _BINARY[node.op], args
    return lambda t: np.asarray(f2(fa(t), fb(t)), dtype=float)
