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
