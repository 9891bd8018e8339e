"""Saddle patterns shared by the solves of one mechanism (a run and its accuracy companion).

The sparsity of [[M, phi_q^T], [phi_q, 0]] is found at a generic state (seeded: the same
state in every solve) from the mechanism's mass and its active equations alone: two systems
built from the same mechanism with the same active rows find the same pattern (and the same
compiled layout of it, `SaddlePattern.layout`). A `SolveMemo` keeps a `KnownPatterns` for
its solves; a pattern is shared only while a system has the equations it was built with (a
lock, an event's, adds one numbered in the order the events came: the same number may be
another joint's lock in another solve).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from mechlib.linalg.factor import SaddlePattern

__all__ = ["KnownPatterns", "generic_pattern", "known_pattern"]


class KnownPatterns:
    """The saddle patterns found by the solves of one mechanism, by kind of system (3-D or
    planar) and active rows."""

    def __init__(self) -> None:
        self.found: dict[tuple[str, bytes], SaddlePattern] = {}

    def attach(self, system: Any) -> None:
        """Let `system` (just built, before any event) share the patterns kept here."""
        system.known_patterns = (self, len(system.coordinates))


def known_pattern(system: Any) -> SaddlePattern:
    """The saddle pattern of `system`'s active rows (a `System` or a `PlanarSystem`):
    `generic_pattern`'s, or the one a solve of the same mechanism found for the same rows
    when the system is attached to a `KnownPatterns` and has made no lock since."""
    known = getattr(system, "known_patterns", None)
    if known is None or len(system.coordinates) != known[1]:
        return generic_pattern(system)
    key = (type(system).__name__, system.active.tobytes())
    pattern = known[0].found.get(key)
    if pattern is None:
        pattern = known[0].found[key] = generic_pattern(system)
    return pattern


def generic_pattern(system: Any) -> SaddlePattern:
    """Sparsity of [[M, phi_q^T], [phi_q, 0]] of `system`'s active rows, from a generic
    state (seeded: the same in every solve)."""
    from mechlib.linalg.factor import SaddlePattern  # here: `validate` imports no scipy

    rng = np.random.default_rng(7)
    q = system.design_q() + 0.1 * rng.standard_normal(system.nq)
    k = system.kin(q, rng.standard_normal(system.nq), 0.0)
    return SaddlePattern(system.mass(k), system.phi_q(k))
