"""Bench models of the kinds users run beyond rigid joints (issue 40 item 1): a contact-heavy
ball rattling in its socket, an event-heavy set of flaps falling onto latches, a hydraulic
actuator driving a mass, and a four-bar with springs, dampers and joint friction.

Each is one `ModelSpec` (the rigid part, as the jointed models) whose `extension` names its
module here; the module adds the rest to both codes from the same numbers: `extend_case`
to the `loads` case, `extend_exudyn` to the Exudyn system. `loads bench --kinds` runs them.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from benchmarks.models import ModelSpec

__all__ = ["KIND_MODULES", "kind_models"]

#: The modules of this package, one model each, in the order the bench runs them.
KIND_MODULES: tuple[str, ...] = ("socket", "latch", "fourbar_friction", "hydraulic")


def kind_models() -> list[ModelSpec]:
    """The bench models of this package."""
    return [import_module(f"benchmarks.kinds.{name}").spec() for name in KIND_MODULES]
