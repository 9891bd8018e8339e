"""Force elements: applied forces and springs, their grouped compiled evaluation and internal
states, and the domain elements of the source documents: joint friction, seals, dampers, cable
loops, bushings, table-driven spring laws, contact and hydraulics (SI units; docs/elements.md
has the equations). Each name is imported on first use: importing one element's module loads
none of the others."""

from __future__ import annotations

from typing import TYPE_CHECKING

from mechlib.core.lazy import lazy_names

if TYPE_CHECKING:
    from mechlib.elements.bushing import Bushing
    from mechlib.elements.cable_loop import CableLoop
    from mechlib.elements.damper import RotationalDamper
    from mechlib.elements.friction import JointFriction
    from mechlib.elements.joint_limit import JointLimit
    from mechlib.elements.laws import TableLaw
    from mechlib.elements.seal import Seal
    from mechlib.elements.series import SeriesLaw, series_stiffness

_HOMES = {
    "Bushing": "mechlib.elements.bushing",
    "CableLoop": "mechlib.elements.cable_loop",
    "JointFriction": "mechlib.elements.friction",
    "JointLimit": "mechlib.elements.joint_limit",
    "RotationalDamper": "mechlib.elements.damper",
    "Seal": "mechlib.elements.seal",
    "SeriesLaw": "mechlib.elements.series",
    "TableLaw": "mechlib.elements.laws",
    "series_stiffness": "mechlib.elements.series",
}

__all__ = [
    "Bushing",
    "CableLoop",
    "JointFriction",
    "JointLimit",
    "RotationalDamper",
    "Seal",
    "SeriesLaw",
    "TableLaw",
    "series_stiffness",
]

__getattr__, __dir__ = lazy_names(__name__, _HOMES, globals(), __all__)
