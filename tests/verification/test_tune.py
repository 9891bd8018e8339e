"""`loads tune` (seed 003 appendix A): root finding on a modes analysis.

- One-DOF rotor (I = 0.5 kg*m^2): the tuned stiffness equals I (2 pi f)^2 within 1e-6
  relative (measured 1e-12; brentq to rtol 1e-12).
- Two panels on a held hinge line (library `solar_array/bepicolombo_latch_tuning.case.yaml`):
  in tests/verification/test_solar_array.py (4.1672 Hz within 1e-4 Hz, stiffness vs the
  exact 2 x 2 eigenvalue problem within 1e-6).
- Bad input exits 2 naming the key; an unreachable target exits 1.
"""

from __future__ import annotations

import math

import pytest
from conftest import LIBRARY
from typer.testing import CliRunner

ROTOR = LIBRARY / "solar_array" / "rotor_modes.case.yaml"
TARGET = 4.1672


def test_rotor_closed_form() -> None:
    from loadcases.studies.tune import tune_parameter

    result = tune_parameter(ROTOR, parameter="k_latch", mode=1, target=TARGET)
    expected = 0.5 * (2 * math.pi * TARGET) ** 2
    assert result.value == pytest.approx(expected, rel=1e-6)
    assert result.frequency == pytest.approx(TARGET, abs=1e-9)
    assert 3 <= result.iterations <= 20


def test_cli_reports_iterations_and_exit_codes() -> None:
    from cli.app import app

    runner = CliRunner()
    ok = runner.invoke(
        app, ["tune", str(ROTOR), "--parameter", "k_latch", "--mode", "1", "--target", "4.1672 Hz"]
    )
    assert ok.exit_code == 0, ok.output
    assert "gives mode 1 = 4.1672000 Hz" in ok.output and "evaluations" in ok.output
    unknown = runner.invoke(
        app, ["tune", str(ROTOR), "--parameter", "k_lacth", "--mode", "1", "--target", "4 Hz"]
    )
    assert unknown.exit_code == 2 and "no parameter 'k_lacth'" in unknown.output
    wrong_unit = runner.invoke(
        app, ["tune", str(ROTOR), "--parameter", "k_latch", "--mode", "1", "--target", "4 m"]
    )
    assert wrong_unit.exit_code == 2 and "frequency" in wrong_unit.output
    too_many = runner.invoke(
        app, ["tune", str(ROTOR), "--parameter", "k_latch", "--mode", "2", "--target", "4 Hz"]
    )
    assert too_many.exit_code == 2 and "has 1 modes" in too_many.output


def test_unreachable_target_fails(tmp_path) -> None:
    """A mode that does not depend on the parameter: no bracket (TuneError, exit 1)."""
    from loadcases.studies.tune import TuneError, tune_parameter

    text = (
        ROTOR.read_text()
        .replace("stiffness: k_latch", "stiffness: 100")
        .replace('k_latch: "100 N*m/rad"', 'k_latch: "100 N*m/rad"\n    unused: 3')
    )
    case = tmp_path / "flat.case.yaml"
    case.write_text(text)
    with pytest.raises(TuneError, match="no value"):
        tune_parameter(case, parameter="unused", mode=1, target=TARGET)


PANEL = LIBRARY / "solar_array" / "torque_margin_panel.case.yaml"
# the panel case's header: friction capacity 0.2 * 0.01 * 2 * 9.81 + 0.05, damper
# 1.5 * 0.1 * pi/2, inertia 1.1 * 0.4 * 0.01; harness 0.3 N*m resisting (factor 2) at 0 deg,
# 0.2 N*m driving at 90 deg
_STATIC = 1.5 * (0.2 * 0.01 * 2 * 9.81 + 0.05) + 1.5 * 0.1 * math.pi / 2 + 1.1 * 0.4 * 0.01
R_STOWED, R_DEPLOYED = _STATIC + 2 * 0.3, _STATIC


def test_spring_stiffness_for_a_target_margin() -> None:
    """TM = k pi / R(0) at the stowed row, where the minimum lies: k = 2 R(0) / pi = 0.61999
    N*m/rad within 1e-9; the case re-run with it gives TM 2 within 1e-9 (the issue asks
    1 %)."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case
    from loadcases.studies.tune import tune_margin

    result = tune_margin(PANEL, parameter="k_drive", hinge_line="HL1")
    assert result.target == 2.0 and result.mode is None
    assert result.value == pytest.approx(2 * R_STOWED / math.pi, rel=1e-9)
    again = run_case(load_case(PANEL, overrides={"k_drive": result.value}))
    line = again.checks["torque_margin"]["hinge_lines"]["HL1"]
    assert line["min_ratio"] == pytest.approx(2.0, rel=1e-9) and line["angle_of_min"] == 0.0
    assert line["min_ratio"] >= 2.0 and line["passed"]  # the value met, not a hair below


def test_wind_up_for_a_target_margin(tmp_path) -> None:
    """The spring's free angle w as the parameter: a small wind-up fails at the deployed end
    (90 deg), where D = k (w - pi/2) + 0.2 (the harness drives) and R = R_deployed: TM 2 at
    w = pi/2 + (2 R_deployed - 0.2) / k = 105.69 deg, within 1e-9 (the stowed TM is then
    3.8)."""
    from loadcases.studies.tune import tune_margin

    case = tmp_path / "windup.case.yaml"
    case.write_text(
        PANEL.read_text()
        .replace('k_drive: "2 N*m/rad"', 'k_drive: "2 N*m/rad"\n    windup: 150 deg')
        .replace("angle0: 180", "angle0: windup")
    )
    result = tune_margin(case, parameter="windup", hinge_line="HL1", target=2.0)
    assert result.value == pytest.approx(math.pi / 2 + (2 * R_DEPLOYED - 0.2) / 2.0, rel=1e-9)
    assert result.achieved == pytest.approx(2.0, rel=1e-9)


def test_cli_margin_tuning_and_its_errors() -> None:
    from cli.app import app

    runner = CliRunner()
    base = ["tune", str(PANEL), "--parameter", "k_drive"]
    ok = runner.invoke(app, [*base, "--margin", "HL1", "--target", "2.5"])
    assert ok.exit_code == 0, ok.output
    assert "gives TM HL1 = 2.5 (target 2.5," in ok.output
    unknown = runner.invoke(app, [*base, "--margin", "HL9"])
    assert unknown.exit_code == 2 and "no hinge line 'HL9'" in unknown.output
    no_tm = runner.invoke(app, ["tune", str(ROTOR), "--parameter", "k_latch", "--margin", "HL1"])
    assert no_tm.exit_code == 2 and "hinge lines: none" in no_tm.output
    both = runner.invoke(app, [*base, "--margin", "HL1", "--mode", "1"])
    assert both.exit_code == 2 and "one of them" in both.output
    bad = runner.invoke(app, [*base, "--margin", "HL1", "--target", "2 Hz"])
    assert bad.exit_code == 2 and "give a ratio" in bad.output


def test_spring_for_a_target_system_margin(tmp_path) -> None:
    """`--margin system` on the two-line case of test_system_margin: its minimum is at the
    end (theta1 = 30 deg), D = k1 (pi/2 - pi/6) + 2 k2 (2 pi/3 - pi/3), R = 1.5 c w1 +
    2 x 1.5 T: k1 = (2 R - 2 k2 pi/3) / (pi/3) within 1e-9."""
    from loadcases.studies.tune import tune_margin
    from tests.verification.test_system_margin import CASE

    case = tmp_path / "two.case.yaml"
    case.write_text(
        CASE.replace("SYSTEM", "system: true")
        .replace("stiffness: 1, angle0: 90", "stiffness: k1, angle0: 90")
        .replace("mechanism:\n", "mechanism:\n  parameters: {k1: 1}\n"),
        "utf-8",
    )
    result = tune_margin(case, parameter="k1", hinge_line="system", target=2.0)
    r = 1.5 * 0.2 * math.pi / 6 + 2 * 1.5 * 0.3
    assert result.value == pytest.approx((2 * r - 2 * 0.2 * math.pi / 3) / (math.pi / 3), rel=1e-9)
    assert result.achieved >= 2.0
