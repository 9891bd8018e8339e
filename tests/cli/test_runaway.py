"""Runs that cannot finish: a load growing without bound, a step limit, and their input
checks (`analysis.max_steps`), through the command line (exit status, rows kept, message)."""

from __future__ import annotations

import csv
import json
import math
import shutil
import time
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from cli.app import app

runner = CliRunner()
LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"
INERTIA = 0.1  # kg*m^2 about the axle
SPIN_AT = 0.05  # s, the event that switches the torque exp(100 t) N*m on

SPIN = """\
case: spin
mechanism:
  gravity: [0, 0, 0]
  bodies:
    wheel: {{mass: 1, cm: [0, 0, 0], inertia: [0.1, 0.1, {inertia}]}}
  joints:
    axle: {{type: revolute, bodies: [wheel, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
  forces:
    spin_up: {{type: torque, body: wheel, value: [0, 0, "exp(100*t)"], active: false}}
events:
  spin: {{when: "t >= {spin_at}", then: [{{activate: spin_up}}]}}
analysis: {{type: dynamic, end: 10.0, step: 0.01{extra}}}
requests:
  angle: {{joint: axle, quantity: angle}}
"""


def _spin(tmp_path: Path, extra: str = "") -> Path:
    path = tmp_path / "spin.case.yaml"
    path.write_text(SPIN.format(inertia=INERTIA, spin_at=SPIN_AT, extra=extra), encoding="utf-8")
    return path


def _rows(path: Path) -> dict[str, np.ndarray]:
    with path.open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def _spun_angle(t: np.ndarray) -> np.ndarray:
    """Closed form: I theta'' = exp(100 t) from rest at SPIN_AT."""
    t = np.maximum(t, SPIN_AT)
    e0 = math.exp(100 * SPIN_AT)
    return (np.exp(100 * t) - e0 - 100 * e0 * (t - SPIN_AT)) / (1e4 * INERTIA)


def test_runaway_torque_stops_in_seconds_after_its_event(tmp_path: Path) -> None:
    """The torque exp(100 t), switched on by an event at 0.05 s, makes the step collapse:
    exit 1 within 30 s (it ran for minutes before), the rows so far kept and equal to the
    closed form (2e-3 relative: the local error of 1e-6 per step, thousands of steps on a
    solution growing as exp(100 t)), the message naming the collapse, the force and the event,
    and the event in the summary."""
    start = time.monotonic()
    result = runner.invoke(app, ["run", str(_spin(tmp_path)), "-o", str(tmp_path / "out")])
    assert time.monotonic() - start < 30.0
    assert result.exit_code == 1, result.output
    summary = json.loads((tmp_path / "out" / "spin.summary.json").read_text())
    assert summary["status"] == "failed"
    message = summary["message"]
    assert "the step size collapsed to" in message and "analysis.max_steps = 500000" in message
    assert "the force 'spin_up' grew from" in message
    assert message.endswith("; events: spin at t = 0.05 s")
    assert [(e["name"], e["time"]) for e in summary["events"]] == [("spin", SPIN_AT)]
    failed_at = float(message.split("failed at t = ")[1].split(" s")[0])
    rows = _rows(tmp_path / "out" / "spin.csv")
    assert 0.1 < failed_at < 0.3 and rows["time"][-1] <= failed_at
    assert len(rows["time"]) == math.floor(failed_at / 0.01) + 2  # output rows + event row
    np.testing.assert_allclose(rows["angle.value"], _spun_angle(rows["time"]), rtol=2e-3, atol=1e-9)


def test_max_steps_reached_names_the_limit_and_the_time(tmp_path: Path) -> None:
    """A limit of 40 steps on the dynamic run (100 output steps at least) and on the
    kinematic slider-crank (1001 output times): exit 1, the limit, the time reached and how
    to raise it in the message, the rows before the limit kept (the last
    within one output interval of the time reached)."""
    dynamic = _spin(tmp_path, ", max_steps: 40")
    shutil.copy(LIBRARY / "slider_crank.mech.yaml", tmp_path)
    kinematic = tmp_path / "slider_crank.case.yaml"
    kinematic.write_text(
        (LIBRARY / "slider_crank.case.yaml")
        .read_text()
        .replace("  step: 0.001 ", "  max_steps: 40\n  step: 0.001 ")
    )
    result = runner.invoke(app, ["run", str(dynamic), str(kinematic), "-o", str(tmp_path)])
    assert result.exit_code == 1, result.output
    for name, analysis in (("spin", "dynamic"), ("slider-crank-constant-speed", "kinematic")):
        summary = json.loads((tmp_path / f"{name}.summary.json").read_text())
        assert summary["status"] == "failed"
        assert summary["message"].startswith(f"{analysis} analysis stopped at t = ")
        assert (
            "the limit of 40 steps (analysis.max_steps, accepted and rejected) is "
            "reached; raise analysis.max_steps"
        ) in summary["message"]
        reached = float(summary["message"].split("stopped at t = ")[1].split(" s")[0])
        last_row = _rows(tmp_path / f"{name}.csv")["time"][-1]
        assert 0.0 < last_row <= reached < last_row + 0.01  # rows at output times
    assert summary["rows"] == 40  # one output time per kinematic step


def test_max_steps_must_be_positive(tmp_path: Path) -> None:
    """max_steps 0 or negative is an input error at its line and column (exit 2); the JSON
    schema says it is an integer of at least 1."""
    for value in ("0", "-5"):
        path = _spin(tmp_path, f", max_steps: {value}")
        result = runner.invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
        assert result.exit_code == 2
        assert (
            f"{path}:12:50: error: analysis.max_steps: must be a positive whole number of steps"
        ) in result.output
    schema = json.loads(runner.invoke(app, ["schema"]).output)
    text = json.dumps(schema)
    assert '"max_steps": {"anyOf": [{"type": "integer"}, {"type": "null"}]' in text
    assert '"minimum": 1' in text[text.index('"max_steps"') :][:400]


def test_a_pendulum_too_long_for_max_steps_is_not_called_a_runaway(tmp_path: Path) -> None:
    """IFToMM A01 (a 1 m pendulum released horizontal) over 100 s with max_steps 10 000
    (it needs about 17 000): its step varies over each swing, it neither collapses nor
    speeds up. Before, the step-collapse watch compared two instants 1000 steps apart and
    failed at 39.8 s with "the step size collapsed ... the motion speeds up without
    bound"; now the run goes on to its step limit and says so. The claim is checked
    against the physics: the rows' largest rate stays within 1 % of the closed form's
    sqrt(2 g / L) = 4.43 rad/s (energy conserved, no speed-up)."""
    for name in ("iftomm_a01_pendulum.mech.yaml", "iftomm_a01_pendulum.case.yaml"):
        shutil.copy(LIBRARY / "hard" / name, tmp_path)
    case = tmp_path / "iftomm_a01_pendulum.case.yaml"
    text = case.read_text(encoding="utf-8")
    case.write_text(
        text.replace("end: 10.0", "end: 100.0\n  max_steps: 10000\n  accuracy: off"),
        encoding="utf-8",
    )
    result = runner.invoke(app, ["run", str(case), "-o", str(tmp_path / "out")])
    assert result.exit_code == 1, result.output
    summary = json.loads((tmp_path / "out" / "iftomm-a01-pendulum.summary.json").read_text())
    message = summary["message"]
    assert message.startswith("dynamic analysis stopped at t = "), message
    assert "the limit of 10000 steps (analysis.max_steps, accepted and rejected)" in message
    assert "collapsed" not in message and "speeds up" not in message
    reached = float(message.split("stopped at t = ")[1].split(" s")[0])
    assert 40.0 < reached < 100.0
    rates = _rows(tmp_path / "out" / "iftomm-a01-pendulum.csv")["rate.value"]
    assert np.abs(rates).max() < 1.01 * math.sqrt(2 * 9.81 / 1.0)
