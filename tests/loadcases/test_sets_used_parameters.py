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
    (tmp_path / "s.set.yaml").write_text("set: s\ncases: ['*.case.yaml']\n"
                                          "sweep: {wind: [0, 1, -1]}\n")
    compiled = load_and_compile_set(tmp_path / "s.set.yaml")
    names = sorted(run.name for run in compiled.runs)
    assert names == ["calm", "windy[wind=-1]", "windy[wind=0]", "windy[wind=1]"]
