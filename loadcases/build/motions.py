"""The case's motions: joint coordinates driven by functions of time, with the exact first
and second derivatives of their expressions."""

from __future__ import annotations

import mechlib as ml
from loadcases.build.context import Builder, Guarded
from loadcases.expressions import ExpressionError

__all__ = ["ExpressionMotion", "add_motions"]


class ExpressionMotion:
    """A motion's coordinate f(t) (rad or m) with exact d/dt and d2/dt2 of its expression."""

    def __init__(self, compiled, what: str = "motion"):
        self._f = Guarded(compiled, what)
        self._d1 = Guarded(compiled.derivative(), what)
        self._d2 = Guarded(compiled.derivative().derivative(), what)

    def value(self, t: float) -> float:
        return self._f(t)

    def rate(self, t: float) -> float:
        return self._d1(t)

    def accel(self, t: float) -> float:
        return self._d2(t)


def add_motions(b: Builder, m: ml.Mechanism) -> None:
    """The motions of the case (none without one), each a function of time only, or an
    error at its key."""
    for name, motion in (b.case.motions if b.case else {}).items():
        key = f"motions.{name}.value"
        fn = b.compile(motion.value, key, "case").compiled
        if not fn.time_only:
            b.error(
                "case",
                key,
                "a motion must be a function of "
                "time only (use a force element for state-dependent loads)",
            )
            continue
        try:
            function = ExpressionMotion(fn, key)
        except ExpressionError as error:  # its rate or acceleration divides by 0
            b.error("case", key, f"invalid expression: {error.message} in its time derivative")
            continue
        m.add_motion(name, joint=motion.joint, function=function)
