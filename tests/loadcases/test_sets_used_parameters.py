"""A swept parameter multiplies only the cases that use it: a mechanism parameter read only
by a force element that a case leaves out (`loads:`) does not multiply that case."""

from __future__ import annotations

from pathlib import Path

from loadcases.sets.specs import load_and_compile_set

MECH = """\
name: bar
gravity: [0, -9.81, 0]
parameters: {wind: 0}
bodies:
  bar: {mass: 2, cm: [0.5, 0, 0], inertia: [0.01, 0.2, 0.2]}
joints:
  hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
forces:
  gust: {type: torque, body: bar, value: [0, 0, "wind * 10"]}
  spring: {type: torsion_spring, joint: hinge, stiffness: 100}
"""
CASE = """\
case: {name}
mechanism: bar.mech.yaml
{loads}
analysis: {{type: static}}
requests:
  angle: {{joint: hinge, quantity: angle}}
"""


def test_only_cases_using_a_swept_parameter_are_multiplied(tmp_path: Path) -> None:
    (tmp_path / "bar.mech.yaml").write_text(MECH)
    (tmp_path / "windy.case.yaml").write_text(CASE.format(name="windy", loads=""))
    (tmp_path / "calm.case.yaml").write_text(CASE.format(name="calm", loads="loads: [spring]"))
    (tmp_path / "s.set.yaml").write_text(
        "set: s\ncases: ['*.case.yaml']\nsweep: {wind: [0, 1, -1]}\n"
    )
    compiled = load_and_compile_set(tmp_path / "s.set.yaml")
    names = sorted(run.name for run in compiled.runs)
    assert names == ["calm", "windy[wind=-1]", "windy[wind=0]", "windy[wind=1]"]


def test_a_parameter_named_in_a_numeric_field_of_a_left_out_element_does_not_multiply(
    tmp_path: Path,
) -> None:
    """The landing-gear repro (shared/repro/landing-gear): `act_damping` is the `damping`
    field of a spring that `retract-qs` leaves out of its `loads:`; the case ran once per
    value of it with byte-identical results. Only `wind` (an expression of a load the case
    keeps) may multiply it; a case keeping the spring is multiplied by `damping` too."""
    mech = MECH.replace("parameters: {wind: 0}", "parameters: {wind: 0, damping: 1}").replace(
        "stiffness: 100}", "stiffness: 100, damping: damping}"
    )
    (tmp_path / "bar.mech.yaml").write_text(mech)
    (tmp_path / "kept.case.yaml").write_text(CASE.format(name="kept", loads=""))
    (tmp_path / "left.case.yaml").write_text(CASE.format(name="left", loads="loads: [gust]"))
    (tmp_path / "s.set.yaml").write_text(
        "set: s\ncases: ['*.case.yaml']\nsweep: {wind: [0, 1], damping: [1, 2]}\n"
    )
    names = sorted(run.name for run in load_and_compile_set(tmp_path / "s.set.yaml").runs)
    assert names == [
        "kept[wind=0,damping=1]",
        "kept[wind=0,damping=2]",
        "kept[wind=1,damping=1]",
        "kept[wind=1,damping=2]",
        "left[wind=0]",
        "left[wind=1]",
    ]
