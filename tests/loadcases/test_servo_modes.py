"""A servo-actuator in a `modes` analysis (issue 36 item 6): `lag` is linearised as its oil
column, `valve` is refused at validate (its chamber pressures follow the piston flow, which
the static equilibrium a modes analysis linearises about does not have).

Reference (closed form, Merritt, Hydraulic Control Systems, 1967): the 100 kg rod of the
library's servo rig on its prismatic guide, held by the oil columns of a cylinder with
A1 = A2 = 10 cm^2, beta = 0.8 GPa and chambers of V = V0 + A * 50 mm at mid-stroke
(V0 = 20 cm^3 dead volume each): k_h = beta A^2 (1/V1 + 1/V2) = 2.2857e7 N/m and the one
mode at f = sqrt(k_h / m) / (2 pi) = 76.0906 Hz.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.build.model import build_run
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.elements.hydraulics.command import held_value

RIG = (
    Path(__file__).resolve().parents[2]
    / "loadcases/library/verification/elements/servo_actuator.case.yaml"
)


def _modes_case(folder: Path, fidelity: str, analysis: str = "{type: modes}") -> Path:
    text = RIG.read_text(encoding="utf-8")
    text = text.replace("fidelity: valve", f"fidelity: {fidelity}")
    text = text.replace(
        "analysis: {type: dynamic, end: 0.2, step: 0.0005}", f"analysis: {analysis}"
    )
    text = text.replace("  actuator: {force: actuator, quantity: force}\n", "")
    path = folder / f"{fidelity}.case.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_lag_actuator_in_modes_is_its_oil_column(tmp_path: Path) -> None:
    area, beta, mass = 10e-4, 0.8e9, 100.0
    volume = 20e-6 + area * 0.05
    k_h = beta * area**2 * 2.0 / volume
    expected = math.sqrt(k_h / mass) / (2.0 * math.pi)
    outcome = run_case(load_case(_modes_case(tmp_path, "lag")))
    assert outcome.solution.status == "ok"
    frequencies = outcome.solution.channels["mode.frequency"]
    assert frequencies.tolist() == pytest.approx([expected], rel=1e-8)  # measured 2.6e-10


@pytest.mark.parametrize("analysis", ["{type: modes}", "{type: static}"])
def test_a_valve_actuator_in_an_equilibrium_analysis_is_refused_at_validate(
    tmp_path: Path, analysis: str
) -> None:
    path = _modes_case(tmp_path, "valve", analysis)
    with pytest.raises(InputError) as error:
        build_run(load_case(path))
    (diagnostic,) = error.value.diagnostics
    assert diagnostic.key == "analysis.type" and diagnostic.line == 34
    kind = analysis.split()[1].rstrip("}")
    assert f"servo actuator 'actuator' (valve) cannot act in a {kind} analysis" in (
        diagnostic.message
    )
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2
    assert "fidelity lag" in result.output and "singular" not in result.output


@pytest.mark.parametrize(
    ("command", "held", "at_half"),
    [
        ('"step_size"', 0.001, 0.001),
        ('"2 * step_size"', 0.002, 0.002),
        ('"step(t, 0, 0, 1, step_size)"', None, 5e-4),
    ],
)
def test_a_constant_command_is_held_and_one_in_time_is_not(
    tmp_path: Path, command: str, held: float | None, at_half: float
) -> None:
    """A command that folds to a number (a parameter, arithmetic of parameters) is built as
    a HeldDemand, which the compiled whole runs read once (mechlib.elements.hydraulics.
    command); one in time stays a function of time: both give the demand (m) at t."""
    text = RIG.read_text(encoding="utf-8").replace('command: "step_size"', f"command: {command}")
    path = tmp_path / "rig.case.yaml"
    path.write_text(text, encoding="utf-8")
    actuator = build_run(load_case(path)).mechanism.forces["actuator"]
    if held is None:
        assert held_value(actuator.command) is None
    else:
        assert held_value(actuator.command) == pytest.approx(held, rel=1e-15)
    assert actuator.command(0.5) == pytest.approx(at_half, rel=1e-12)
