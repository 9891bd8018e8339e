"""The energy request from YAML (`NAME: {quantity: energy}`): its columns and units in the
results, and the torsion spring's swing balanced (closed form: the energy k theta0^2 / 2
turns into kinetic energy and back)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from loadcases.run import run_file

CASE = """\
case: swing
units: {angle: deg}
mechanism:
  bodies:
    panel: {mass: 1, cm: [0, 0, 0], inertia: [0.5, 0.5, 0.5]}
  joints:
    hinge: {type: revolute, bodies: [panel, ground], at: [0, 0, 0], axis: [0, 0, 1]}
  forces:
    spring: {type: torsion_spring, joint: hinge, stiffness: "2 N*m/rad", angle0: 60}
analysis: {type: dynamic, end: 1.0, step: 0.005, tolerance: 1.0e-9}
requests:
  energy: {quantity: energy}
"""
COMPONENTS = ("kinetic", "gravitational", "elastic", "drive_work", "load_work", "dissipated")


def test_energy_request_columns_and_balance(tmp_path: Path) -> None:
    """Columns energy.kinetic ... energy.balance in J; the spring's energy k (pi/3)^2 / 2
    = 1.0966 J at the start, kinetic + elastic constant within 1e-5 J
    (balance column; measured 4.5e-6 J with the dense output of 0.7.0, 1.2e-6 J with
    `output: steps`: generalized-alpha's numerical damping),
    no gravity, drive, load work or dissipation."""
    path = tmp_path / "swing.case.yaml"
    path.write_text(CASE, encoding="utf-8")
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    sol = outcome.solution
    assert sol.ok, sol.message
    columns = [c for c in sol.channels if c.startswith("energy.")]
    assert columns == [f"energy.{c}" for c in (*COMPONENTS, "balance")]
    e0 = 0.5 * 2.0 * (np.pi / 3) ** 2
    assert sol.channels["energy.elastic"][0] == pytest.approx(e0, rel=1e-12)
    total = sol.channels["energy.kinetic"] + sol.channels["energy.elastic"]
    assert sol.channels["energy.kinetic"].max() > 0.9 * e0
    assert np.abs(total - e0).max() < 1e-5
    assert np.abs(sol.channels["energy.balance"]).max() < 1e-5
    for quiet in ("gravitational", "drive_work", "load_work", "dissipated"):
        assert np.abs(sol.channels[f"energy.{quiet}"]).max() == 0.0
    summary = json.loads(next((tmp_path / "out").glob("*.summary.json")).read_text())
    assert "J" in json.dumps(summary)


def test_energy_request_on_a_flexible_body_validates(tmp_path: Path) -> None:
    """The energy request covers flexible bodies (modal kinetic and strain energy, modal
    damping: tests/mechlib/test_flexible_mechanism.py checks the balance): a case asking
    for it validates, with the body flexible or made rigid."""
    from typer.testing import CliRunner

    from cli.app import app

    library = Path(__file__).parents[2] / "loadcases" / "library" / "examples" / "flexible"
    text = (library / "flexible_pendulum.case.yaml").read_text()
    text = text.replace("requests:\n", "requests:\n  energy: {quantity: energy}\n", 1)
    case = tmp_path / "flex.case.yaml"
    case.write_text(text)
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 0, result.output
    rigid = tmp_path / "rigid.case.yaml"
    rigid.write_text(
        text.replace("case: flexible-pendulum\n", "case: rigid\neffects: {flexibility: false}\n")
    )
    result = CliRunner().invoke(app, ["validate", str(rigid)])
    assert result.exit_code == 0, result.output
