"""A mechanism file's own parameters named in numeric fields are put in place when the file
is validated or run alone (`loads validate door.mech.yaml`), as they are for a case."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.inputs.loader import load_mechanism

MECH = """\
name: pad
parameters:
  stop_gap: 1.3 mm
  seal_springs: 7
bodies:
  door: {mass: 1, cm: [0, 0, 0], inertia: [1, 1, 1]}
forces:
  seal: {type: seal, bodies: [door, ground], start: [0, 0, 0], end: [0, 0, 1],
         normal: [0, 1, 0], springs: seal_springs, stiffness: 1.0e4}
contacts:
  stop:
    type: impact
    bodies: [door, ground]
    geometry: {shape: sphere_plane, center: [0, 0, 0], radius: 0.01,
               plane_point: [0, stop_gap, 0], normal: [0, -1, 0]}
    stiffness: 1.0e8
"""


def test_mechanism_file_reads_its_parameters_in_numeric_fields(tmp_path: Path) -> None:
    path = tmp_path / "pad.mech.yaml"
    path.write_text(MECH, encoding="utf-8")
    model = load_mechanism(path).model
    assert model.contacts["stop"].geometry.plane_point[1] == pytest.approx(0.0013)
    assert model.forces["seal"].springs == 7
