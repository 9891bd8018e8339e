"""A servo-actuator's stroke demand held at one value: the command a compiled whole run
(mechlib.solvers.genalpha.run) can read once, exactly, instead of calling Python at every
step. Any other command (a function of time) keeps the runs' steps in Python."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

__all__ = ["HeldDemand", "held_value"]


@dataclass(frozen=True)
class HeldDemand:
    """The stroke demand `value` (m from the design length) at every time t (s)."""

    value: float
    constant: ClassVar[bool] = True  # the convention of a held coordinate's function

    def __call__(self, t: float) -> float:
        return self.value


def held_value(command) -> float | None:
    """The value (m) of a command held constant (`constant` True, as HeldDemand's), else
    None: a function of time, which only Python evaluates."""
    if not getattr(command, "constant", False):
        return None
    return float(command(0.0))
