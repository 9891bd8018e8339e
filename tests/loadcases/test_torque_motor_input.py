"""Input of the jet-pipe torque motor: the linear law or the reluctance law, not both; the
reluctance law's values positive (an input error at file, line and key, exit 2)."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case

ROD_END = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "rod_end"
MOTOR = "      torque_motor: {pole_area: 4 cm^2, air_gap: 0.5 mm,"


@pytest.mark.parametrize(
    ("new", "expected"),
    [
        (
            "      motor_gain: 1000\n" + MOTOR,
            "give 'motor_gain' (linear law) or 'torque_motor', not both",
        ),
        (MOTOR.replace("0.5 mm", "-0.5 mm"), "air_gap"),
    ],
)
def test_bad_torque_motor_is_an_input_error(tmp_path: Path, new: str, expected: str) -> None:
    mech = (ROD_END / "rod_end.mech.yaml").read_text()
    assert MOTOR in mech
    (tmp_path / "rod_end.mech.yaml").write_text(mech.replace(MOTOR, new))
    case = (ROD_END / "extend_retract_servo.case.yaml").read_text()
    (tmp_path / "servo.case.yaml").write_text(case)
    with pytest.raises(InputError) as caught:
        load_case(tmp_path / "servo.case.yaml")
    messages = [d.format() for d in caught.value.diagnostics if d.severity == "error"]
    assert any(expected in m and "rod_end.mech.yaml:" in m and "jet_pipe" in m for m in messages), (
        messages
    )
