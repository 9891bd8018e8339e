"""Dimension inference of an expression tree (before names are resolved).

A dimension is a sorted tuple of (base dimension, power) pairs, `()` for a dimensionless
number, or None when it is not known (a number, a parameter written without a unit, a table
of bare numbers, `effort`). What is not known never makes an error: only two known
dimensions that must agree and do not (a sum, a comparison, the arguments of `min`, `step`,
`atan2` or `table`, a function that needs a plain number) or a power of a quantity with an
exponent that is not a constant.

Angles: radian is a base dimension (`[angle]`) so that `angle(hinge)` reads in rad and
`omega(hinge)` in rad/s, but, as in SI, an angle may meet a plain number: the agreement of
two dimensions ignores the power of `[angle]` (`sin(omega * t)`, `k_t * angle(j)`).

Numbers (`pi` too): in the expressions of motions, forces, events and requests a number is SI of
whatever the expression needs (`55*deg * t`: 55 is a rate; `100 * cos(angle(j))` in a force:
100 is in N), so a product with a number has no known dimension. In a numeric field given as
an expression of parameters (`inertia: ["0.5*m*r^2", ...]`), `coefficients=True`: a number
in a product is a plain coefficient, and in a sum takes the dimension of the other terms.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from ..foundation.units import describe_dimension
from .errors import ExpressionError
from .nodes import Call, Measure, Name, Node, Num, Op, Table, Time

__all__ = ["DimensionScope", "Dims", "infer_dimension", "same_dimension", "without_angle"]

Dims = tuple[tuple[str, float], ...]

_L, _T, _A, _M = "[length]", "[time]", "[angle]", "[mass]"
_TIME: Dims = ((_T, 1.0),)
_ANGLE: Dims = ((_A, 1.0),)
_MEASURES: dict[str, Dims | None] = {
    "angle": _ANGLE,
    "omega": ((_A, 1.0), (_T, -1.0)),
    "travel": ((_L, 1.0),),
    "speed": ((_L, 1.0), (_T, -1.0)),
    "dist": ((_L, 1.0),),
    **dict.fromkeys(("x", "y", "z"), ((_L, 1.0),)),
    **{f"v{axis}": ((_L, 1.0), (_T, -1.0)) for axis in ("x", "y", "z")},
    "effort": None,  # a torque or a force, by the motion's joint (`DimensionScope.efforts`)
}
_PLAIN_ARGUMENT = frozenset({"sin", "cos", "tan", "exp", "log", "asin", "acos", "atan"})
_ANGLE_RESULT = frozenset({"asin", "acos", "atan", "atan2"})
_SAME_AS_ARGUMENT = frozenset({"abs", "min", "max"})


def without_angle(dims: Dims) -> Dims:
    """`dims` without its power of `[angle]`."""
    return tuple(pair for pair in dims if pair[0] != _A)


def same_dimension(a: Dims, b: Dims) -> bool:
    """Whether two known dimensions agree (the power of `[angle]` aside)."""
    return without_angle(a) == without_angle(b)


def _make(powers: Mapping[str, float]) -> Dims:
    return tuple(sorted((k, float(v)) for k, v in powers.items() if abs(v) > 1e-12))


def _combine(a: Dims, b: Dims, sign: float) -> Dims:
    powers = dict(a)
    for base, power in b:
        powers[base] = powers.get(base, 0.0) + sign * power
    return _make(powers)


def _scaled(a: Dims, factor: float) -> Dims:
    return _make({base: power * factor for base, power in a})


@dataclass(frozen=True)
class DimensionScope:
    """What names mean: `names(name)` the dimension of a parameter, `pi` or unit name
    (None: not known); `tables[name]` the (x, y) dimensions of a table; `coefficients`:
    numbers in products are plain (see the module's docstring); `parameters` which names
    are parameters; `efforts` the dimension of `effort(M)` of each motion (a torque or a
    force, by its joint)."""

    names: Callable[[str], Dims | None]
    tables: Mapping[str, tuple[Dims | None, Dims | None]]
    coefficients: bool = False
    parameters: frozenset[str] = frozenset()  # the names that are parameters
    efforts: Mapping[str, Dims] = field(default_factory=dict)  # `effort(M)` by motion


@dataclass(frozen=True)
class _Term:
    dims: Dims | None
    number: bool = False  # a plain number (in `coefficients` mode: takes a sum's dimension)


def infer_dimension(tree: Node, scope: DimensionScope) -> Dims | None:
    """The dimension of `tree` (None if not known); ExpressionError at the offending
    operator or call when two known dimensions disagree."""
    return _Inference(scope).term(tree).dims


def _text(dims: Dims) -> str:
    return describe_dimension(dict(dims))


class _Inference:
    def __init__(self, scope: DimensionScope) -> None:
        self.scope = scope

    def term(self, node: Node) -> _Term:
        if isinstance(node, Num) or (isinstance(node, Name) and node.id == "pi"):
            # a number (pi too) may carry a unit: `sin(pi * t)`, pi in rad/s
            return _Term(() if self.scope.coefficients else None, number=True)
        if isinstance(node, Time):
            return _Term(_TIME)
        if isinstance(node, Name):
            if node.id == "t":
                return _Term(_TIME)
            return _Term(self.scope.names(node.id))
        if isinstance(node, Measure):
            if node.kind == "effort" and node.names:
                return _Term(self.scope.efforts.get(node.names[0]))
            return _Term(_MEASURES.get(node.kind))
        if isinstance(node, Table):
            return self.table(node)
        if isinstance(node, Op):
            return self.operation(node)
        if isinstance(node, Call):
            return self.call(node)
        return _Term(None)

    def agree(self, terms: list[_Term], offset: int, message: str) -> _Term:
        """The common dimension of terms that must agree (a sum, min, ...); `message` with
        `{a}` and `{b}` for the first two that do not."""
        known = [t for t in terms if t.dims is not None and not (t.number and t.dims == ())]
        for other in known[1:]:
            if not same_dimension(known[0].dims or (), other.dims or ()):
                raise ExpressionError(
                    message.format(a=_text(known[0].dims or ()), b=_text(other.dims or ())),
                    offset,
                )
        if known:
            return _Term(known[0].dims)
        return _Term(terms[0].dims if terms else None, number=all(t.number for t in terms))

    def operation(self, node: Op) -> _Term:
        terms = [self.term(arg) for arg in node.args]
        if node.op in ("neg",):
            return terms[0]
        if node.op in ("+", "-"):
            return self.agree(terms, node.offset, "cannot add {a} and {b}")
        if node.op in ("<", "<=", ">", ">=", "==", "!="):
            self.agree(terms, node.offset, "cannot compare {a} with {b}")
            return _Term(())
        if node.op in ("and", "or", "not"):
            return _Term(())
        if node.op in ("*", "/"):
            a, b = terms
            if a.dims is None or b.dims is None:
                return _Term(None)
            return _Term(_combine(a.dims, b.dims, 1.0 if node.op == "*" else -1.0))
        return self.power(node, terms)

    def power(self, node: Op, terms: list[_Term]) -> _Term:
        base, exponent = terms
        self.plain(exponent, node.offset, "an exponent")
        if base.dims is None:
            return _Term(None)
        value = _constant(node.args[1])
        if value is None:
            if without_angle(base.dims):
                raise ExpressionError(
                    f"a power of {_text(base.dims)} needs a number as exponent", node.offset
                )
            return _Term(())
        return _Term(_scaled(base.dims, value), number=base.number)

    def plain(self, term: _Term, offset: int, what: str) -> None:
        """ExpressionError if `term` has a known dimension other than a plain number or an
        angle."""
        if term.dims is not None and without_angle(term.dims):
            raise ExpressionError(
                f"{what} must be a plain number or an angle, not {_text(term.dims)}", offset
            )

    def call(self, node: Call) -> _Term:
        terms = [self.term(arg) for arg in node.args]
        func = node.func
        if func in _PLAIN_ARGUMENT:
            self.plain(terms[0], node.offset, f"the argument of '{func}'")
        if func == "atan2":
            self.agree(
                terms, node.offset, "'atan2' needs y and x of one dimension, not {a} and {b}"
            )
        if func in _ANGLE_RESULT:
            return _Term(_ANGLE)
        if func in _PLAIN_ARGUMENT or func == "sign":
            return _Term(())
        if func in _SAME_AS_ARGUMENT:
            return self.agree(
                terms,
                node.offset,
                f"'{func}' needs arguments of one dimension, not {{a}} and {{b}}",
            )
        if func == "sqrt":
            dims = terms[0].dims
            return _Term(None if dims is None else _scaled(dims, 0.5))
        if func == "step":
            self.agree(
                [terms[0], terms[1], terms[3]],
                node.offset,
                "'step' needs x, x0 and x1 of one dimension, not {a} and {b}",
            )
            return self.agree(
                [terms[2], terms[4]],
                node.offset,
                "'step' needs h0 and h1 of one dimension, not {a} and {b}",
            )
        return _Term(None)

    def table(self, node: Table) -> _Term:
        x_dims, y_dims = self.scope.tables.get(node.name, (None, None))
        argument = self.term(node.args[0]) if node.args else _Term(None)
        self.agree(
            [_Term(x_dims), argument],
            node.offset,
            f"table '{node.name}' has x in {{a}}, read at {{b}}",
        )
        return _Term(y_dims)


def _constant(node: Node) -> float | None:
    """The value of a constant exponent (a number, possibly negated), else None."""
    if isinstance(node, Num):
        return node.value if math.isfinite(node.value) else None
    if isinstance(node, Op) and node.op == "neg":
        inner = _constant(node.args[0])
        return None if inner is None else -inner
    return None
