"""Tabulated functions y(x): akima, cubic or linear interpolation, explicit extrapolation."""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable
from functools import cached_property
from typing import Any

import numpy as np

__all__ = ["Table", "TableRangeError"]


class TableRangeError(ValueError):
    """x outside the data of a table that does not extrapolate."""


class Table:
    """y(x) from data (SI); `interpolation` akima|cubic|linear; `extrapolate`
    error|hold|linear outside [x_min, x_max]. `derivative()` gives dy/dx as a Table-like
    callable (used for exact time derivatives of expressions)."""

    def __init__(
        self,
        name: str,
        x,
        y,
        interpolation: str = "akima",
        extrapolate: str = "error",
        _order: int = 0,
    ):
        self.name, self.interpolation, self.extrapolate = name, interpolation, extrapolate
        self.x, self.y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        if self.x.ndim != 1 or self.x.shape != self.y.shape or len(self.x) < 2:
            raise ValueError(f"table '{name}' needs x and y of equal length >= 2")
        if np.any(np.diff(self.x) <= 0.0):
            raise ValueError(f"table '{name}': x must increase strictly")
        self._order = _order

    # The interpolant and its pieces are built on first use: a model that is only built and
    # checked (`loads validate`) imports no scipy.interpolate.
    @cached_property
    def _f(self) -> Callable:
        return self._interpolant()

    @cached_property
    def _pieces(self) -> tuple[list[float], list[tuple[float, ...]]]:
        return self._piecewise()

    def _interpolant(self) -> Callable:
        x, y = self.x, self.y
        if self.interpolation == "linear":
            slopes = np.diff(y) / np.diff(x)
            if self._order == 0:
                return lambda v: np.interp(v, x, y)
            if self._order == 1:
                return lambda v: slopes[
                    np.clip(np.searchsorted(x, v, "right") - 1, 0, len(slopes) - 1)
                ]
            return lambda v: np.zeros_like(np.asarray(v, float))
        from scipy.interpolate import Akima1DInterpolator, CubicSpline

        if self.interpolation == "cubic":
            base = CubicSpline(x, y, bc_type="not-a-knot" if len(x) > 3 else "natural")
        elif len(x) < 3:
            base = CubicSpline(x, y, bc_type="natural")
        else:
            base = Akima1DInterpolator(x, y)
        return base.derivative(self._order) if self._order else base

    def _piecewise(self) -> tuple[list[float], list[tuple[float, ...]]]:
        """(breakpoints, per interval the polynomial's coefficients, lowest power first) of
        the interpolant, as Python floats: one value costs a bisection and a few products
        instead of a scipy call (the door's seal and latch laws are called per station and
        per column of the differenced tangent)."""
        if self.interpolation == "linear":
            x, y = self.x, self.y
            slopes = np.diff(y) / np.diff(x)
            if self._order == 0:
                coefs = np.column_stack((y[:-1], slopes))
            elif self._order == 1:
                coefs = slopes[:, None]
            else:
                coefs = np.zeros((len(slopes), 1))
            return x.tolist(), [tuple(row) for row in coefs.tolist()]
        spline: Any = self._f  # a scipy PPoly: c[k, i] multiplies (v - x_i)^(K - 1 - k)
        return spline.x.tolist(), [tuple(col[::-1]) for col in spline.c.T.tolist()]

    def _value(self, v: float) -> float:
        """The interpolant at v within the data (the same sum as scipy's PPoly)."""
        breaks, pieces = self._pieces
        if v == breaks[-1] and self.interpolation == "linear" and self._order == 0:
            return float(self.y[-1])  # np.interp's value there (the sum may be an ulp off)
        i = min(max(bisect_right(breaks, v) - 1, 0), len(pieces) - 1)
        d, power, out = v - breaks[i], 1.0, 0.0
        for c in pieces[i]:
            out += c * power
            power *= d
        return out

    def __call__(self, v: float) -> float:
        lo, hi = self.x[0], self.x[-1]
        if lo <= v <= hi:
            return self._value(float(v))
        if self.extrapolate == "error":
            raise TableRangeError(
                f"table '{self.name}': x = {v:.6g} is outside its data "
                f"[{lo:.6g}, {hi:.6g}] (set extrapolate: hold or linear)"
            )
        end = lo if v < lo else hi
        value, slope = self._ends[0 if v < lo else 1]
        if self.extrapolate == "hold":
            return value if self._order == 0 else 0.0
        if self._order == 0:
            return value + slope * (v - end)
        return value if self._order == 1 else 0.0  # the line's slope is y' at the end

    @cached_property
    def packed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The table as `table_value` (mechlib.model.table_kernel) evaluates it: (breakpoints,
        coefficients (pieces, powers; lowest power first), (value, slope) at the first
        and the last x (2, 2), [extrapolation: 0 error, 1 hold, 2 linear; order; 1 where
        x[-1] gives y[-1] itself (a linear table's value)])."""
        breaks, pieces = self._pieces
        mode = ("error", "hold", "linear").index(self.extrapolate)
        exact = int(self.interpolation == "linear" and self._order == 0)
        return (
            np.array(breaks, dtype=float),
            np.array(pieces, dtype=float).reshape(len(pieces), -1),
            np.array(self._ends, dtype=float),
            np.array([mode, self._order, exact], dtype=np.int64),
        )

    @cached_property
    def _ends(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """(value, slope) of the interpolant at the first and the last x, which the
        extrapolation continues: found once (the slope's interpolant is a table of its own;
        a tabulated spring outside its data asks at every force evaluation)."""
        return tuple(  # type: ignore[return-value]
            (float(self._f(end)), float(self._slope_at(end))) for end in (self.x[0], self.x[-1])
        )

    def _slope_at(self, end: float) -> float:
        d = Table(self.name, self.x, self.y, self.interpolation, "hold", self._order + 1)
        return d._f(end) if self._order == 0 else (d._f(end) if self._order == 1 else 0.0)

    def integral(self, a: float, b: float) -> float:
        """The exact integral of y(x) over [a, b] (x's unit times y's): the interpolant is
        piecewise linear or cubic, so its integral is closed-form; outside the data the
        extrapolation (held value or line) is integrated too, `error` raises."""
        return self._primitive(b) - self._primitive(a)

    def _primitive(self, v: float) -> float:
        """Integral of y from x[0] to v (negative below x[0])."""
        lo, hi = self.x[0], self.x[-1]
        if v < lo:
            return self._beyond(lo, v)
        if v > hi:
            return self._inside(hi) + self._beyond(hi, v)
        return self._inside(v)

    def _inside(self, v: float) -> float:
        """Integral of the interpolant from x[0] to v in [x[0], x[-1]]."""
        if self.interpolation != "linear":
            spline: Any = self._f  # a scipy PPoly (CubicSpline, Akima1DInterpolator)
            return float(spline.integrate(self.x[0], v))
        x, y = self.x, self.y
        slopes, knots = self._linear_primitive
        i = int(np.clip(np.searchsorted(x, v, "right") - 1, 0, len(slopes) - 1))
        d = v - x[i]
        return float(knots[i] + y[i] * d + 0.5 * slopes[i] * d * d)

    @cached_property
    def _linear_primitive(self) -> tuple[np.ndarray, np.ndarray]:
        """(slope of each interval, integral from x[0] to each point) of the linear table."""
        x, y = self.x, self.y
        knots = np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])
        return np.diff(y) / np.diff(x), knots

    def _beyond(self, end: float, v: float) -> float:
        """Integral of the extrapolation (a held value or a line) from the data's `end` to
        v beyond it: the trapezoid, exact for both; `self(v)` raises outside the data of a
        table that does not extrapolate."""
        return 0.5 * (v - end) * (float(self._f(end)) + float(self(v)))

    def derivative(self) -> Table:
        """dy/dx with the same extrapolation rule (held value -> zero slope)."""
        return Table(
            self.name, self.x, self.y, self.interpolation, self.extrapolate, self._order + 1
        )
