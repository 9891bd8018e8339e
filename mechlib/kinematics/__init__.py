"""One state's kinematics: per-body arrays, the compiled constraint primitives and
rigid-body terms, constraint rows and their compiled arrays, joint coordinates, reactions
from the multipliers, and the read-only state view that force elements see."""
