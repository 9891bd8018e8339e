"""Which force elements a forward-difference column of the tangent can change.

A column perturbs one coordinate of q (or qd). The elements that join two bodies
(contacts, seals: `body_pair()`) depend on those two bodies' states alone, so the column of
another body's coordinate leaves them out: their forces are the same at the base and at the
perturbed state. The other elements (springs, point forces, joint friction, actuators, whose
laws may read any measure) are evaluated for every column. A modal coordinate moves no
body: its columns leave out only what is always left out. Shared by the static stiffness
(mechlib.balance) and the dynamic tangent (mechlib.genalpha), where the two-body elements
cost most of a force evaluation (the door: 5 contacts and 2 seals, 80 % of it).
"""

from __future__ import annotations

from mechlib.system import System

__all__ = ["ColumnSkips"]


class ColumnSkips:
    """Per column of q: the ids of the elements its forward difference leaves out (those in
    `always`, e.g. the elements that add their own tangent, and the two-body elements of
    other bodies)."""

    def __init__(self, system: System, always: set[int] | frozenset[int] = frozenset()):
        pairs = [(id(e), e.body_pair()) for e in system.elements if hasattr(e, "body_pair")]
        self._per_body = system.per_body
        self._rigid = system.per_body * system.nb
        self._of_body = {
            b: frozenset({i for i, pair in pairs if b not in pair} | set(always))
            for b in range(system.nb)
        }
        self._of_body[-1] = frozenset(always)

    def body(self, column: int) -> int:
        """The body whose coordinate `column` is; -1 for a modal coordinate."""
        return column // self._per_body if column < self._rigid else -1

    def skip(self, body: int) -> frozenset[int]:
        """The element ids a column of `body` (-1: modal) leaves out."""
        return self._of_body[body]
