"""Which force elements a forward-difference column of the tangent can change.

A column perturbs one coordinate of q (or qd): of one body, or a modal coordinate. An
element that knows the bodies its force depends on (`state_bodies()`: the body indices
whose positions and rates it reads, and it reads no modal coordinate; None or no such
method: unknown) is left out of the columns of every other body: its force is the same at
the base and at the perturbed state. So are contacts and seals (their two bodies), springs,
torsion springs, dampers, bushings and cable loops (the bodies they join), and point forces
and torques (their body, their frame's body and the bodies their value's measures read).
The others are evaluated in every column: joint friction (it reads the multipliers),
elements with internal states, and a load whose value reads a motion's effort. A modal
coordinate moves no body: its columns leave out every element with known bodies. Shared by
the static stiffness (mechlib.balance) and the dynamic tangent (mechlib.genalpha).
"""

from __future__ import annotations

from mechlib.system import System

__all__ = ["ColumnSkips", "element_bodies"]


def element_bodies(element) -> frozenset[int] | None:
    """The body indices (ground harmless) an element's force depends on; None: unknown."""
    bodies = getattr(element, "state_bodies", None)
    found = bodies() if bodies is not None else None
    return None if found is None else frozenset(int(b) for b in found)


class ColumnSkips:
    """Per column of q: the ids of the elements its forward difference leaves out (those in
    `always`, e.g. the elements that add their own tangent, and the elements whose force
    depends on other bodies only)."""

    def __init__(self, system: System, always: set[int] | frozenset[int] = frozenset()):
        known = [(id(e), b) for e in system.elements if (b := element_bodies(e)) is not None]
        self._per_body = system.per_body
        self._rigid = system.per_body * system.nb
        self._of_body = {
            b: frozenset({i for i, bodies in known if b not in bodies} | set(always))
            for b in range(system.nb)
        }
        self._of_body[-1] = frozenset({i for i, _ in known} | set(always))

    def body(self, column: int) -> int:
        """The body whose coordinate `column` is; -1 for a modal coordinate."""
        return column // self._per_body if column < self._rigid else -1

    def skip(self, body: int) -> frozenset[int]:
        """The element ids a column of `body` (-1: modal) leaves out."""
        return self._of_body[body]
