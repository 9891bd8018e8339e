"""The safe expression language of case files (parsed here, never run as Python).

    step(t, 0, 0, 2, 90*deg)      crank_speed * t      angle(hinge) >= 113*deg
    table(wind_moment, angle(hinge))      sqrt(x(p)^2 + y(p)^2)

Numbers are SI; `t` is the time; `pi`, parameters and unit names (`deg`, `mm`, `kN`) are
constants. Operators: + - * / ** (or ^), unary -, comparisons (1.0 / 0.0), and, or, not.
Functions: sin cos tan asin acos atan atan2 sqrt abs min max sign exp log step.
State measures (bare names as arguments): angle omega travel speed (a joint),
dist (two points), x y z and vx vy vz (a point's position and velocity).
`table(name, x)` interpolates a named table.

    compiled = parse("crank_speed * t").compile({"crank_speed": 6.28})
    compiled(0.5)                  # -> 3.14
    compiled.derivative()(0.5)     # -> 6.28 (exact d/dt)
"""

from .errors import ExpressionError
from .expression import CompiledExpression, Expression, parse

__all__ = ["CompiledExpression", "Expression", "ExpressionError", "parse"]
