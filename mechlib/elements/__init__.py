"""Domain force elements of the source documents: joint friction, seals, dampers, cable loops,
bushings and table-driven spring laws (SI units; see docs/elements.md for the equations)."""

from mechlib.elements.bushing import Bushing
from mechlib.elements.cable_loop import CableLoop
from mechlib.elements.damper import RotationalDamper
from mechlib.elements.friction import JointFriction
from mechlib.elements.laws import TableLaw
from mechlib.elements.seal import Seal
from mechlib.elements.series import SeriesLaw, series_stiffness

__all__ = [
    "Bushing",
    "CableLoop",
    "JointFriction",
    "RotationalDamper",
    "Seal",
    "SeriesLaw",
    "TableLaw",
    "series_stiffness",
]
