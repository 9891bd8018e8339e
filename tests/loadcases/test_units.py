"""Units: quantities to SI floats, file units for bare numbers, angles as a dimension."""

from __future__ import annotations

import math

import pytest

from loadcases.foundation import units
from loadcases.foundation.units import (
    UnitError,
    check_unit_name,
    to_si,
    unit_constant,
    vector_to_si,
)

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


# pint's disk cache of the parsed definitions (loadcases.foundation.units._cached_registry)


def _every_conversion(registry) -> dict[str, tuple[float, float, str]]:
    """(SI factor, SI offset, SI unit) of every unit and of metres and newtons under every
    prefix; a unit pint cannot convert gives its error instead."""
    names = [*registry._units, *(f"{p}m" for p in registry._prefixes)]
    names += [f"{p}N" for p in registry._prefixes]
    out = {}
    for name in names:
        try:
            one = registry.Quantity(1.0, name).to_base_units()
            zero = registry.Quantity(0.0, name).to_base_units()
            out[name] = (one.magnitude, zero.magnitude, str(one.units))
        except Exception as error:  # noqa: BLE001  (the error is the result to compare)
            out[name] = (math.nan, math.nan, repr(error))
    return out


def _uncached():
    import pint

    registry = pint.UnitRegistry(None, autoconvert_offset_to_baseunit=False)
    registry.load_definitions(units._definitions().splitlines())
    registry.default_system = "mks"
    return registry


@pytest.fixture
def cache_folder(tmp_path, monkeypatch):
    folder = tmp_path / "cache" / "loads" / "pint"
    monkeypatch.setattr(units, "_unit_cache_folder", lambda: folder)
    return folder


def test_cached_unit_registry_gives_the_same_numbers(cache_folder) -> None:
    """The first registry fills the cache (its files moved in whole, then the `.ready`
    mark), the second is read from it; both convert every unit exactly as a registry
    parsed without the cache (factors, offsets and SI units compared bit for bit)."""
    text = units._definitions()
    first = units._cached_registry(text)
    assert first is not None
    assert len(list(cache_folder.glob("*.ready"))) == 1
    assert len(list(cache_folder.glob("*.pickle"))) >= 1
    assert not list(cache_folder.glob(".fill-*"))  # the private folder is gone
    second = units._cached_registry(text)
    assert second is not None and second.cache_folder == cache_folder
    second.default_system = first.default_system = "mks"
    expected = _every_conversion(_uncached())
    assert len(expected) > 1000
    for registry in (first, second):
        got = _every_conversion(registry)
        assert got.keys() == expected.keys()
        for name, (factor, offset, unit) in expected.items():
            assert got[name][2] == unit, name
            assert got[name][:2] == (factor, offset) or math.isnan(factor), name


def test_unit_cache_that_cannot_be_written_is_not_used(tmp_path, monkeypatch) -> None:
    """A cache folder that cannot be made (a file in the way) gives no registry: the caller
    parses the definitions as before."""
    blocker = tmp_path / "file"
    blocker.write_text("", encoding="utf-8")
    monkeypatch.setattr(units, "_unit_cache_folder", lambda: blocker / "pint")
    assert units._cached_registry(units._definitions()) is None


def test_broken_unit_cache_is_refilled(cache_folder) -> None:
    """A cache whose files are cut short gives no registry and loses its `.ready` mark;
    the next registry fills it again."""
    text = units._definitions()
    assert units._cached_registry(text) is not None
    for pickled in cache_folder.glob("*.pickle"):
        pickled.write_bytes(pickled.read_bytes()[:1000])
    assert units._cached_registry(text) is None
    assert not list(cache_folder.glob("*.ready"))
    refilled = units._cached_registry(text)
    assert refilled is not None and list(cache_folder.glob("*.ready"))
    assert units._cached_registry(text) is not None
    assert refilled.Quantity("110 mm").to_base_units().magnitude == 0.11
