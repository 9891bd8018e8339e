"""Unit conversions pint has made before, kept in the user cache folder, so that a command
meeting only known unit texts never imports pint (pint, the dask its compat layer imports
when installed, and its registry: about 0.2 s of a `loads validate` of a door case).

Three sections, each entry pint's own result:
- `quantities`: the unit part of a quantity text `NUMBER UNIT` -> the SI value of one of it
  and the dimensionality of its base units;
- `units`: a file's header unit (the unit of its bare numbers) -> the SI value of one of it;
- `constants`: an identifier of an expression -> `units.unit_constant` of it (or null).

pint converts a multiplicative unit with one product, `value * factor`, so `number *
factor` is pint's float bit for bit. An entry is kept only if that product equals pint's
result for the value that made it and zero converts to zero (no offset or logarithmic
unit). A quantity text is looked up only when its unit part is letters joined by
spaces, `*` or `/`, with integer exponents: pint then reads it as the leading number times
units of magnitude one.

The table is named like pint's cache of the same definitions (`units._cache_stem`): other
definitions, another pint or another Python start a new one. A missing, unreadable or
foreign file is an empty table; entries learnt by a process are merged into the file when
it exits (a new file, then an atomic rename).
"""

from __future__ import annotations

import atexit
import json
import math
import os
import re
import tempfile
from contextlib import suppress
from pathlib import Path
from typing import Any

from loadcases.foundation.number_text import SIGNED_NUMBER

__all__ = ["UnitTable"]

FORMAT = 1  # the layout of the file; another layout is a foreign file
MAX_ENTRIES = 4096  # per section: names of any file's making never grow the file further
SECTIONS = ("quantities", "units", "constants")
_WORD = r"[^\W\d_]+"
_POWER = rf"{_WORD}(?:(?:\^|\*\*)-?\d+)?"
_QUANTITY = re.compile(
    rf"^\s*(?P<number>{SIGNED_NUMBER})\s+"
    rf"(?P<unit>{_POWER}(?:\s*[*/]?\s*{_POWER})*)\s*$"
)

Dimensionality = dict[str, float]


def _number(text: str) -> float:
    """The number as pint reads it: a float, integers too (`units` gives pint its numbers
    as floats: `-0 mm` is -0.0 m, as `-0` is -0.0)."""
    return float(text)


def _factor(number: float, factor: float) -> float | None:
    """`number * factor` as pint computes it; None where Python cannot (a factor that is an
    int too large for a float: pint fails there, and its message is wanted)."""
    try:
        return float(number * factor)
    except OverflowError:
        return None


class UnitTable:
    """The conversions stored in the file `path`, read on first use."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._entries: dict[str, dict[str, Any]] | None = None
        self._learnt: dict[str, dict[str, Any]] = {name: {} for name in SECTIONS}
        self._saving = False

    def _section(self, name: str) -> dict[str, Any]:
        if self._entries is None:
            self._entries = _read(self.path)
        return self._entries[name]

    def quantity(self, text: str) -> tuple[float, Dimensionality] | None:
        """SI magnitude and base dimensionality of the quantity text `text` ("110 mm"), or
        None when its unit is not in the table."""
        match = _QUANTITY.match(text)
        if match is None:
            return None
        entry = self._section("quantities").get(match["unit"])
        if entry is None:
            return None
        magnitude = _factor(_number(match["number"]), entry[0])
        return None if magnitude is None else (magnitude, entry[1])

    def unit(self, unit: str) -> float | None:
        """SI value of one `unit` (a header unit), or None when not in the table."""
        return self._section("units").get(unit)

    def constant(self, name: str) -> tuple[bool, float | None]:
        """(known, value): the stored `unit_constant(name)`, if any."""
        constants = self._section("constants")
        return (name in constants, constants.get(name))

    def learn_quantity(
        self, text: str, result: float, one: float, zero: float, dims: Dimensionality
    ) -> None:
        """Keep pint's conversion of `text`: `result` its SI magnitude, `one` and `zero`
        those of 1 and 0 of its unit, `dims` its base dimensionality."""
        match = _QUANTITY.match(text)
        if match is None:
            return
        number = _number(match["number"])
        if zero == 0 and _factor(number, one) == result:
            self._learn("quantities", match["unit"], [one, dims])

    def learn_unit(self, unit: str, value: float, result: float, one: float, zero: float) -> None:
        """Keep pint's conversion of `value` in `unit` (`one`, `zero`: of 1 and 0)."""
        if zero == 0 and _factor(value, one) == result:
            self._learn("units", unit, one)

    def learn_constant(self, name: str, value: float | None) -> None:
        """Keep `unit_constant(name)`."""
        self._learn("constants", name, value)

    def _learn(self, section: str, key: str, value: Any) -> None:
        if value is not None and not all(
            math.isfinite(v) for v in (value[:1] if isinstance(value, list) else [value])
        ):
            return
        stored = self._section(section)
        if len(stored) >= MAX_ENTRIES:
            return
        stored[key] = self._learnt[section][key] = value
        if not self._saving:
            self._saving = True
            atexit.register(self.save)

    def save(self) -> None:
        """Merge the entries learnt here into the file (no error if it cannot be written:
        the next run learns them again)."""
        if not any(self._learnt.values()):
            return
        entries = _read(self.path)
        for section, learnt in self._learnt.items():
            room = MAX_ENTRIES - len(entries[section])
            entries[section].update(list(learnt.items())[: max(room, 0)])
        with suppress(OSError):
            self.path.parent.mkdir(parents=True, exist_ok=True)
            handle, name = tempfile.mkstemp(dir=self.path.parent, prefix=".table-")
            try:
                with os.fdopen(handle, "w", encoding="utf-8") as file:
                    json.dump({"format": FORMAT, **entries}, file)
                os.replace(name, self.path)
            finally:
                with suppress(OSError):
                    os.unlink(name)
        self._learnt = {name: {} for name in SECTIONS}


def _read(path: Path) -> dict[str, dict[str, Any]]:
    """The sections of the file at `path`; empty ones where it is missing or not a table
    of this layout."""
    empty: dict[str, dict[str, Any]] = {name: {} for name in SECTIONS}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return empty
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        return empty
    sections = {name: data.get(name) for name in SECTIONS}
    for name, entries in sections.items():
        if not isinstance(entries, dict) or not all(_valid(name, v) for v in entries.values()):
            return empty
    return {name: dict(entries) for name, entries in sections.items() if entries is not None}


def _valid(section: str, value: Any) -> bool:
    """Whether `value` is an entry of `section` as this module writes them."""
    if section == "constants" and value is None:
        return True
    if section in ("units", "constants"):
        return isinstance(value, float) and math.isfinite(value)
    return (
        isinstance(value, list)
        and len(value) == 2
        and isinstance(value[0], float)
        and math.isfinite(value[0])
        and isinstance(value[1], dict)
        and all(
            isinstance(k, str) and isinstance(v, (int, float)) and not isinstance(v, bool)
            for k, v in value[1].items()
        )
    )
