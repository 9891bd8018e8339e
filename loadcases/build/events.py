"""Events of a mechanism (`events:`) as mechlib events: the `when` condition as a function
that crosses zero at the event, the `then` actions checked against the model."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import mechlib as ml
from loadcases.expressions import Expression, ExpressionError, parse
from loadcases.expressions.nodes import Op

__all__ = ["build_events"]

_COORDINATE_JOINTS = ("revolute", "prismatic", "cylindrical", "screw")


def _condition(
    builder, text: str, what: str, kind: str = "mechanism"
) -> Callable[[float, Any], float]:
    """g(t, state): lhs - rhs for `lhs >= rhs` (rhs - lhs for <=), so that a located zero
    is the event time; any other condition gives -1 (false) / +1 (true), located by
    bisection."""
    expression = parse(text)
    tree = expression.tree
    if isinstance(tree, Op) and tree.op in (">=", ">", "<=", "<", "=="):
        lhs, rhs = (builder.compile_tree(Expression(text, node), what, kind) for node in tree.args)
        sign = -1.0 if tree.op in ("<=", "<") else 1.0
        return lambda t, view: sign * (lhs(t, view) - rhs(t, view))
    truth = builder.compile(text, what, kind)
    return lambda t, view: 1.0 if truth(t, view) else -1.0


def _check_action(builder, kind: str, name: str, i: int, action) -> bool:
    key = f"events.{name}.then[{i}]"
    mech, case = builder.mech, builder.case
    target = action.target
    if action.action in ("activate", "deactivate"):
        known = {*mech.forces, *mech.contacts, *mech.limits, *(case.motions if case else ())}
        if target not in known:
            builder.error(
                kind,
                key,
                f"'{target}' is not a force element, contact, limit or motion of this case",
            )
            return False
    elif action.action in ("release", "lock"):
        joint = mech.joints.get(target)
        if joint is None:
            builder.error(kind, key, f"unknown joint '{target}'")
            return False
        if action.action == "lock" and joint.type not in _COORDINATE_JOINTS:
            builder.error(
                kind,
                key,
                f"lock needs a joint with a coordinate "
                f"({', '.join(_COORDINATE_JOINTS)}); '{target}' is {joint.type}",
            )
            return False
    return True


def build_events(builder) -> list[ml.Event]:
    """mechlib events of the mechanism and of the case; problems go to the builder's
    diagnostics (at the file and key of each event)."""
    sources = [("mechanism", builder.mech.events)]
    if builder.case is not None:
        sources.append(("case", builder.case.events))
    events = []
    for kind, found in sources:
        for name, e in found.items():
            if kind == "case" and name in builder.mech.events:
                builder.error(
                    "case",
                    f"events.{name}",
                    f"event '{name}' is also an event of the mechanism: names must be unique",
                )
                continue
            checked = [_check_action(builder, kind, name, i, a) for i, a in enumerate(e.then)]
            try:
                condition = _condition(builder, e.when, f"events.{name}.when", kind)
            except ExpressionError as error:
                builder.error(kind, f"events.{name}.when", f"invalid condition: {error.message}")
                continue
            if not all(checked):
                continue
            actions = tuple(ml.Action(a.action, a.target) for a in e.then)
            events.append(ml.Event(name, condition, actions))
    return events
