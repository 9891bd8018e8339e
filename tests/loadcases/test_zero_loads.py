"""A load switched off by its parameters costs nothing: an expression with a constant factor
0 folds to 0, and a force or torque that is zero throughout is left out of the model unless
a request or an event names it."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.build.model import build_run
from loadcases.expressions import parse
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

CASE = """\
case: zero-loads
parameters: {pressure_on: 0, push: 5 N}
mechanism:
  gravity: [0, 0, -9.81]
  bodies:
    arm: {mass: 1, cm: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
  points:
    tip: {body: arm, at: [1, 0, 0]}
  joints:
    hinge: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 1, 0]}
  forces:
    pressure: {type: force, point: tip,
               value: [0, 0, "pressure_on * 1000 * step(angle(hinge), 0, 1, 0.5, 0)"]}
    side: {type: force, point: tip, value: ["push", 0, 0]}
    spare: {type: torque, body: arm, value: [0, "0 * t", 0]}
motions:
  hold: {joint: hinge, value: "0"}
analysis: {type: static}
requests:
  hold: {motion: hold, quantity: torque}
{extra}
"""


def _built(tmp_path: Path, extra: str = ""):
    path = tmp_path / "zero.case.yaml"
    path.write_text(CASE.replace("{extra}", extra), encoding="utf-8")
    return load_case(path), path


@pytest.mark.parametrize(
    "text, value",
    [("0 * angle(h)", 0.0), ("p * step(x(a), 0, 1, 1, 0)", 0.0), ("2 + x(a) * 0", 2.0)],
)
def test_a_zero_factor_folds_the_product(text: str, value: float) -> None:
    compiled = parse(text).compile({"p": 0.0})
    assert compiled.is_constant and compiled.value == value


def test_zero_loads_are_left_out_unless_named(tmp_path: Path) -> None:
    """pressure (pressure_on 0) and spare (0 * t) are not built; side (5 N, constant) is;
    requested, spare is built and reports 0; the holding torque is the weight's moment
    m g 0.5 m = 4.905 N*m (side pulls along the arm: no moment), 1e-9."""
    cf, _ = _built(tmp_path)
    built = build_run(cf)
    assert set(built.mechanism.forces) == {"side"}
    outcome = run_case(cf)
    assert abs(outcome.solution.channels["hold.value"][0]) == pytest.approx(9.81 * 0.5, abs=1e-9)
    cf, _ = _built(tmp_path, "  spare: {force: spare}")
    assert set(build_run(cf).mechanism.forces) == {"side", "spare"}
    assert run_case(cf).solution.channels["spare.ty"][0] == 0.0
