"""Events with delays (`after: {event: NAME, delay: TIME}`): a falling block, braked a given
time after it passes a level, locked, and the run stopped a given time after the lock,
against the closed form of free fall (y = -g t^2 / 2) and of a constant deceleration."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.run import run_file

G = 9.81  # m/s^2
MASS = 2.0  # kg
LEVEL = 0.2  # m: the brake's trigger, below the start

CASE = """\
case: {name}
mechanism:
  gravity: [0, -9.81, 0]
  bodies:
    block: {{mass: 2, cm: [0, 0, 0], inertia: [0.1, 0.1, 0.1]}}
  joints:
    slide: {{type: prismatic, bodies: [block, ground], at: [0, 0, 0], axis: [0, 1, 0]}}
  forces:
    brake: {{type: force, body: block, value: [0, "2*2*9.81", 0], active: false}}
events:
{events}
analysis: {{type: dynamic, end: 2.0, step: 0.01, tolerance: 1.0e-8, accuracy: off}}
requests:
  travel: {{joint: slide, quantity: travel}}
"""
CHAIN = """\
  braking: {when: "travel(slide) <= -0.2", then: [{activate: brake}]}
  lock: {after: {event: braking, delay: 100 ms}, then: {lock: slide}}
  halt: {after: {event: lock, delay: 0.2 s}, then: stop}
"""


def _write(tmp_path: Path, name: str, events: str) -> Path:
    path = tmp_path / f"{name}.case.yaml"
    path.write_text(CASE.format(name=name, events=events), encoding="utf-8")
    return path


def test_delayed_brake_lock_and_stop_against_the_closed_form(tmp_path: Path) -> None:
    """Free fall to 0.2 m below the start (t1 = sqrt(2 * 0.2 / g)), then 0.1 s braked at a
    net +g (2 m g up), then locked; the run stops 0.2 s after the lock. Event times within
    1e-6 s (location tolerance 1e-9 s, the first event located on the travel), the locked
    travel within 1e-6 m of y(t1) + v(t1) * 0.1 + g * 0.1^2 / 2 (integrator tolerance
    1e-8), the last row at t_lock + 0.2 s."""
    path = _write(tmp_path, "delays", CHAIN)
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    sol = outcome.solution
    t1 = math.sqrt(2 * LEVEL / G)
    times = {e.name: e.time for e in sol.events}
    assert list(times) == ["braking", "lock", "halt"]
    assert times["braking"] == pytest.approx(t1, abs=1e-6)
    assert times["lock"] == pytest.approx(t1 + 0.1, abs=1e-6)
    assert times["halt"] == pytest.approx(t1 + 0.3, abs=1e-6)
    assert sol.time[-1] == pytest.approx(t1 + 0.3, abs=1e-9)
    locked = -LEVEL - G * t1 * 0.1 + 0.5 * G * 0.1**2
    travel = sol.channels["travel.value"]
    assert travel[-1] == pytest.approx(locked, abs=1e-6)
    assert outcome.solution.ok


def test_zero_delay_fires_with_the_event_it_follows(tmp_path: Path) -> None:
    """`delay: 0` stops the run at the lock's own instant (free fall: t = sqrt(2 * 0.2 / g))."""
    events = (
        '  lock: {when: "travel(slide) <= -0.2", then: [{lock: slide}]}\n'
        "  halt: {after: {event: lock}, then: [stop]}\n"
    )
    (outcome,) = run_file(_write(tmp_path, "at-once", events), output_dir=tmp_path / "out")
    sol = outcome.solution
    assert [(e.name, e.time) for e in sol.events] == [
        ("lock", pytest.approx(math.sqrt(2 * LEVEL / G), abs=1e-6)),
        ("halt", sol.events[0].time),
    ]
    assert sol.time[-1] == pytest.approx(sol.events[0].time, abs=1e-12)


def test_a_delay_after_an_event_that_never_fires_does_nothing(tmp_path: Path) -> None:
    """The lock's level is never reached in 2 s: neither it nor the stop after it fires."""
    events = (
        '  lock: {when: "travel(slide) <= -100", then: [{lock: slide}]}\n'
        "  halt: {after: {event: lock, delay: 0.1 s}, then: stop}\n"
    )
    (outcome,) = run_file(_write(tmp_path, "never", events), output_dir=tmp_path / "out")
    assert outcome.solution.events == []
    assert outcome.solution.time[-1] == pytest.approx(2.0)


@pytest.mark.parametrize(
    ("events", "expected"),
    [
        (
            "  halt: {after: {event: lok, delay: 0.1 s}, then: stop}\n"
            '  lock: {when: "t >= 0.1", then: [{lock: slide}]}\n',
            "events.halt.after.event: unknown event 'lok' | did you mean 'lock'?",
        ),
        (
            "  a: {after: {event: b, delay: 0.1 s}, then: stop}\n"
            "  b: {after: {event: a, delay: 0.1 s}, then: stop}\n",
            "events.a.after.event: events that follow each other in a loop never fire "
            "(a -> b -> a)",
        ),
    ],
)
def test_bad_delays_are_named_at_their_keys(tmp_path: Path, events: str, expected: str) -> None:
    with pytest.raises(InputError) as caught:
        run_file(_write(tmp_path, "bad", events), output_dir=tmp_path / "out")
    messages = [
        f"{d.key}: {d.message}" + (f" | {d.hint}" if d.hint else "")
        for d in caught.value.diagnostics
    ]
    assert expected in messages


@pytest.mark.parametrize(
    ("event", "expected"),
    [
        ('{when: "t >= 1", after: {event: x}, then: stop}', "give either 'when'"),
        ("{then: stop}", "give either 'when'"),
        ("{after: {event: x, delay: -1 s}, then: stop}", "must be >= 0"),
        ("{after: {event: x, delay: 3 m}, then: stop}", "time"),
    ],
)
def test_malformed_delays_are_input_errors(tmp_path: Path, event: str, expected: str) -> None:
    path = _write(tmp_path, "malformed", f"  e: {event}\n")
    with pytest.raises(InputError) as caught:
        run_file(path, output_dir=tmp_path / "out")
    assert any(expected in d.message for d in caught.value.diagnostics), [
        d.message for d in caught.value.diagnostics
    ]
