"""Tabulated functions (mechlib.model.tables.Table): values and slopes against the interpolants
of NumPy and SciPy built independently in the test (np.interp, CubicSpline with the same
end conditions, Akima1DInterpolator), at the data points and at random points inside."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import Akima1DInterpolator, CubicSpline

from mechlib.model.tables import Table, TableRangeError

RNG = np.random.default_rng(7)
X = np.sort(RNG.uniform(0.0, 10.0, 12))
Y = RNG.normal(size=12)
POINTS = np.r_[X, RNG.uniform(X[0], X[-1], 500)]


def _reference(interpolation: str, order: int):
    if interpolation == "linear":
        slopes = np.diff(Y) / np.diff(X)
        if order == 0:
            return lambda v: np.interp(v, X, Y)
        if order == 1:
            return lambda v: slopes[min(max(np.searchsorted(X, v, "right") - 1, 0), 10)]
        return lambda v: 0.0
    spline = CubicSpline(X, Y) if interpolation == "cubic" else Akima1DInterpolator(X, Y)
    return spline.derivative(order) if order else spline


@pytest.mark.parametrize("interpolation", ["linear", "cubic", "akima"])
@pytest.mark.parametrize("order", [0, 1, 2])
def test_table_matches_the_interpolant(interpolation: str, order: int) -> None:
    """Value (order 0), slope (1) and curvature (2) inside the data: equal to the reference
    within 1e-14 of its largest magnitude (measured: bit-identical, the same sums)."""
    table = Table("t", X, Y, interpolation, "error", order)
    reference = _reference(interpolation, order)
    got = np.array([table(v) for v in POINTS])
    want = np.array([float(reference(v)) for v in POINTS])
    assert np.abs(got - want).max() <= 1e-14 * max(np.abs(want).max(), 1.0)


def test_table_outside_its_data() -> None:
    """`hold` keeps the end value, `linear` continues the end slope, `error` refuses."""
    akima = Akima1DInterpolator(X, Y)
    slope = float(akima.derivative(1)(X[-1]))
    assert Table("t", X, Y, "akima", "hold")(X[-1] + 1.0) == pytest.approx(Y[-1], abs=1e-14)
    assert Table("t", X, Y, "akima", "linear")(X[-1] + 2.0) == pytest.approx(
        Y[-1] + 2.0 * slope, abs=1e-12
    )
    with pytest.raises(TableRangeError):
        Table("t", X, Y, "akima", "error")(X[0] - 1e-6)


def test_linear_table_at_its_last_point_is_its_last_value() -> None:
    """At x[-1] a linear table gives y[-1] exactly, as np.interp does (the last piece's
    sum y[-2] + slope (x[-1] - x[-2]) may be an ulp off)."""
    x, y = np.array([0.0, 0.1, 0.3]), np.array([0.0, 0.7, 0.1])
    assert Table("t", x, y, "linear", "error")(0.3) == 0.1
    assert Table("t", X, Y, "linear", "hold")(X[-1]) == Y[-1]


@pytest.mark.parametrize("interpolation", ["linear", "cubic", "akima"])
def test_extrapolation_at_both_ends(interpolation: str) -> None:
    """Below x[0] and above x[-1], many times over (the end values and slopes are found
    once): `linear` continues the reference's value at that end with its slope there, and
    the table's derivative() is that slope (it gave the end's curvature before 0.10.0: 0 for
    a linear table), its second derivative 0; `hold` keeps the end value, slope 0. Within
    1e-12 of the largest magnitude; the derivative also against a central difference of
    the table (1e-6)."""
    reference, slope = _reference(interpolation, 0), _reference(interpolation, 1)
    linear = Table("t", X, Y, interpolation, "linear")
    hold = Table("t", X, Y, interpolation, "hold")
    rate, curvature = linear.derivative(), linear.derivative().derivative()
    for end, beyond in ((X[0], X[0] - np.r_[1e-3, 0.5, 3.0]), (X[-1], X[-1] + np.r_[1e-3, 2.0])):
        value, tangent = float(reference(end)), float(slope(end))
        for v in np.r_[beyond, beyond]:
            want = value + tangent * (v - end)
            assert linear(v) == pytest.approx(want, abs=1e-12 * max(abs(want), 1.0))
            assert rate(v) == pytest.approx(tangent, abs=1e-12 * max(abs(tangent), 1.0))
            assert curvature(v) == 0.0
            h = 1e-6
            assert (linear(v + h) - linear(v - h)) / (2 * h) == pytest.approx(tangent, abs=1e-6)
            assert hold(v) == pytest.approx(value, abs=1e-12)
            assert hold.derivative()(v) == 0.0


@pytest.mark.parametrize("interpolation", ["linear", "cubic", "akima"])
@pytest.mark.parametrize("extrapolate", ["error", "hold", "linear"])
@pytest.mark.parametrize("order", [0, 1, 2])
def test_compiled_table_value_is_the_tables(interpolation, extrapolate, order) -> None:
    """mechlib.model.table_kernel.table_value of Table.packed (compiled: the tabulated torsion
    spring's law) gives the table's own value, bit for bit, inside (the data points, the
    last one included, and random points), at and beyond both ends; where the table
    refuses a value (extrapolate: error), it says so instead of a value."""
    from mechlib.model.table_kernel import table_value

    table = Table("t", X, Y, interpolation, extrapolate, order)
    points = np.r_[POINTS, X[0] - np.r_[1e-9, 0.3, 4.0], X[-1] + np.r_[1e-9, 2.0], np.nan]
    for v in points:
        ok, value = table_value(*table.packed, float(v))
        try:
            want = table(float(v))
        except TableRangeError:
            assert not ok, v
            continue
        assert ok, v
        assert value == want or (np.isnan(value) and np.isnan(want)), (v, value, want)
