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
