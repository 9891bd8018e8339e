"""Units: quantities to SI floats, file units for bare numbers, angles as a dimension."""

from __future__ import annotations

import math

import pytest

from loadcases.units import UnitError, check_unit_name, to_si, unit_constant, vector_to_si

MM_DEG = {"length": "mm", "angle": "deg"}


@pytest.mark.parametrize(
    ("value", "dimension", "expected"),
    [
        ("110 mm", "length", 0.11),
        ("35 deg", "angle", 0.6108652382),
        ("12 N/mm", "stiffness", 12000.0),
        ("1334 N", "force", 1334.0),
        ("60 knot", "velocity", 30.8666667),
        ("2 A/m", "any", 2.0),
        ("360 deg/s", "angular_velocity", 2 * math.pi),
        ("10 rpm", "angular_velocity", math.pi / 3),
        ("50 N*m/rad", "torsional_stiffness", 50.0),
        ("50 N*m", "torsional_stiffness", 50.0),  # per radian implied
        ("1.0e7", "stiffness", 1.0e7),
        ("1 bar", "pressure", 1.0e5),
        ("5 kN", "force", 5000.0),
        ("10 %", "dimensionless", 0.1),
        ("2 t", "mass", 2000.0),
        (3, "length", 3.0),
    ],
)
def test_to_si(value: object, dimension: str, expected: float) -> None:
    assert to_si(value, dimension, None) == pytest.approx(expected, abs=1e-4, rel=1e-9)


def test_file_units_apply_to_bare_numbers_of_their_kind_only() -> None:
    assert to_si(110, "length", MM_DEG) == pytest.approx(0.11)
    assert to_si("35", "angle", MM_DEG) == pytest.approx(math.radians(35))
    assert to_si(2.0e6, "stiffness", MM_DEG) == pytest.approx(2.0e6)  # compound: SI
    assert to_si(2, "angular_velocity", MM_DEG) == pytest.approx(2.0)
    assert to_si("1 m", "length", MM_DEG) == pytest.approx(1.0)  # explicit unit wins
    assert to_si(3, "force", {"force": "kN"}) == pytest.approx(3000.0)


@pytest.mark.parametrize(
    ("value", "dimension", "message"),
    [
        ("12 kg", "length", "expected a length, got '12 kg' (a mass)"),
        ("3 m", "angle", "expected an angle, got '3 m' (a length)"),
        ("1 deg", "dimensionless", "expected a dimensionless number, got '1 deg' (an angle)"),
        (
            "50 N/m",
            "torsional_stiffness",
            "expected a torsional stiffness, got '50 N/m' (a stiffness)",
        ),
        ("3 N/deg", "stiffness", "expected a stiffness, got '3 N/deg' (units of kg*m/rad/s**2)"),
        ("3 foo", "length", "cannot read '3 foo': unknown unit 'foo'"),
        ("mm", "length", "cannot read 'mm': expected a number with a unit, like '110 mm'"),
        ("1 m/", "length", "cannot read '1 m/': not a quantity"),
        (True, "length", "expected a number or a quantity text, got true"),
    ],
)
def test_wrong_values(value: object, dimension: str, message: str) -> None:
    with pytest.raises(UnitError) as raised:
        to_si(value, dimension, None)
    assert str(raised.value) == message


def test_vectors() -> None:
    assert vector_to_si("[0, 0, 1500] mm", "length") == pytest.approx((0.0, 0.0, 1.5))
    assert vector_to_si(["1 m", 2, "3 mm"], "length", MM_DEG) == pytest.approx((1.0, 0.002, 0.003))
    assert vector_to_si("[0, 90] deg", "angle", size=None) == pytest.approx((0, math.pi / 2))
    with pytest.raises(UnitError, match=r"^expected 3 values, got 2$"):
        vector_to_si([1, 2], "length")
    with pytest.raises(UnitError, match=r"^item 2: expected a length, got '2 kg' \(a mass\)$"):
        vector_to_si([1, "2 kg", 3], "length")


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("deg", math.pi / 180),
        ("mm", 0.001),
        ("kN", 1000.0),
        ("knot", 1852 / 3600),
        ("bar", 1.0e5),
        ("rpm", 2 * math.pi / 60),
        ("percent", 0.01),
        ("hour", 3600.0),
    ],
)
def test_unit_constants(name: str, expected: float) -> None:
    assert unit_constant(name) == pytest.approx(expected)


@pytest.mark.parametrize("name", ["t", "x", "min", "pi", "angle", "foo", "degC", "2mm", "m*s"])
def test_not_unit_constants(name: str) -> None:
    assert unit_constant(name) is None


def test_unit_names_of_a_header() -> None:
    assert check_unit_name(" mm", "length") == "mm"
    with pytest.raises(UnitError, match=r"^'deg' is not a unit of length$"):
        check_unit_name("deg", "length")
    with pytest.raises(UnitError, match=r"^unknown unit 'mmm'$"):
        check_unit_name("mmm", "length")
