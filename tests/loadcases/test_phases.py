"""Analysis sequences (`phases:`): a static preload before a dynamic run, a quasi-static
phase handing its end angle to a dynamic one, locks held for one phase only, and the
errors at their keys. References are closed forms (stated in each test)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_file

G = 9.81  # m/s^2
MASS = 2.0  # kg
STIFFNESS = 800.0  # N/m
LENGTH = 0.5  # m, pendulum: point mass at the end of a massless-like rod

SPRING_MASS = """\
case: {name}
mechanism:
  gravity: [0, -9.81, 0]
  bodies:
    block: {{mass: 2, cm: [0, 0, 0], inertia: [0.001, 0.001, 0.001]}}
  joints:
    slide: {{type: prismatic, bodies: [block, ground], at: [0, 0, 0], axis: [0, 1, 0]}}
  forces:
    spring: {{type: spring, points: [eye, anchor], stiffness: 800, free_length: 1.0}}
  points:
    eye: {{body: block, at: [0, 0, 0]}}
    anchor: {{body: ground, at: [0, 1, 0]}}
{analysis}
requests:
  travel: {{joint: slide, quantity: travel}}
  spring_force: {{force: spring}}
"""
DYNAMIC = "{type: dynamic, end: 1.0, step: 0.005, tolerance: 1.0e-8, accuracy: off}"


def _spring_mass(tmp_path: Path, name: str, analysis: str) -> Path:
    path = tmp_path / f"{name}.case.yaml"
    path.write_text(SPRING_MASS.format(name=name, analysis=analysis), encoding="utf-8")
    return path


def _run(path: Path, out: Path):
    (outcome,) = run_file(path, output_dir=out)
    assert outcome.solution.status == "ok", outcome.solution.message
    return outcome.solution


def test_static_preload_removes_the_start_oscillation(tmp_path: Path) -> None:
    """A mass on a spring (free at the design position) under gravity. Dynamic alone: it
    oscillates about the static deflection -m g / k with amplitude m g / k (closed form,
    undamped: travel between -2 m g / k and 0), within 1e-6 m. With a static phase first
    it starts at the equilibrium and stays there: |travel + m g / k| < 1e-9 m over the
    run, the spring force m g (tension) throughout."""
    static_sag = MASS * G / STIFFNESS  # 0.024525 m
    alone = _run(_spring_mass(tmp_path, "alone", f"analysis: {DYNAMIC}"), tmp_path / "a")
    travel = alone.channels["travel.value"]
    assert (travel.max() - travel.min()) / 2 == pytest.approx(static_sag, abs=1e-6)
    assert travel.min() == pytest.approx(-2 * static_sag, abs=1e-6)
    phased = "phases:\n  - {name: preload, analysis: {type: static}}\n"
    phased += f"  - {{analysis: {DYNAMIC}}}"
    out = tmp_path / "p"
    sol = _run(_spring_mass(tmp_path, "preloaded", phased), out)
    travel = sol.channels["travel.value"]
    assert np.abs(travel + static_sag).max() < 1e-9
    assert np.abs(sol.channels["spring_force.value"] - MASS * G).max() < 1e-6
    summary = json.loads((out / "preloaded.summary.json").read_text())
    assert summary["analysis"] == "phases"
    assert [(p["name"], p["analysis"], p["rows"]) for p in summary["phases"]] == [
        ("preload", "static", 1),
        ("phase2", "dynamic", 201),
    ]
    assert summary["rows"] == 202 and summary["phases"][1]["first_row"] == 1


PENDULUM = """\
case: pendulum-phases
mechanism:
  gravity: [0, -9.81, 0]
  bodies:
    bob: {mass: 1, cm: [0.5, 0, 0], inertia: [1.0e-6, 1.0e-6, 1.0e-6]}
  joints:
    pivot: {type: revolute, bodies: [bob, ground], at: [0, 0, 0], axis: [0, 0, 1]}
motions:
  lift: {joint: pivot, value: "step(t, 0, 0, 1, 60*deg)"}
phases:
  - {name: lifted, analysis: {type: quasi-static, end: 1.0, step: 0.1}}
  - name: swing
    motions: []
    analysis: {type: dynamic, end: 3.0, step: 0.002, tolerance: 1.0e-8, accuracy: off}
requests:
  angle: {joint: pivot, quantity: angle}
  rate: {joint: pivot, quantity: omega}
"""


def test_quasi_static_lift_then_free_swing(tmp_path: Path) -> None:
    """A pendulum (point-like bob, L = 0.5 m) lifted quasi-statically by a motion to +60 deg
    (the angle from the horizontal x axis, gravity -y), then let go (`motions: []`): the
    dynamic phase starts at the quasi-static end angle at rest and swings through the
    bottom (-90 deg) with the rate of energy conservation, |omega| = sqrt(2 g (sin 60 deg
    + 1) / L) (closed form, bob inertia 1e-6 kg m^2 neglected: relative 1e-6), within
    1e-4 relative; the lowest angle reached mirrors the start, -240 deg (within 0.01 deg)."""
    path = tmp_path / "pendulum.case.yaml"
    path.write_text(PENDULUM, encoding="utf-8")
    sol = _run(path, tmp_path / "out")
    first, second = sol.phases
    assert (first.name, first.rows, second.name) == ("lifted", 11, "swing")
    angle, rate = sol.channels["angle.value"], sol.channels["rate.value"]
    start = second.first_row
    assert angle[start] == pytest.approx(math.radians(60.0), abs=1e-9)
    assert rate[start] == pytest.approx(0.0, abs=1e-9)
    drop = LENGTH * (math.sin(math.radians(60.0)) + 1.0)
    assert np.abs(rate[start:]).max() == pytest.approx(math.sqrt(2 * G * drop) / LENGTH, rel=1e-4)
    assert math.degrees(angle[start:].min()) == pytest.approx(-240.0, abs=0.01)


def test_a_lock_holds_for_its_phase_only(tmp_path: Path) -> None:
    """The pendulum held at +60 deg by a lock in a static phase, then released: the same
    swing as a quasi-static lift (the lock's row goes with its phase); while locked, the
    joint carries the weight's moment m g L cos 60 deg (closed form, within 1e-6 N m)."""
    text = PENDULUM.replace(
        'motions:\n  lift: {joint: pivot, value: "step(t, 0, 0, 1, 60*deg)"}\n',
        "initial:\n  pivot: {value: 60 deg}\n",
    )
    text = text.replace(
        "  - {name: lifted, analysis: {type: quasi-static, end: 1.0, step: 0.1}}",
        "  - {name: held, analysis: {type: static}, locks: [pivot]}",
    )
    text = text.replace("    motions: []\n", "").replace("end: 3.0", "end: 2.0")
    text += "  moment: {joint: pivot, quantity: force}\n"
    path = tmp_path / "held.case.yaml"
    path.write_text(text, encoding="utf-8")
    sol = _run(path, tmp_path / "out")
    angle, rate = sol.channels["angle.value"], sol.channels["rate.value"]
    weight_moment = 1.0 * G * LENGTH * math.cos(math.radians(60.0))
    assert abs(sol.channels["moment.tz"][0]) == pytest.approx(weight_moment, abs=1e-6)
    assert angle[1] == pytest.approx(math.radians(60.0), abs=1e-9)
    drop = LENGTH * (math.sin(math.radians(60.0)) + 1.0)
    assert np.abs(rate).max() == pytest.approx(math.sqrt(2 * G * drop) / LENGTH, rel=1e-4)


@pytest.mark.parametrize(
    ("phases", "key", "message"),
    [
        (
            "  - {analysis: {type: quasi-static, end: 1.0, step: 0.1}}\n"
            "  - {analysis: {type: dynamic, end: 0.5, step: 0.01}}\n",
            "phases[1].analysis.end",
            "a phase ends after the one before it",
        ),
        (
            "  - {analysis: {type: modes}}\n",
            "phases[0].analysis.type",
            "a phase is a static, quasi-static or dynamic analysis",
        ),
        (
            "  - {analysis: {type: static}, locks: [pivt]}\n",
            "phases[0].locks[0]",
            "unknown joint 'pivt'",
        ),
    ],
)
def test_phase_errors_at_their_keys(tmp_path: Path, phases: str, key: str, message: str) -> None:
    """Bad phases are input errors at the key, with file, line and column."""
    text = PENDULUM.split("phases:\n")[0] + "phases:\n" + phases
    text += "requests:\n  angle: {joint: pivot, quantity: angle}\n"
    path = tmp_path / "bad.case.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as raised:
        load_case(path)
    found = [d for d in raised.value.diagnostics if d.severity == "error"]
    assert [d.key for d in found] == [key], found
    assert message in found[0].message and found[0].line > 1 and found[0].file == str(path)


def test_analysis_beside_phases_is_refused(tmp_path: Path) -> None:
    """`analysis` and `phases` together: an error at `analysis`."""
    text = PENDULUM.replace("phases:", "analysis: {type: static}\nphases:")
    path = tmp_path / "both.case.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as raised:
        load_case(path)
    (error,) = [d for d in raised.value.diagnostics if d.severity == "error"]
    assert error.key == "analysis" and "not both" in error.message


BEAM_PHASES = """\
case: beam-phases
mechanism:
  units: {length: mm}
  bodies:
    beam:
      flexible:
        beam: {start: [0, 0, 0], end: [800, 0, 0], section: {width: 30, height: 10},
               material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}, elements: 4,
               y_axis: [0, 1, 0]}
        interface: {root: [0, 0, 0], tip: [800, 0, 0]}
        fixed_interface_modes: 2
        modes: 1
        damping: 0
  joints:
    clamp: {type: fixed, bodies: [beam, ground], at: [0, 0, 0]}
  forces:
    load: {type: force, point: beam.tip, value: [0, 0, 5]}
phases:
  - {name: fine, analysis: {type: dynamic, end: 0.02, step: 0.001, max_step: 5.0e-5,
                            tolerance: 1.0e-4, accuracy: off}}
  - {name: second, analysis: {type: dynamic, end: 0.12, step: 0.01, max_step: MAX_STEP,
                              tolerance: 1.0e-2, accuracy: off}}
requests:
  tip: {point: beam.tip, quantity: position}
"""


@pytest.mark.parametrize("max_step, fires", [(0.01, True), (0.0005, False)])
def test_unresolved_mode_warning_per_phase(tmp_path: Path, max_step: float, fires: bool) -> None:
    """The mean step of the unresolved-mode warning is each phase's own (its duration over
    its own steps), not the phase's duration over the steps of all phases. The beam's one
    kept mode is 82.06 Hz (20 steps a period: steps up to 0.609 ms). The first phase
    resolves it (0.02 s in 400 steps of 0.05 ms); the second, 0.1 s with steps of up to
    10 ms, does not: warned, naming the phase and its own mean step (at least 5 ms; the
    whole run's step count gave 0.24 ms and no warning). With steps of at most 0.5 ms the
    second phase resolves it too: no warning."""
    case = BEAM_PHASES.replace("MAX_STEP", str(max_step))
    path = tmp_path / "beam.case.yaml"
    path.write_text(case, encoding="utf-8")
    solution = _run(path, tmp_path / "out")
    unresolved = [w for w in solution.warnings if "not resolved by the mean step" in w]
    if not fires:
        assert unresolved == []
        return
    (message,) = unresolved
    assert message.startswith("phase second: flexible body beam: 1 of its 1 modes")
    mean = float(message.split("mean step ")[1].split(" s")[0])
    assert 0.005 <= mean <= 0.01
