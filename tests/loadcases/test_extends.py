"""`extends:` in a mechanism file: the base's items, those named again replaced whole,
`remove:`, errors at the file and line where the item was written, cycles refused, the
base's content in the input hash."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case, load_mechanism

BASE = """\
name: base-door
units: {length: mm}
gravity: [0, -9.81, 0]
parameters:
  k: 50 N*m/rad
  damping_c: 0.5
bodies:
  door: {mass: 10, cm: [500, 0, 0], inertia: [0.1, 1, 1]}
points:
  tip: {body: door, at: [1000, 0, 0]}
  eye: {body: door, at: [200, 0, 0]}
joints:
  hinge: {type: revolute, bodies: [door, ground], at: [0, 0, 0], axis: [0, 0, 1]}
forces:
  coil: {type: torsion_spring, joint: hinge, stiffness: k, damping: damping_c}
  rub: {type: joint_friction, joint: hinge, mu: 0.1, pin_radius: 10}
"""

DERIVED = """\
extends: base.mech.yaml
remove: [rub, eye, parameters.damping_c]
name: heavy-door
parameters:
  k: 100 N*m/rad
bodies:
  door: {mass: 20, cm: [500, 0, 0], inertia: [0.2, 2, 2]}
forces:
  coil: {type: torsion_spring, joint: hinge, stiffness: k}
  wind: {type: torque, body: door, value: [0, 0, 1], frame: ground}
"""


def _files(tmp_path: Path, derived: str = DERIVED, base: str = BASE) -> Path:
    (tmp_path / "base.mech.yaml").write_text(base, encoding="utf-8")
    path = tmp_path / "derived.mech.yaml"
    path.write_text(derived, encoding="utf-8")
    return path


def test_overrides_replace_whole_items_and_removals_drop(tmp_path: Path) -> None:
    """Items named again replace the base's whole (the spring's damping is gone with the
    base's item), new ones follow the base's, removed ones are gone, the rest is the
    base's (in the base's units: mm)."""
    model = load_mechanism(_files(tmp_path)).model
    assert model.name == "heavy-door"
    assert model.bodies["door"].mass == 20.0
    assert list(model.forces) == ["coil", "wind"]
    assert model.forces["coil"].damping in (None, 0.0)
    assert list(model.points) == ["tip"]
    assert model.points["tip"].at == pytest.approx((1.0, 0.0, 0.0))
    assert set(model.parameters) == {"k"}
    assert model.gravity == pytest.approx((0.0, -9.81, 0.0))


def test_errors_name_the_file_that_wrote_the_item(tmp_path: Path) -> None:
    """A bad key in a base item is reported in the base file at its line; one in the
    derived file's own item in the derived file."""
    base = BASE.replace("pin_radius: 10}", "pin_radius: 10, colour: red}")
    derived = DERIVED.replace("rub, ", "").replace("frame: ground}", "frame: ground, colour: 1}")
    path = _files(tmp_path, derived, base)
    with pytest.raises(InputError) as raised:
        load_mechanism(path)
    errors = {d.key: d for d in raised.value.diagnostics if d.severity == "error"}
    colour = next(d for k, d in errors.items() if k.startswith("forces.rub"))
    assert Path(colour.file).name == "base.mech.yaml" and colour.line == 16
    frame = next(d for k, d in errors.items() if k.startswith("forces.wind"))
    assert Path(frame.file).name == "derived.mech.yaml" and frame.line == 10


@pytest.mark.parametrize(
    ("derived", "key", "message"),
    [
        ("extends: base.mech.yaml\nremove: [latch]\n", "remove[0]", "no item 'latch'"),
        ("extends: missing.mech.yaml\n", "extends", "base mechanism file not found"),
        ("extends: ../base.mech.yaml\n", "extends", "leaves the folder"),
        ("extends: derived.mech.yaml\n", "extends", "extend in a cycle"),
        (
            "extends: base.mech.yaml\nunits: {length: m}\n",
            "units",
            "units differ from those of the base",
        ),
        (
            "extends: base.mech.yaml\nremove: [coil]\nforces:\n  coil: {type: torsion_spring, "
            "joint: hinge, stiffness: 1}\n",
            "remove[0]",
            "removed and defined again",
        ),
    ],
)
def test_bad_extends_at_its_key(tmp_path: Path, derived: str, key: str, message: str) -> None:
    """Each problem of `extends:`/`remove:` is an error at its key in the derived file."""
    path = _files(tmp_path, derived)
    with pytest.raises(InputError) as raised:
        load_mechanism(path)
    found = [d for d in raised.value.diagnostics if d.severity == "error"]
    assert [d.key for d in found] == [key], found
    assert message in found[0].message and found[0].file == str(path)


def test_a_cycle_through_two_files_is_refused(tmp_path: Path) -> None:
    """a extends b extends a: refused (never a recursion error)."""
    (tmp_path / "a.mech.yaml").write_text("extends: b.mech.yaml\n", encoding="utf-8")
    (tmp_path / "b.mech.yaml").write_text("extends: a.mech.yaml\n", encoding="utf-8")
    with pytest.raises(InputError) as raised:
        load_mechanism(tmp_path / "a.mech.yaml")
    assert any("cycle" in d.message for d in raised.value.diagnostics)


def test_the_base_is_part_of_the_input_hash(tmp_path: Path) -> None:
    """A case on the derived file: changing the base alone changes its input hash."""
    _files(tmp_path)
    case = tmp_path / "swing.case.yaml"
    case.write_text(
        "case: swing\nmechanism: derived.mech.yaml\nanalysis: {type: static}\n"
        "requests:\n  angle: {joint: hinge, quantity: angle}\n",
        encoding="utf-8",
    )
    first = load_case(case).input_sha256
    (tmp_path / "base.mech.yaml").write_text(BASE.replace("mass: 10", "mass: 11"), "utf-8")
    assert load_case(case).input_sha256 != first


def test_extends_in_an_inline_mechanism_is_refused(tmp_path: Path) -> None:
    """An inline mechanism cannot extend (never ignored): an error at its key."""
    _files(tmp_path)
    case = tmp_path / "inline.case.yaml"
    case.write_text(
        "case: inline\nmechanism:\n  extends: base.mech.yaml\n  bodies: {}\n"
        "analysis: {type: static}\n",
        encoding="utf-8",
    )
    with pytest.raises(InputError) as raised:
        load_case(case)
    keys = [d.key for d in raised.value.diagnostics if d.severity == "error"]
    assert keys == ["mechanism.extends"]
