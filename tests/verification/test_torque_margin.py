"""Torque margin TM = sum D / sum R (seed 003 eq. 2.1) by hand at three angles.

Case `solar_array/torque_margin_panel.case.yaml`: a 2 kg panel (cm 0.5 m from the pin)
driven quasi-statically 0 -> 90 deg in 1 s under g along -y, so the pin carries
F_r = m g radially. Hand values from its header (spring k (pi - theta), friction capacity
mu r F_r + T_pret of eq. 2.2, linear harness table, damper c omega at the motion's rate,
inertia as an expression); tolerance 1e-9 relative (the only numerics are the pin
reaction of a static equilibrium, solved to machine precision).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import LIBRARY

CASE = LIBRARY / "solar_array" / "torque_margin_panel.case.yaml"
K, MU, R_PIN, T_PRET, MASS, G = 2.0, 0.2, 0.01, 0.05, 2.0, 9.81
C_DAMP, OMEGA, INERTIA_TORQUE = 0.1, math.pi / 2, 0.4 * 0.01


def _harness(theta: float) -> float:
    """Moment resisting deployment (N*m): the case's linear table 0.3 -> 0 -> -0.2."""
    return np.interp(theta, [0.0, math.pi / 4, math.pi / 2], [0.3, 0.0, -0.2])


def _hand(theta: float, k: float = K) -> tuple[float, float, float]:
    """(D, R, R at restart) with the case's factors (friction 1.5, harness 2 given,
    damper 1.5, inertia 1.1; restart: friction x 1.2, no damper, no inertia)."""
    h = _harness(theta)
    friction = MU * R_PIN * MASS * G + T_PRET
    driving = k * (math.pi - theta) + max(0.0, -h)
    static = 1.5 * friction + 2.0 * max(0.0, h)
    resistive = static + 1.5 * C_DAMP * OMEGA + 1.1 * INERTIA_TORQUE
    restart = 1.5 * 1.2 * friction + 2.0 * max(0.0, h)
    return driving, resistive, restart


@pytest.fixture(scope="module")
def outcome():
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    return run_case(load_case(CASE))


@pytest.mark.parametrize("time", [0.0, 0.3, 1.0])
def test_margin_by_hand(outcome, time: float) -> None:
    ch, t = outcome.solution.channels, outcome.solution.time
    i = int(np.argmin(np.abs(t - time)))
    theta = ch["tm_HL1.angle"][i]
    assert theta == pytest.approx(OMEGA * time, rel=1e-9, abs=1e-12)
    driving, resistive, restart = _hand(theta)
    assert ch["tm_HL1.driving"][i] == pytest.approx(driving, rel=1e-9)
    assert ch["tm_HL1.resistive"][i] == pytest.approx(resistive, rel=1e-9)
    assert ch["tm_HL1.ratio"][i] == pytest.approx(driving / resistive, rel=1e-9)
    assert ch["tm_HL1.restart_ratio"][i] == pytest.approx(driving / restart, rel=1e-9)
    assert ch["tm_HL1.excess"][i] == pytest.approx(driving - 2 * resistive, rel=1e-9)


def test_minimum_and_verdict(outcome) -> None:
    block = outcome.checks["torque_margin"]
    line = block["hinge_lines"]["HL1"]
    thetas = np.linspace(0, math.pi / 2, 2001)
    ratios = [d / r for d, r, _ in map(_hand, thetas)]
    # the rows are 4.5 deg apart: the sampled minimum is the minimum at t = 0 here
    assert line["min_ratio"] == pytest.approx(min(ratios), rel=1e-9)
    assert line["angle_of_min"] == 0.0 and block["passed"] and line["passed"]
    assert not any("torque margin" in w for w in outcome.warnings)
    assert "_tm_" not in "".join(outcome.solution.channels)


def test_weak_spring_fails_the_check() -> None:
    """k = 0.1 N*m/rad: D(90 deg) = 0.157 + 0.2 < 2 R: the check fails, the run is ok."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    weak = run_case(load_case(CASE, overrides={"k_drive": 0.1}))
    block = weak.checks["torque_margin"]
    assert weak.solution.status == "ok" and not block["passed"]
    line = block["hinge_lines"]["HL1"]
    d, r, _ = _hand(line["angle_of_min"], k=0.1)
    assert line["min_ratio"] == pytest.approx(d / r, rel=1e-9) and line["min_ratio"] < 2
    assert any("check failed" in w for w in weak.solution.warnings)


def test_bad_contributor_is_an_input_error(tmp_path) -> None:
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    text = CASE.read_text().replace("pin_friction: friction", "pin_frixion: friction")
    bad = tmp_path / "bad.case.yaml"
    bad.write_text(text)
    with pytest.raises(InputError) as error:
        run_case(load_case(bad))
    (d,) = error.value.diagnostics
    assert d.key == "torque_margin.hinge_lines.HL1.contributors.pin_frixion"
    assert d.line > 1 and "joint_friction" in d.message
    assert d.hint == "did you mean 'pin_friction'?"
