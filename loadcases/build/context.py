"""What every builder of a case's model reads and writes: the models, parameters, tables and
effects, the diagnostics found so far, and expressions compiled into guarded functions."""

from __future__ import annotations

from collections.abc import Callable

import mechlib as ml
from loadcases.expressions import CompiledExpression, ExpressionError, parse
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import FlexibleBody
from mechlib.model.joints import ROTATIONAL, TRANSLATIONAL
from mechlib.model.tables import Table, TableRangeError

__all__ = ["NOT_YET", "Builder", "Guarded"]

NOT_YET = "is not simulated by this version of loads yet"
_MEASURE_JOINTS = {
    "angle": ROTATIONAL,
    "omega": ROTATIONAL,
    "travel": TRANSLATIONAL,
    "speed": TRANSLATIONAL,
}


class Guarded:
    """The compiled expression `compiled`, its run-time errors (math, table range) turned
    into a solver failure that says which input and when."""

    def __init__(self, compiled: CompiledExpression, what: str):
        self.compiled, self.what = compiled, what

    def __call__(self, t: float, state=None) -> float:
        try:
            return self.compiled(t, state)
        except (ExpressionError, TableRangeError, ZeroDivisionError, OverflowError) as exc:
            raise ml.SolverFailure(
                f"{self.what}: {exc} at t = {t:.6g} s", time=t, where=(self.what,)
            ) from None


def _named_elsewhere(mechanism, case) -> set[str]:
    """Force elements a request or an event names: built even when their load is zero."""
    events = list(mechanism.events.values())
    if case is not None:
        events += list(case.events.values())
    names = {a.target for e in events for a in e.then if a.target}
    if case is not None:
        names |= {getattr(r, "force", None) for r in case.requests.values()}
    return names


class Builder:
    """Builds from a mechanism model and, when given, the case that uses it: the state the
    builders of bodies, joints, forces, contacts, motions, requests and events share.
    `built` is the mechlib mechanism once `loadcases.build.model` has made it."""

    built: ml.Mechanism

    def __init__(self, mechanism, parameters: dict[str, float], where: Callable, case=None):
        self.case, self.mech, self.parameters, self.where = case, mechanism, parameters, where
        self.problems: list[Diagnostic] = []
        effects = dict(case.effects) if case is not None else {}
        self.effects = {"gravity": True, "damping": True} | effects
        self.loads = case.loads if case is not None else None
        self.tables = {
            n: Table(n, t.x, t.y, t.interpolation, t.extrapolate)
            for n, t in self.mech.tables.items()
        }
        self.kept = _named_elsewhere(mechanism, case)

    def error(self, kind: str, key: str, message: str, hint: str | None = None) -> None:
        file, line, col = self.where(kind, key)
        self.problems.append(Diagnostic(file, line, col, key, message, hint=hint))

    def compile(self, text: str, what: str, kind: str = "mechanism") -> Guarded:
        return self.compile_tree(parse(text), what, kind)

    def compile_tree(self, expression, what: str, kind: str = "mechanism") -> Guarded:
        """A parsed expression (or part of one) compiled and guarded."""
        self._check_measures(expression, what, kind)
        try:
            compiled = expression.compile(self.parameters, self.tables)
        except ExpressionError as error:  # a constant part that overflows or divides by 0
            self.error(
                kind, what, f"invalid expression: {error.message} at character {error.offset + 1}"
            )
            compiled = parse("0").compile()
        return Guarded(compiled, what)

    def _check_measures(self, expression, what: str, kind: str) -> None:
        """angle/omega need a rotational joint, travel/speed a translational one, effort a
        motion of the case."""
        for measure, args in expression.measures():
            if measure == "effort" and args[0] not in (self.case.motions if self.case else {}):
                self.error(kind, what, f"effort({args[0]}): no motion '{args[0]}' in this case")
                continue
            types = _MEASURE_JOINTS.get(measure)
            joint = self.mech.joints.get(args[0]) if types else None
            if joint is not None and types and joint.type not in types:
                self.error(
                    kind,
                    what,
                    f"{measure}({args[0]}): joint '{args[0]}' is "
                    f"{joint.type}; {measure} needs a {' or '.join(types)} joint",
                )

    def body_owner(self, body: str) -> str:
        """The body a body name stands for: `BODY.POINT` (a flexible body's interface point,
        that node's rigid body) is on BODY."""
        for name, b in self.mech.bodies.items():
            if isinstance(b, FlexibleBody) and any(
                body == f"{name}.{point}" for point in b.flexible.points()
            ):
                return name
        return body
