"""The functions of the language: names, arities, scalar and numpy implementations.

`step(x, x0, h0, x1, h1)` is the cubic step of MSC Adams: h0 for x <= x0, h1 for x >= x1,
else h0 + (h1 - h0) * s**2 * (3 - 2 s) with s = (x - x0) / (x1 - x0). Its derivatives use
the internal `_smooth` family (the step from 0 to 1 over s in [0, 1] and its derivatives).
`_minsel(a1..an, v1..vn)` / `_maxsel` give the v of the smallest / largest a: the
piecewise derivatives of `min` and `max`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import reduce

import numpy as np

from mechlib.core.smooth import step  # the one cubic step of loads (seed 004 eq. 3.10)

__all__ = [
    "FUNCTIONS",
    "INTERNAL",
    "MEASURES",
    "FunctionSpec",
    "d2smooth",
    "d3smooth",
    "dsmooth",
    "maxsel",
    "minsel",
    "sign",
    "smooth",
    "step",
]

# Measure name -> (number of name arguments, what each argument names).
MEASURES: dict[str, tuple[int, str]] = {
    "angle": (1, "joint"),
    "omega": (1, "joint"),
    "travel": (1, "joint"),
    "speed": (1, "joint"),
    "dist": (2, "point"),
    "x": (1, "point"),
    "y": (1, "point"),
    "z": (1, "point"),
    "vx": (1, "point"),
    "vy": (1, "point"),
    "vz": (1, "point"),
    "effort": (1, "motion"),
}


@dataclass(frozen=True)
class FunctionSpec:
    """A function: `arity` exact, or the minimum when `variadic`; `guarded` functions can
    raise ValueError / OverflowError (math domain or range), reported with their name."""

    arity: int
    scalar: Callable[..., float]
    vector: Callable[..., np.ndarray]
    variadic: bool = False
    guarded: bool = False


def sign(x: float) -> float:
    """-1, 0 or 1."""
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


def smooth(s: float) -> float:
    """0 for s <= 0, 1 for s >= 1, s^2 (3 - 2 s) between."""
    return 0.0 if s <= 0.0 else (1.0 if s >= 1.0 else s * s * (3.0 - 2.0 * s))


def dsmooth(s: float) -> float:
    """d smooth / ds: 6 s (1 - s) inside (0, 1), else 0."""
    return 6.0 * s * (1.0 - s) if 0.0 < s < 1.0 else 0.0


def d2smooth(s: float) -> float:
    """d2 smooth / ds2: 6 - 12 s inside (0, 1), else 0."""
    return 6.0 - 12.0 * s if 0.0 < s < 1.0 else 0.0


def d3smooth(s: float) -> float:
    """d3 smooth / ds3: -12 inside (0, 1), else 0."""
    return -12.0 if 0.0 < s < 1.0 else 0.0


def minsel(*args: float) -> float:
    """The second-half value paired with the smallest first-half value (first on ties)."""
    n = len(args) // 2
    keys = args[:n]
    return args[n + keys.index(min(keys))]


def maxsel(*args: float) -> float:
    """The second-half value paired with the largest first-half value (first on ties)."""
    n = len(args) // 2
    keys = args[:n]
    return args[n + keys.index(max(keys))]


def _v_step(x, x0, h0, x1, h1):
    with np.errstate(all="ignore"):
        s = (x - x0) / (x1 - x0)
        inner = h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)
    return np.where(x <= x0, h0, np.where(x >= x1, h1, inner))


def _inside(s, value, outside):
    return np.where((s > 0.0) & (s < 1.0), value, outside)


def _v_smooth(s):
    return np.where(s <= 0.0, 0.0, np.where(s >= 1.0, 1.0, s * s * (3.0 - 2.0 * s)))


def _v_select(pick):
    def select(*args):
        n = len(args) // 2
        arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in args))
        keys, values = np.stack(arrays[:n]), np.stack(arrays[n:])
        index = pick(keys, axis=0)
        return np.take_along_axis(values, index[np.newaxis], axis=0)[0]

    return select


def _v_sign(x):
    return np.sign(np.asarray(x, dtype=float))


FUNCTIONS: dict[str, FunctionSpec] = {
    "sin": FunctionSpec(1, math.sin, np.sin, guarded=True),
    "cos": FunctionSpec(1, math.cos, np.cos, guarded=True),
    "tan": FunctionSpec(1, math.tan, np.tan, guarded=True),
    "asin": FunctionSpec(1, math.asin, np.arcsin, guarded=True),
    "acos": FunctionSpec(1, math.acos, np.arccos, guarded=True),
    "atan": FunctionSpec(1, math.atan, np.arctan),
    "atan2": FunctionSpec(2, math.atan2, np.arctan2),
    "sqrt": FunctionSpec(1, math.sqrt, np.sqrt, guarded=True),
    "abs": FunctionSpec(1, math.fabs, np.abs),
    "min": FunctionSpec(2, min, lambda *a: reduce(np.minimum, a), variadic=True),
    "max": FunctionSpec(2, max, lambda *a: reduce(np.maximum, a), variadic=True),
    "sign": FunctionSpec(1, sign, _v_sign),
    "exp": FunctionSpec(1, math.exp, np.exp, guarded=True),
    "log": FunctionSpec(1, math.log, np.log, guarded=True),
    "step": FunctionSpec(5, step, _v_step),
}

INTERNAL: dict[str, FunctionSpec] = {
    "_smooth": FunctionSpec(1, smooth, _v_smooth),
    "_dsmooth": FunctionSpec(1, dsmooth, lambda s: _inside(s, 6.0 * s * (1.0 - s), 0.0)),
    "_d2smooth": FunctionSpec(1, d2smooth, lambda s: _inside(s, 6.0 - 12.0 * s, 0.0)),
    "_d3smooth": FunctionSpec(1, d3smooth, lambda s: _inside(s, -12.0, 0.0)),
    "_minsel": FunctionSpec(2, minsel, _v_select(np.argmin), variadic=True),
    "_maxsel": FunctionSpec(2, maxsel, _v_select(np.argmax), variadic=True),
}
