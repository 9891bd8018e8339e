"""Quantities with units -> SI floats (m, kg, s, N, rad, N*m, Pa).

Angles are a dimension of their own here: pint's definitions are loaded with `radian` as the
base unit of `[angle]`, so `"3 m"` where an angle is expected is an error and `"35 deg"` is
0.6109 rad. Where an angle is part of a compound dimension (angular velocity, torsional
stiffness) a value without it is taken per radian: `"50 N*m"` is accepted as 50 N*m/rad.

Bare numbers: for the five file-unit kinds (length, angle, mass, time, force) a bare number is
in the file's unit (`units: {length: mm}`); for every other dimension a bare number is SI.

A quantity text is bounded before pint reads it (`_pint_text`): at most MAX_QUANTITY_CHARS
characters, digits 0-9 in decimal numbers, a plain space as its only space, no hidden
character (`loadcases.foundation.clip`), letters and the signs of a unit expression only
(pint would read `1:30 kg` as 30 kg and `1,5 mm` as 15 mm), balanced parentheses; and its
numbers are given to pint as floats, so that its arithmetic cannot grow without bound
(`10**10**10` would be a ten-billion-digit integer; in floats it overflows at once: "a
number out of range").
"""

from __future__ import annotations

import hashlib
import io
import math
import os
import re
import sys
import tokenize
import unicodedata
from collections.abc import Mapping, Sequence
from contextlib import suppress
from functools import lru_cache
from pathlib import Path
from typing import Any

from loadcases.foundation.clip import clip, describe_character, hidden_character
from loadcases.foundation.limits import MAX_QUANTITY_CHARS
from loadcases.foundation.number_text import SIGNED_NUMBER
from loadcases.foundation.unit_table import UnitTable

__all__ = [
    "DIMENSIONS",
    "FILE_UNIT_KINDS",
    "REPORT_KINDS",
    "RESERVED_NAMES",
    "SIValue",
    "UnitError",
    "UnreadableError",
    "check_unit_name",
    "describe_dimension",
    "dimension_mismatch",
    "finite",
    "quantity_dimension",
    "si_unit_text",
    "si_value_problem",
    "to_si",
    "unit_constant",
    "unit_dimension",
    "vector_text_unit",
    "vector_to_si",
]

# Expected dimensionality of each dimension name, as {base dimension: exponent}.
_L, _M, _T, _A = "[length]", "[mass]", "[time]", "[angle]"
DIMENSIONS: dict[str, dict[str, int]] = {
    "length": {_L: 1},
    "angle": {_A: 1},
    "mass": {_M: 1},
    "time": {_T: 1},
    "force": {_M: 1, _L: 1, _T: -2},
    "torque": {_M: 1, _L: 2, _T: -2},
    "energy": {_M: 1, _L: 2, _T: -2},
    "inertia": {_M: 1, _L: 2},
    "velocity": {_L: 1, _T: -1},
    "angular_velocity": {_A: 1, _T: -1},
    "acceleration": {_L: 1, _T: -2},
    "angular_acceleration": {_A: 1, _T: -2},
    "stiffness": {_M: 1, _T: -2},
    "torsional_stiffness": {_M: 1, _L: 2, _T: -2, _A: -1},
    "damping": {_M: 1, _T: -1},
    "torsional_damping": {_M: 1, _L: 2, _T: -1, _A: -1},
    "pressure": {_M: 1, _L: -1, _T: -2},
    "area": {_L: 2},
    "volume": {_L: 3},
    "density": {_M: 1, _L: -3},
    "second_moment": {_L: 4},
    "frequency": {_T: -1},
    "flow": {_L: 3, _T: -1},
    "leakage": {_L: 4, _T: 1, _M: -1},
    "current": {"[current]": 1},
    "current_gain": {"[current]": 1, _L: -1},
    "integral_gain": {"[current]": 1, _L: -1, _T: -1},
    "dimensionless": {},
}
FILE_UNIT_KINDS = ("length", "angle", "mass", "time", "force")
# The kinds a report may show in other units (`report.units`), by the SI unit text the engine
# gives their result columns.
REPORT_KINDS: dict[str, str] = {
    "force": "N",
    "torque": "N*m",
    "angle": "rad",
    "length": "m",
    "velocity": "m/s",
    "angular_velocity": "rad/s",
    "acceleration": "m/s^2",
    "angular_acceleration": "rad/s^2",
    "time": "s",
    "mass": "kg",
    "pressure": "Pa",
    "stiffness": "N/m",
    "torsional_stiffness": "N*m/rad",
    "frequency": "Hz",
    "energy": "J",
    "flow": "m^3/s",
}
# Identifiers of the expression language that are never unit constants (`t` is not tonne).
RESERVED_NAMES = frozenset(
    {
        "t",
        "pi",
        "sin",
        "cos",
        "tan",
        "asin",
        "acos",
        "atan",
        "atan2",
        "sqrt",
        "abs",
        "min",
        "max",
        "sign",
        "exp",
        "log",
        "step",
        "table",
        "angle",
        "omega",
        "travel",
        "speed",
        "dist",
        "x",
        "y",
        "z",
        "vx",
        "vy",
        "vz",
    }
)
_NUMBER = re.compile(rf"^ *{SIGNED_NUMBER} *\Z")
_LEADING_NUMBER = re.compile(rf"^ *{SIGNED_NUMBER}")
# a number as pint's tokenizer (Python's) gives it: decimal, without `_`, `0x`, `j`
_DECIMAL = re.compile(r"(?:(?:0|[1-9][0-9]*)(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")
_INTEGER = re.compile(r"[0-9]+")
_MAX_POWER = 99  # of a base dimension in a quantity text
_VECTOR = re.compile(r"^\s*\[(?P<items>[^\]]*)\]\s*(?P<unit>.*?)\s*$")
_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class UnitError(ValueError):
    """A value that is not a quantity of the expected dimension; `str()` says why."""


class UnreadableError(UnitError):
    """A text that is no quantity at all (`cannot read 'off2': ...`), whatever its dimension."""


@lru_cache(maxsize=1)
def _registry() -> Any:
    """The shared pint registry with `[angle]` as a base dimension (built once, lazily)."""
    import pint

    text = _definitions()
    registry = _cached_registry(text)
    if registry is None:
        registry = pint.UnitRegistry(None, autoconvert_offset_to_baseunit=False)
        registry.load_definitions(text.splitlines())
    registry.default_system = "mks"
    return registry


@lru_cache(maxsize=1)
def _definitions() -> str:
    """pint's own definitions (its constants put in place) with `radian = [angle]`, read
    from pint's folder without importing pint."""
    import importlib.util

    spec = importlib.util.find_spec("pint")
    if spec is None or not spec.submodule_search_locations:
        raise ImportError("pint is not installed")
    files = Path(next(iter(spec.submodule_search_locations)))
    text = (files / "default_en.txt").read_text(encoding="utf-8")
    constants = (files / "constants_en.txt").read_text(encoding="utf-8")
    text = text.replace("radian = [] = rad", "radian = [angle] = rad")
    return text.replace("@import constants_en.txt", constants)


def _cache_stem(text: str) -> str:
    """The name of the cached files of the definitions `text` read by this pint and this
    Python (pint's version from its metadata: pint itself is not imported)."""
    from importlib.metadata import version

    key = "\0".join((text, version("pint"), sys.version))
    return "units-" + hashlib.sha256(key.encode("utf-8")).hexdigest()[:24]


@lru_cache(maxsize=1)
def _table() -> UnitTable:
    """The table of the conversions pint made before (`loadcases.foundation.unit_table`)."""
    return UnitTable(_unit_cache_folder() / f"{_cache_stem(_definitions())}.table.json")


def _unit_cache_folder() -> Path:
    """Where pint keeps the parsed unit definitions of loads: `loads/pint` in the user's
    cache folder (on Linux `$XDG_CACHE_HOME`, else `~/.cache`)."""
    import platformdirs

    return platformdirs.user_cache_path("loads", appauthor=False) / "pint"


def _cached_registry(text: str) -> Any:
    """The registry of the definitions `text` through pint's own disk cache (its
    `cache_folder` option, flexcache): parsing the definitions costs about 0.2 s, loading
    them parsed a few hundredths. The same definitions parsed by the same pint: the same
    registry, the same numbers. None when the cache folder cannot be written or its files
    cannot be read: the caller then parses as without a cache.

    The files are named by the SHA-256 of the definitions, pint's version and Python's. A
    first run fills a private folder and moves each file into the cache folder (an atomic
    rename: flexcache writes its files in place), then writes the `.ready` mark; without
    the mark a run fills the cache itself, so no run reads a file another is writing."""
    ready: Path | None = None
    try:
        stem = _cache_stem(text)
        folder = _unit_cache_folder()
        definitions, ready = folder / f"{stem}.txt", folder / f"{stem}.ready"
        if ready.is_file() and definitions.read_text(encoding="utf-8") == text:
            return _parsed_registry(definitions, folder)
        folder.mkdir(parents=True, exist_ok=True)
        return _fill_unit_cache(text, folder, definitions, ready)
    # Whatever stops the cache (a read-only or full disk, a truncated or foreign file) only
    # costs the parse: the registry is then built without it.
    except Exception:  # noqa: BLE001
        if ready is not None:
            with suppress(OSError):
                ready.unlink(missing_ok=True)  # the next run fills the cache again
    return None


def _parsed_registry(definitions: Path, cache: Path) -> Any:
    """A registry of the definitions file `definitions`, parsed through pint's cache in
    `cache` (as `_registry` builds it without: offsets not converted, cache built lazily)."""
    import pint

    registry: pint.UnitRegistry = pint.UnitRegistry(
        None, autoconvert_offset_to_baseunit=False, cache_folder=cache
    )
    registry.load_definitions(definitions)
    return registry


def _fill_unit_cache(text: str, folder: Path, definitions: Path, ready: Path) -> Any:
    """The registry of `text`, parsed once with pint's cache in a private folder whose
    files then move into `folder`."""
    import tempfile

    with tempfile.TemporaryDirectory(dir=folder, prefix=".fill-") as private:
        staged = Path(private) / definitions.name
        staged.write_text(text, encoding="utf-8")
        registry = _parsed_registry(staged, Path(private))
        for made in Path(private).iterdir():
            if made != staged:
                os.replace(made, folder / made.name)
        os.replace(staged, definitions)
        ready.touch()
    return registry


def _describe(dimensionality: Mapping[str, float], units: Any = None) -> str:
    """Engineer's name of a dimensionality: `a mass`, or `units of kg*m/s**2/rad`."""
    wanted = {k: v for k, v in dimensionality.items() if v}
    for name, dims in DIMENSIONS.items():
        if dims == wanted:
            name = name.replace("_", " ")
            return (
                "a dimensionless number"
                if name == "dimensionless"
                else f"an {name}"
                if name[0] in "aeiou"
                else f"a {name}"
            )
    if units is not None:
        return f"units of {units:~C}"
    return "dimension " + " ".join(f"{k}^{v:g}" if v != 1 else k for k, v in wanted.items())


def _matches(got: Mapping[str, float], dimension: str) -> bool:
    """True if `got` is `dimension`, or is it without its angle (taken per radian)."""
    want = DIMENSIONS[dimension]
    got = {k: v for k, v in got.items() if v}
    if got == want:
        return True
    return (
        dimension != "angle"
        and _A in want
        and _A not in got
        and got == {k: v for k, v in want.items() if k != _A}
    )


# Characters of a quantity text besides letters and the digits 0-9 (`°`, `µm`, `m²`, `N·m`)
_QUANTITY_SIGNS = frozenset(" .*/^()+-_%°·⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def _character_problem(char: str, quantity: bool = True) -> str | None:
    """Why `char` cannot be part of a quantity text (`quantity`; else of a vector text
    such as "[0, 0, 1] mm": only hidden characters, spaces and digits are checked), or
    None."""
    if char == " ":
        return None
    if char.isspace() or hidden_character(char):
        return f"{describe_character(char)}: write a plain space or nothing"
    if not char.isascii() and unicodedata.category(char) == "Nd":
        return f"{describe_character(char)}: write numbers with the digits 0-9"
    if not quantity or char in _QUANTITY_SIGNS or char.isalpha() or "0" <= char <= "9":
        return None
    if char == ",":  # pint would read "1,5 mm" as 15 mm
        return "',' is not part of a quantity: write 1500 for 1,500 and 1.5 for 1,5"
    return f"'{char}' is not part of a quantity"  # pint reads "1:30 kg" as 30 kg


def _text_problem(text: str) -> str | None:
    """Why the quantity text `text` is refused before pint reads it, or None."""
    if len(text) > MAX_QUANTITY_CHARS:
        return f"longer than {MAX_QUANTITY_CHARS} characters"
    problem = next(filter(None, map(_character_problem, text)), None)
    if problem is not None:
        return problem
    depth = 0
    for char in text:
        depth += (char == "(") - (char == ")")
        if depth < 0:
            break
    return "unbalanced parentheses" if depth else None


def _cannot_read(text: str, reason: str) -> UnreadableError:
    return UnreadableError(f"cannot read '{clip(text)}': {reason}")


def _check_text(text: str) -> None:
    """UnitError if the quantity text `text` is refused before pint reads it."""
    problem = _text_problem(text)
    if problem is not None:
        raise _cannot_read(text, problem)


def _pint_text(text: str) -> str:
    """`text` (checked by `_check_text`) as pint is to read it: pint's own preprocessing
    (`^` to `**`, `2m` to `2*m`, `²`, thousands commas dropped), then each integer written
    as a float, but an integer power of a unit (`m**2`, `s**-1`: at most two digits):
    pint's arithmetic stays in floats and ends at once. UnitError for a number that is not
    decimal (`0x10`, `1_000`, `010`)."""
    from pint.util import string_preprocessor

    prepared = string_preprocessor(text)
    try:
        tokens = [
            token
            for token in tokenize.generate_tokens(io.StringIO(prepared).readline)
            if token.type not in (tokenize.NEWLINE, tokenize.NL, tokenize.ENDMARKER)
        ]
    except (tokenize.TokenError, SyntaxError):
        raise _cannot_read(text, "not a quantity") from None
    pieces, done = [], 0
    for index, token in enumerate(tokens):
        if token.type != tokenize.NUMBER:
            continue
        start, end = token.start[1], token.end[1]
        after = tokens[index + 1] if index + 1 < len(tokens) else None
        if after is not None and after.type == tokenize.NUMBER and after.start[1] == end:
            end = after.end[1]  # `010` is read by Python as 0 then 10
        written = prepared[start:end]
        if not _DECIMAL.fullmatch(written):
            raise _cannot_read(text, f"'{written}' is not a decimal number")
        if _INTEGER.fullmatch(written) and not _unit_power(tokens, index):
            pieces += [prepared[done:start], written + ".0"]
            done = end
    return "".join(pieces) + prepared[done:]


def _unit_power(tokens: list[tokenize.TokenInfo], index: int) -> bool:
    """Whether the integer token at `index` is a small power of a unit: `m**2`, `m**-2`,
    `m**(2)` (pint writes `m²` so), not followed by another power."""
    if len(tokens[index].string) > 2:
        return False
    k = index - 1
    opened = k >= 0 and tokens[k].string == "("
    k -= opened
    if k >= 0 and tokens[k].string in ("-", "+"):
        k -= 1
    if k < 1 or tokens[k].string != "**" or tokens[k - 1].type != tokenize.NAME:
        return False
    after = index + 1
    if opened:
        if after >= len(tokens) or tokens[after].string != ")":
            return False
        after += 1
    return after >= len(tokens) or tokens[after].string != "**"


def _quantity(text: str) -> tuple[Any, Any]:
    """Parse `text` ("110 mm") into a pint quantity and the same in base units; raises
    UnitError if it is not one."""
    if not _LEADING_NUMBER.match(text):
        raise _cannot_read(text, "expected a number with a unit, like '110 mm'")
    _check_text(text)
    registry = _registry()
    import pint

    try:
        quantity = registry.Quantity(_pint_text(text))
        if not isinstance(quantity, registry.Quantity) or isinstance(quantity.magnitude, complex):
            raise _cannot_read(text, "not a quantity")
        base = quantity.to_base_units()
        float(base.magnitude)
        if any(not abs(power) <= _MAX_POWER for power in base.dimensionality.values()):
            raise OverflowError  # `m**99**99`: a unit to the power 3.7e197
    except (OverflowError, RecursionError, MemoryError):
        raise _cannot_read(text, "a number out of range") from None
    # pint's expression parser raises AssertionError on some malformed texts ("1 m/").
    except (
        pint.errors.PintError,
        ValueError,
        TypeError,
        SyntaxError,
        AttributeError,
        KeyError,
        ZeroDivisionError,
        AssertionError,
        tokenize.TokenError,
    ) as error:
        if isinstance(error, UnitError):
            raise
        reason = (
            f"unknown unit '{error.unit_names[0]}'"
            if isinstance(error, pint.errors.UndefinedUnitError) and error.unit_names
            else "not a quantity"
        )
        raise _cannot_read(text, reason) from None
    return quantity, base


def _file_unit(dimension: str, file_units: Mapping[str, str] | None) -> str | None:
    """The unit of bare numbers of `dimension` in a file with header `units:`."""
    if file_units and dimension in FILE_UNIT_KINDS:
        return file_units.get(dimension)
    return None


class SIValue(float):
    """A value already in SI (a parameter, or an expression of parameters, put in place of
    its text): no file unit applies. `dims` is its base dimensionality ({"[length]": 1}) when
    known (a parameter written with a unit), None when not (a bare number: SI of whatever it
    is); `source` says what it replaced, for messages (`parameter 'airspeed' = '250 kg'`)."""

    dims: Mapping[str, float] | None
    source: str

    def __new__(
        cls, value: float, dims: Mapping[str, float] | None = None, source: str = ""
    ) -> SIValue:
        made = super().__new__(cls, value)
        made.dims = None if dims is None else {k: v for k, v in dims.items() if v}
        made.source = source
        return made

    def __reduce__(self) -> tuple:
        return (SIValue, (float(self), self.dims, self.source))


def si_value_problem(value: SIValue, dimension: str) -> str | None:
    """Why the SI value `value` (of a known dimension) cannot stand where `dimension` is
    expected, or None: the rule of quantity texts (`_matches`), so a parameter written
    `250 kg` is refused where the same text written in place would be."""
    if dimension == "any" or value.dims is None or _matches(value.dims, dimension):
        return None
    return (
        f"expected {_describe(DIMENSIONS[dimension])}, got {value.source or 'a value'} "
        f"({describe_dimension(value.dims)})"
    )


def describe_dimension(dims: Mapping[str, float]) -> str:
    """Engineer's name of a base dimensionality: `a velocity`, `a mass`, or
    `units of kg^3/m` when it has no name."""
    wanted = {k: v for k, v in dims.items() if v}
    if any(wanted == d for d in DIMENSIONS.values()):
        return _describe(wanted)
    return f"units of {si_unit_text(wanted)}"


_SI_SYMBOLS = {
    "[mass]": "kg",
    "[length]": "m",
    "[time]": "s",
    "[angle]": "rad",
    "[current]": "A",
    "[temperature]": "K",
    "[substance]": "mol",
    "[luminosity]": "cd",
}


def si_unit_text(dims: Mapping[str, float]) -> str:
    """The SI unit of a base dimensionality as the engine writes units: the text of its
    kind where it has one (`N`, `N*m`, `rad/s`: the units a report converts), else its base
    units (`kg*m^3/(s^2*rad)`); `1` for a plain number."""
    wanted = {k: v for k, v in dims.items() if v}
    for kind, unit in REPORT_KINDS.items():
        if DIMENSIONS[kind] == wanted:
            return unit
    if not wanted:
        return "1"

    def power(base: str, value: float) -> str:
        symbol = _SI_SYMBOLS.get(base, base)
        return symbol if value == 1 else f"{symbol}^{value:g}"

    up = [power(b, v) for b, v in sorted(wanted.items(), key=_base_order) if v > 0]
    down = [power(b, -v) for b, v in sorted(wanted.items(), key=_base_order) if v < 0]
    text = "*".join(up) or "1"
    if down:
        text += "/" + (down[0] if len(down) == 1 else "(" + "*".join(down) + ")")
    return text


def _base_order(item: tuple[str, float]) -> int:
    order = list(_SI_SYMBOLS)
    return order.index(item[0]) if item[0] in order else len(order)


@lru_cache(maxsize=4096)
def quantity_dimension(text: str) -> tuple[tuple[str, float], ...] | None:
    """Base dimensionality of the quantity text `text` ("250 knot") as sorted (base,
    power) pairs; () for a dimensionless one, None for a bare number (SI of an unknown
    dimension); UnitError if it is not a quantity."""
    if _NUMBER.match(text):
        return None
    _check_text(text)
    known = _table().quantity(text)
    if known is not None:
        dims = known[1]
    else:
        quantity, base = _quantity(text)
        _learn_quantity(text, quantity, base)
        dims = dict(base.dimensionality)
    return tuple(sorted((k, float(v)) for k, v in dims.items() if v))


def unit_dimension(name: str) -> tuple[tuple[str, float], ...] | None:
    """Base dimensionality of the unit constant `name` of expressions (`deg` -> angle), or
    None if `name` is not one (see `unit_constant`)."""
    if unit_constant(name) is None:
        return None
    try:
        return quantity_dimension(f"1 {name}")
    except UnitError:
        return None


def to_si(value: Any, dimension: str, file_units: Mapping[str, str] | None = None) -> float:
    """SI magnitude of a number or quantity text of the given dimension name.

    `dimension` is a key of DIMENSIONS or "any" (any dimension, returns the SI magnitude).
    Raises UnitError with a message such as "expected a length, got '12 kg' (a mass)".
    """
    if dimension != "any" and dimension not in DIMENSIONS:
        raise KeyError(f"unknown dimension name {dimension!r}")
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise UnitError(f"expected a number or a quantity text, got {_show(value)}")
    if isinstance(value, SIValue):
        problem = si_value_problem(value, dimension)
        if problem is not None:
            raise UnitError(problem)
        return float(value)
    return finite(_si_magnitude(value, dimension, file_units), value)


def _si_magnitude(
    value: int | float | str, dimension: str, file_units: Mapping[str, str] | None
) -> float:
    """to_si without the finiteness check."""
    if isinstance(value, str) and _NUMBER.match(value):
        value = float(value)
    if not isinstance(value, str):
        unit = _file_unit(dimension, file_units)
        if unit is None or not math.isfinite(value):
            return float(value)
        return _number_in_unit(float(value), unit, math.copysign(1.0, value) < 0.0)
    return _text_magnitude(value, dimension)


# A set reads its mechanism once per case and run (the door: 800 quantities each), and
# pint parses a quantity in about 0.2 ms: the conversions are remembered (pure functions
# of their arguments; a failed one raises again each time).
@lru_cache(maxsize=8192)
def _number_in_unit(value: float, unit: str, negative: bool) -> float:
    """SI magnitude of a bare number in `unit` (`negative`: its sign bit, which tells the
    cache -0.0 from 0.0)."""
    one = _table().unit(unit)
    if one is not None:
        return value * one
    registry = _registry()
    result = float(registry.Quantity(value, unit).to_base_units().magnitude)
    _table().learn_unit(
        unit,
        value,
        result,
        one=float(registry.Quantity(1.0, unit).to_base_units().magnitude),
        zero=float(registry.Quantity(0.0, unit).to_base_units().magnitude),
    )
    return result


@lru_cache(maxsize=8192)
def _text_magnitude(value: str, dimension: str) -> float:
    """SI magnitude of a quantity text of `dimension` ("any": of any); UnitError if it is
    not one."""
    _check_text(value)  # before the table: it may hold texts read by an older `loads`
    known = _table().quantity(value)
    if known is not None and (dimension == "any" or _matches(known[1], dimension)):
        return known[0]
    quantity, base = _quantity(value)
    if known is None:
        _learn_quantity(value, quantity, base)
    if dimension != "any" and not _matches(base.dimensionality, dimension):
        raise UnitError(
            f"expected {_describe(DIMENSIONS[dimension])}, got '{clip(value)}' "
            f"({_describe(base.dimensionality, base.units)})"
        )
    return float(base.magnitude)


def _learn_quantity(text: str, quantity: Any, base: Any) -> None:
    """Put pint's conversion of the quantity text `text` into the table."""
    registry = _registry()
    try:
        one = float(registry.Quantity(1.0, quantity.units).to_base_units().magnitude)
        zero = float(registry.Quantity(0.0, quantity.units).to_base_units().magnitude)
    except OverflowError:
        return  # a unit out of float range: not kept (the text is refused as not finite)
    _table().learn_quantity(
        text, float(base.magnitude), one=one, zero=zero, dims=dict(base.dimensionality)
    )


def finite(magnitude: float, given: Any) -> float:
    """`magnitude` if it is finite; else UnitError "expected a finite number, got NaN"
    (`given`: the input as written, a float or a text)."""
    if math.isfinite(magnitude):
        return magnitude
    if isinstance(given, str):
        shown = f"'{clip(given.strip())}'"
    else:
        shown = "NaN" if math.isnan(given) else "infinity" if given > 0 else "-infinity"
    raise UnitError(f"expected a finite number, got {shown}")


def _show(value: Any) -> str:
    """Short text of a wrong-typed value for messages."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return f"a list of {len(value)} values"
    if isinstance(value, dict):
        return "a mapping"
    return "nothing" if value is None else repr(value)


def vector_to_si(
    value: Any, dimension: str, file_units: Mapping[str, str] | None = None, size: int | None = 3
) -> tuple[float, ...]:
    """SI components of a list of numbers/quantities or a text like "[0, 0, 1500] mm".

    `size=None` accepts any length; otherwise a different length raises UnitError
    ("expected 3 values, got 2").
    """
    unit = ""
    if isinstance(value, str):
        problem = next(filter(None, (_character_problem(c, False) for c in value)), None)
        if problem is not None:
            raise _cannot_read(value, problem)
        match = _VECTOR.match(value)
        if match is None:
            raise UnitError(
                f"expected a list of values or a text like '[0, 0, 1] mm', got '{clip(value)}'"
            )
        items: Sequence[Any] = [s.strip() for s in match["items"].split(",") if s.strip()]
        unit = match["unit"]
    elif isinstance(value, (list, tuple)):
        items = value
    else:
        raise UnitError(f"expected a list of values, got {_show(value)}")
    if size is not None and len(items) != size:
        raise UnitError(f"expected {size} values, got {len(items)}")
    result = []
    for index, item in enumerate(items):
        if unit and isinstance(item, str):
            item = f"{item} {unit}" if _NUMBER.match(item) else item
        try:
            result.append(to_si(item, dimension, file_units))
        except UnitError as error:
            raise UnitError(f"item {index + 1}: {error}") from None
    return tuple(result)


def vector_text_unit(text: str) -> str | None:
    """The unit written after the brackets of a vector text (`"[0, 30] deg"` -> `deg`), or
    None when there is none or `text` is not a vector text."""
    match = _VECTOR.match(text)
    return match["unit"] or None if match else None


@lru_cache(maxsize=512)
def unit_constant(name: str) -> float | None:
    """SI magnitude of unit `name` used as a constant in expressions (deg -> pi/180).

    None if `name` is not a unit, is an offset unit (degC), or is an identifier of the
    expression language (`t`, `x`, `min` ... see RESERVED_NAMES).
    """
    if name in RESERVED_NAMES or not _IDENTIFIER.match(name):
        return None
    known, value = _table().constant(name)
    if known:
        return value
    value = _pint_unit_constant(name)
    _table().learn_constant(name, value)
    return value


def _pint_unit_constant(name: str) -> float | None:
    """unit_constant computed by pint."""
    registry = _registry()
    import pint

    try:
        unit = registry.Unit(name)
        magnitude = registry.Quantity(1.0, unit).to_base_units().magnitude
        offset = registry.Quantity(0.0, unit).to_base_units().magnitude
    except (pint.errors.PintError, ValueError, TypeError, AttributeError, KeyError):
        return None
    return float(magnitude) if math.isfinite(magnitude) and offset == 0 else None


def check_unit_name(unit: Any, kind: str) -> str:
    """Validate the unit name of a `units:` header entry of `kind`; raises UnitError."""
    if not isinstance(unit, str) or not unit.strip():
        raise UnitError(f"expected a unit name such as 'mm', got {_show(unit)}")
    try:
        to_si(f"1 {unit}", kind)
    except UnreadableError:
        raise UnitError(f"unknown unit '{unit}'") from None
    except UnitError:
        raise UnitError(f"'{unit}' is not a unit of {kind}") from None
    return unit.strip()


def dimension_mismatch(value: str, reference: Any) -> str | None:
    """Why the quantity text `value` cannot replace `reference` (a parameter as written),
    or None: both must have the same dimension. A bare number on either side (SI, of an
    unknown dimension) is never a mismatch."""
    if not isinstance(reference, str) or _NUMBER.match(reference) or _NUMBER.match(value):
        return None
    try:
        want_dims = quantity_dimension(reference)
    except UnitError:
        return None  # a bad definition is reported where it is written
    if quantity_dimension(value) == want_dims:  # the unit table's: pint only for new units
        return None
    want, got = _quantity(reference)[1], _quantity(value)[1]
    return (
        f"expected {_describe(want.dimensionality, want.units)} like '{clip(reference)}', "
        f"got {_describe(got.dimensionality, got.units)}"
    )
