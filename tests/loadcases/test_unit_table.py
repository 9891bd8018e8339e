"""The table of the unit conversions pint made before (loadcases.foundation.unit_table): a run that
meets only known units gives pint's numbers bit for bit and pint's messages, without
importing pint."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from loadcases.foundation.unit_table import UnitTable

ROOT = Path(__file__).resolve().parents[2]
QUANTITIES = [
    "110 mm", "-35 deg", "0 N*m*s/rad", "-0 mm", "-0.0 mm", "+2.5 kN/mm", "1e3 N*m/rad",
    ".5 mm^2", "12 N*mm/deg", "5 L/min", "1 bar", "100 mm/s^2", "0.3 mm", "7 lbf*in",
    "12 psi", "3 kg*m**2", "9.81 m/s^2", "2 N m", "4 rad/s", "1.5E-3 s",
]  # fmt: skip
HEADER_UNITS = {"length": ["mm", "in", "m"], "angle": ["deg", "rad"], "mass": ["g", "kg"],
                "time": ["ms", "min"], "force": ["kN", "lbf"]}  # fmt: skip
WRONG = [("12 kg", "length"), ("3 m", "angle"), ("5 N", "torque"), ("2 mm", "angular_velocity")]
CONSTANTS = ["deg", "mm", "kN", "crank_speed", "degC"]

_CONVERT = """
import json, sys
from loadcases.foundation.units import UnitError, to_si, unit_constant
quantities, header_units, wrong, constants = json.loads(sys.argv[1])
out = {"quantities": [repr(to_si(q, "any")) for q in quantities], "numbers": [], "errors": []}
for kind, names in header_units.items():
    for name in names:
        out["numbers"] += [repr(to_si(v, kind, {kind: name})) for v in (1.25, -0.0, 3, -7.5e8)]
for text, kind in wrong:
    try:
        to_si(text, kind)
    except UnitError as error:
        out["errors"].append(str(error))
out["constants"] = [unit_constant(name) for name in constants]
out["pint"] = "pint" in sys.modules
print(json.dumps(out))
"""


def _convert(cache: Path, wrong: list[tuple[str, str]] = WRONG) -> dict:
    """The conversions made by a fresh interpreter whose user cache folder is `cache`."""
    inputs = json.dumps([QUANTITIES, HEADER_UNITS, wrong, CONSTANTS])
    done = subprocess.run(
        [sys.executable, "-c", _CONVERT, inputs],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
        env=os.environ | {"XDG_CACHE_HOME": str(cache)},
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_table_gives_pints_numbers_and_messages(tmp_path: Path) -> None:
    """A first process converts with pint and fills the table; a second, reading it, gives
    the same floats (repr: bit for bit, the sign of zero too), the same messages for a
    wrong dimension (from pint) and the same unit constants; it imports pint only for the
    messages."""
    first = _convert(tmp_path)
    second = _convert(tmp_path)
    assert first["pint"] is True
    assert second == first | {"pint": True}
    assert first["quantities"][:4] == ["0.11", "-0.6108652381980153", "0.0", "-0.0"]
    assert first["quantities"][4] == "-0.0"  # numbers reach pint as floats (issue 39)
    assert first["errors"][0] == "expected a length, got '12 kg' (a mass)"
    assert first["constants"] == [pytest.approx(0.017453292519943295), 0.001, 1000.0, None, None]


def test_known_units_need_no_pint(tmp_path: Path) -> None:
    """Without wrong dimensions to explain, the second process never imports pint."""
    _convert(tmp_path, wrong=[])
    assert _convert(tmp_path, wrong=[])["pint"] is False


def test_table_keeps_only_multiplicative_conversions(tmp_path: Path) -> None:
    """An entry is kept only if `number * factor` is pint's result and zero converts to
    zero: an offset unit (degC: 0 -> 273.15 K) and a result that is not the product stay
    out; what is kept is written at save and read back by another table."""
    path = tmp_path / "table.json"
    table = UnitTable(path)
    table.learn_unit("degC", 20.0, 293.15, one=274.15, zero=273.15)
    table.learn_unit("mm", 3.0, 0.004, one=0.001, zero=0.0)
    table.learn_quantity("2 mm", 0.002, one=0.001, zero=0.0, dims={"[length]": 1})
    table.learn_quantity("2 * 3 mm", 0.006, one=0.001, zero=0.0, dims={"[length]": 1})
    table.learn_constant("crank_speed", None)
    assert table.unit("degC") is None and table.unit("mm") is None
    table.save()
    again = UnitTable(path)
    assert again.quantity("-7 mm") == (-0.007, {"[length]": 1})
    assert again.quantity("7 mm + 1 m") is None
    assert again.constant("crank_speed") == (True, None)
    assert again.constant("deg") == (False, None)


@pytest.mark.parametrize(
    "text",
    ["not json", '{"format": 1}', '{"format": 2, "quantities": {}, "units": {}, "constants": {}}',
     '{"format": 1, "quantities": {"mm": [true, {}]}, "units": {}, "constants": {}}'],
)  # fmt: skip
def test_foreign_or_broken_file_is_an_empty_table(tmp_path: Path, text: str) -> None:
    path = tmp_path / "table.json"
    path.write_text(text, encoding="utf-8")
    table = UnitTable(path)
    assert table.quantity("1 mm") is None and table.unit("mm") is None
