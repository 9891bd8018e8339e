"""An imported FE model as a flexible body's source (`flexible: file:`, issue 13 item 3c).

Reference: the same Timoshenko cantilever as tests/loadcases/test_flexible_yaml.py (0.8 m,
30 x 10 mm aluminium, 5 N at the tip), built by the `beam:` source; the imported copy
(written with `write_neutral`) must give the same tip deflection (1e-9 relative) in its own
axes and turned onto global y by the file source's `x`, `y`, and both the closed form
P L^3/(3 E I) + P L/(k G A) within 0.1 %.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.flexible.neutral import write_neutral
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.flexible.beam import Material, Section
from mechlib.flexible.grillage import straight_beam

CASE = """\
case: imported-cantilever
mechanism:
  units: {length: mm}
  bodies:
    beam:
      flexible:
        SOURCE
        interface: {root: [0, 0, 0], tip: TIP}
        fixed_interface_modes: 6
  joints:
    clamp: {type: fixed, bodies: [beam, ground], at: [0, 0, 0]}
  forces:
    load: {type: force, point: beam.tip, value: [0, 0, 5]}
analysis: {type: static}
requests:
  tip: {point: beam.tip, quantity: position}
"""
BEAM = (
    "beam: {start: [0, 0, 0], end: [800, 0, 0], section: {width: 30, height: 10}, "
    "material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}, elements: 8, y_axis: [0, 1, 0]}"
)


def _write_model(folder: Path, modulus: float = 70e9) -> None:
    """The `beam:` source's FE model, written as a neutral file in its own axes (SI)."""
    named = straight_beam(
        (0.0, 0.0, 0.0),
        (0.8, 0.0, 0.0),
        Section.rectangle(0.03, 0.01, shear=True),
        Material(modulus, 0.33, 2700.0),
        8,
        {"root": (0.0, 0.0, 0.0), "tip": (0.8, 0.0, 0.0)},
        (0.0, 1.0, 0.0),
    )
    write_neutral(folder / "strip.json", named.model, description="test strip")


def _tip_z(folder: Path, source: str, tip: str = "[800, 0, 0]") -> float:
    path = folder / f"c{abs(hash(source + tip))}.case.yaml"
    path.write_text(CASE.replace("SOURCE", source).replace("TIP", tip), "utf-8")
    outcome = run_case(load_case(path))
    assert outcome.solution.ok, outcome.solution.message
    return float(outcome.solution.channels["tip.z"][0])


def test_imported_model_deflects_as_the_built_in_beam(tmp_path: Path) -> None:
    _write_model(tmp_path)
    built_in = _tip_z(tmp_path, BEAM)
    imported = _tip_z(tmp_path, "file: {path: strip.json}")
    turned = _tip_z(
        tmp_path, "file: {path: strip.json, x: [0, 1, 0], y: [-1, 0, 0]}", "[0, 800, 0]"
    )
    E, G, width, height, L, P = 70e9, 70e9 / 2.66, 0.03, 0.01, 0.8, 5.0
    exact = P * L**3 / (3 * E * width * height**3 / 12) + P * L / (5 / 6 * G * width * height)
    assert built_in == pytest.approx(exact, rel=1e-3)
    assert imported == pytest.approx(built_in, rel=1e-9)
    assert turned == pytest.approx(built_in, rel=1e-9)


@pytest.mark.parametrize(
    "source, tip, message",
    [
        ("file: {path: strip.json}", "[790, 0, 0]", "at no node of strip.json"),
        ("file: {path: ../strip.json}", "[800, 0, 0]", "leaves the folder"),
        ("file: {path: missing.json}", "[800, 0, 0]", "missing.json"),
        (
            "file: {path: strip.json}\n        stiffening: true",
            "[800, 0, 0]",
            "geometric stiffening needs the elements",
        ),
    ],
)
def test_file_source_errors_name_the_problem(
    tmp_path: Path, source: str, tip: str, message: str
) -> None:
    _write_model(tmp_path)
    with pytest.raises(InputError, match=message):
        _tip_z(tmp_path, source, tip)


def test_a_changed_imported_matrix_changes_the_run_identity(tmp_path: Path) -> None:
    """Saved runs are reused only for the same inputs: the imported files' bytes are part
    of the case's input hash, as a hardpoint table's are."""
    _write_model(tmp_path)
    path = tmp_path / "c.case.yaml"
    path.write_text(
        CASE.replace("SOURCE", "file: {path: strip.json}").replace("TIP", "[800, 0, 0]"), "utf-8"
    )
    before = load_case(path).input_sha256
    assert load_case(path).input_sha256 == before
    _write_model(tmp_path, modulus=71e9)  # the same header, a stiffer matrix
    assert load_case(path).input_sha256 != before
