"""System torque margin of synchronised hinge lines (issue 37 item 6; definition in
loadcases/build/system_margin.py) by hand.

Two panels turned quasi-statically in step, theta2 = 2 theta1 (as a cable loop of pulley
ratio 2 would keep them; here motions impose it), gravity off:
  HL1: spring k1 (pi/2 - theta1), damper 1.5 c w1 (resistive, factor 1.5)
  HL2: spring k2 (2 pi/3 - theta2), friction 1.5 T (a preload, mu 0)
Virtual work about HL1 (w2 / w1 = 2): D = D1 + 2 D2, R = R1 + 2 R2, TM = D / R; restart
(no damper, friction x 1.25): R = 2 x 1.25 x 1.5 T. Tolerance 1e-9 (closed forms; the only
numerics are the motions' rates, exact).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

K1, K2, C, T = 1.0, 0.2, 0.2, 0.3
W1, W2 = math.pi / 6, math.pi / 3  # rad/s

CASE = """\
case: two-lines
units: {angle: deg}
mechanism:
  bodies:
    panel_1: {mass: 1, cm: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
    panel_2: {mass: 1, cm: [0.5, 0, 1], inertia: [0.01, 0.1, 0.1]}
  joints:
    hl1: {type: revolute, bodies: [panel_1, ground], at: [0, 0, 0], axis: [0, 0, 1]}
    hl2: {type: revolute, bodies: [panel_2, ground], at: [0, 0, 1], axis: [0, 0, 1]}
  forces:
    spring_1: {type: torsion_spring, joint: hl1, stiffness: 1, angle0: 90}
    damper_1: {type: damper, joint: hl1, damping: 0.2}
    spring_2: {type: torsion_spring, joint: hl2, stiffness: 0.2, angle0: 120}
    friction_2: {type: joint_friction, joint: hl2, mu: 0, pin_radius: 0.01, preload: 0.3}
effects: {gravity: false}
motions:
  m1: {joint: hl1, value: "30*deg * t"}
  m2: {joint: hl2, value: "60*deg * t"}
analysis: {type: quasi-static, end: 1.0, step: 0.25}
requests:
  a1: {joint: hl1, quantity: angle}
torque_margin:
  restart_friction: 1.25
  SYSTEM
  hinge_lines:
    HL1: {joint: hl1, contributors: {spring_1: spring, damper_1: damper}}
    HL2: {joint: hl2, contributors: {spring_2: spring, friction_2: friction}}
"""


def _case(tmp_path: Path, system: str = "system: true", replace=("", "")) -> Path:
    path = tmp_path / "two.case.yaml"
    path.write_text(CASE.replace("SYSTEM", system).replace(*replace), "utf-8")
    return path


def test_system_margin_by_hand(tmp_path: Path) -> None:
    outcome = run_case(load_case(_case(tmp_path)))
    ch, t = outcome.solution.channels, outcome.solution.time
    theta1, theta2 = W1 * t, W2 * t
    d = K1 * (math.pi / 2 - theta1) + 2 * K2 * (2 * math.pi / 3 - theta2)
    r = 1.5 * C * W1 + 2 * 1.5 * T
    assert ch["tm_system.driving"] == pytest.approx(d, rel=1e-9)
    assert ch["tm_system.resistive"] == pytest.approx(np.full_like(t, r), rel=1e-9)
    assert ch["tm_system.ratio"] == pytest.approx(d / r, rel=1e-9)
    assert ch["tm_system.restart_ratio"] == pytest.approx(d / (2 * 1.25 * 1.5 * T), rel=1e-9)
    assert ch["tm_system.angle"] == pytest.approx(theta1, rel=1e-9, abs=1e-15)
    block = outcome.checks["torque_margin"]
    system = block["system"]
    assert system["reference"] == "HL1"
    assert system["min_ratio"] == pytest.approx(d[-1] / r, rel=1e-9)  # at the end, 30 deg
    # the per-line margins are eq. 2.1's, and they alone decide `passed`
    assert ch["tm_HL2.ratio"] == pytest.approx(
        K2 * (2 * math.pi / 3 - theta2) / (1.5 * T), rel=1e-9
    )
    line_ok = all(v["passed"] for v in block["hinge_lines"].values())
    assert block["passed"] == line_ok
    assert outcome.column_units["tm_system.driving"] == "N*m"


def test_system_margin_off_costs_nothing(tmp_path: Path) -> None:
    """Without `system: true` no system column and no rate request."""
    channels = run_case(load_case(_case(tmp_path, system=""))).solution.channels
    assert not any(c.startswith("tm_system") for c in channels)
    assert not any("_rate" in c for c in channels)


def test_system_margin_input_errors(tmp_path: Path) -> None:
    """One hinge line, or a hinge line named `system`, is an input error at its key."""
    second = "    HL2: {joint: hl2, contributors: {spring_2: spring, friction_2: friction}}\n"
    one_line = _case(tmp_path, replace=(second, ""))
    with pytest.raises(InputError, match="two hinge lines or more") as error:
        run_case(load_case(one_line))
    assert error.value.diagnostics[0].key == "torque_margin.system"
    clash = _case(tmp_path, replace=("    HL2: {joint", "    system: {joint"))
    with pytest.raises(InputError, match="rename this hinge line"):
        run_case(load_case(clash))
