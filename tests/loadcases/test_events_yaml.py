"""Events from YAML: in the mechanism or in the case, refused targets named at their key,
and a mechanism's events waiting (with a warning) in static analyses."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.run import run_file

CASE = """\
case: {name}
units: {{angle: deg}}
mechanism:
  bodies:
    panel: {{mass: 1, cm: [0, 0, 0], inertia: [0.5, 0.5, 0.5]}}
  joints:
    hinge: {{type: revolute, bodies: [panel, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
  forces:
    drive: {{type: torsion_spring, joint: hinge, stiffness: "2 N*m/rad", angle0: 180}}
{mech_events}
{case_events}
analysis: {analysis}
requests:
  angle: {{joint: hinge, quantity: angle}}
"""
LOCK = '{when: "angle(hinge) >= 90*deg", then: [{lock: hinge}]}'


def _write(
    tmp_path: Path,
    name: str,
    *,
    mech_events: str = "",
    case_events: str = "",
    analysis: str = "{type: dynamic, end: 1.0, step: 0.01, tolerance: 1.0e-10}",
) -> Path:
    path = tmp_path / f"{name}.case.yaml"
    path.write_text(
        CASE.format(name=name, mech_events=mech_events, case_events=case_events, analysis=analysis),
        encoding="utf-8",
    )
    return path


def test_case_events_lock_the_hinge(tmp_path: Path) -> None:
    """An event given in the case locks the hinge at 90 deg, at t = (pi/3)/sqrt(k/I)
    within 1e-6 s (closed form of the spring swing), and holds it there."""
    path = _write(tmp_path, "case-lock", case_events=f"events:\n  latched: {LOCK}")
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    sol = outcome.solution
    assert [e.name for e in sol.events] == ["latched"]
    assert abs(sol.events[0].time - (math.pi / 3) / math.sqrt(2.0 / 0.5)) < 1e-6
    assert sol.channels["angle.value"][-1] == pytest.approx(math.pi / 2, abs=1e-8)


def test_bad_event_targets_are_named_at_their_keys(tmp_path: Path) -> None:
    """An unknown joint and a joint without a coordinate for `lock`, each an input error."""
    events = (
        'events:\n  a: {when: "t >= 0.1", then: [{release: hingee}]}\n'
        '  b: {when: "t >= 0.2", then: [{activate: nothing}]}'
    )
    path = _write(tmp_path, "bad-events", case_events=events)
    with pytest.raises(InputError) as caught:
        run_file(path, output_dir=tmp_path / "out")
    messages = sorted(f"{d.key}: {d.message}" for d in caught.value.diagnostics)
    assert messages == [
        "events.a.then[0]: unknown joint 'hingee'",
        "events.b.then[0]: 'nothing' is not a force element, contact, limit or motion of this case",
    ]


def test_mechanism_events_wait_in_a_static_case(tmp_path: Path) -> None:
    """A mechanism's events do not stop its static cases: they are left out, with a warning
    that says so (the equilibrium: the spring's free angle, 180 deg, from a start near it)."""
    path = _write(
        tmp_path,
        "static-with-events",
        mech_events=f"  events:\n    latched: {LOCK}",
        analysis="{type: static}",
    )
    text = path.read_text().replace(
        "case: static-with-events", "case: static-with-events\ninitial: {hinge: {value: 170 deg}}"
    )
    path.write_text(text)
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    assert outcome.solution.ok
    assert outcome.solution.channels["angle.value"][0] == pytest.approx(math.pi, abs=1e-8)
    (warning,) = [w for w in outcome.warnings if "need an analysis in time" in w.message]
    assert (warning.file, warning.severity) == (str(path), "warning") and warning.line > 0
