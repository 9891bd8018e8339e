"""Tiny mechanisms, cases and sets written into a test's tmp folder (fast kinematic runs)."""

from __future__ import annotations

from pathlib import Path

# a one-panel torque-margin case (every contributor kind), shared by set tests
TM_PANEL_CASE = (
    Path(__file__).resolve().parents[2]
    / "loadcases"
    / "library"
    / "verification"
    / "solar_array"
    / "torque_margin_panel.case.yaml"
)
CRANK_MECH = """\
name: crank
gravity: [0, -9.81, 0]
parameters: {speed: 1.0, load: 10.0, stroke: 0.05}
bodies:
  crank: {mass: 1.0, cm: [0.05, 0, 0], inertia: [0.0001, 0.001, 0.001]}
points:
  tip: {body: crank, at: [0.1, 0, 0]}
joints:
  pivot: {type: revolute, bodies: [crank, ground], at: [0, 0, 0], axis: [0, 0, 1]}
forces:
  push: {type: force, point: tip, value: [0, "-load", 0], frame: ground}
"""

CRANK_CASE = """\
case: crank-turn
mechanism: crank.mech.yaml
motions:
  drive: {joint: pivot, value: "speed * t"}
analysis: {type: kinematic, end: 0.5, step: 0.05}
requests:
  pivot_force: {joint: pivot, quantity: force, frame: ground}
  drive_torque: {motion: drive, quantity: torque}
abscissa: "angle(pivot)"
"""

# A slider-crank driven by its slider: out of reach (x > 0.4 m) when stroke * 1 s > 0.117 m.
SLIDER_MECH = """\
name: slider
gravity: [0, -9.81, 0]
parameters: {stroke: 0.05}
bodies:
  crank:  {mass: 1.0, cm: [0, 0.05, 0], inertia: [0.001, 0.0001, 0.001]}
  rod:    {mass: 0.5, cm: [0.141421, 0.05, 0], inertia: [0.0001, 0.004, 0.004]}
  slider: {mass: 2.0, cm: [0.282843, 0, 0], inertia: [0.001, 0.001, 0.001]}
joints:
  pivot: {type: revolute, bodies: [crank, ground], at: [0, 0, 0], axis: [0, 0, 1]}
  big:   {type: spherical, bodies: [rod, crank], at: [0, 0.1, 0]}
  small: {type: universal, bodies: [slider, rod], at: [0.282843, 0, 0],
         axes: [[0, 0, 1], [0.333333, 0.942809, 0]]}
  guide: {type: prismatic, bodies: [slider, ground], at: [0.282843, 0, 0], axis: [1, 0, 0]}
"""

SLIDER_CASE = """\
case: slider-push
mechanism: slider.mech.yaml
motions:
  push: {joint: guide, value: "stroke * t"}
analysis: {type: kinematic, end: 1.0, step: 0.05}
requests:
  pivot_force: {joint: pivot, quantity: force, frame: ground}
  push_force: {motion: push, quantity: force}
"""

SET_3X2 = """\
set: crank-set
cases: [crank.case.yaml]
sweep:
  speed: [1.0, 2.0, 3.0]
  load: ["10 N", "20 N"]
factors: {ultimate: 1.5}
allowables:
  drive_torque.value: {max: 2.5, min: -2.5}
report: {output: crank-envelope.xlsx}
"""

SET_FAILING = """\
set: slider-set
cases: [slider.case.yaml, crank.case.yaml]
sweep: {stroke: [0.05, 0.2]}
report: {output: slider.xlsx}
"""


def write_inputs(folder: Path) -> Path:
    """Write every mechanism, case and set file into `folder`; return `folder`."""
    files = {
        "crank.mech.yaml": CRANK_MECH,
        "crank.case.yaml": CRANK_CASE,
        "slider.mech.yaml": SLIDER_MECH,
        "slider.case.yaml": SLIDER_CASE,
        "crank.set.yaml": SET_3X2,
        "slider.set.yaml": SET_FAILING,
    }
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    return folder
