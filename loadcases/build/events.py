"""Events of a mechanism (`events:`) as mechlib events: the `when` condition as a function
that crosses zero at the event, the `then` actions checked against the model."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import mechlib as ml
from loadcases.expressions import Expression, ExpressionError, parse
from loadcases.expressions.nodes import Op
from loadcases.schema.errors import did_you_mean

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
            condition = None
            if e.when is not None:
                try:
                    condition = _condition(builder, e.when, f"events.{name}.when", kind)
                except ExpressionError as error:
                    builder.error(
                        kind, f"events.{name}.when", f"invalid condition: {error.message}"
                    )
                    continue
            elif not _check_after(builder, kind, name):
                continue
            if not all(checked):
                continue
            actions = tuple(ml.Action(a.action, a.target) for a in e.then)
            after, delay = (e.after.event, e.after.delay) if e.after else (None, 0.0)
            events.append(ml.Event(name, condition, actions, after=after, delay=delay))
    return events


def _all_events(builder) -> dict:
    """The events of the mechanism and of the case by name."""
    found = dict(builder.mech.events)
    if builder.case is not None:
        found.update(builder.case.events)
    return found


def _check_after(builder, kind: str, name: str) -> bool:
    """An `after:` names another event, and the chain of events it follows starts at a
    `when:` condition (a loop of delayed events would never fire)."""
    known = _all_events(builder)
    key = f"events.{name}.after.event"
    seen = [name]
    follows = known[name].after.event
    while follows not in seen:
        if follows not in known:
            hint = did_you_mean(follows, [n for n in known if n != name])
            builder.error(kind, key, f"unknown event '{follows}'", hint=hint)
            return False
        seen.append(follows)
        if known[follows].after is None:
            return True
        follows = known[follows].after.event
    chain = " -> ".join([*seen, follows])
    builder.error(kind, key, f"events that follow each other in a loop never fire ({chain})")
    return False
