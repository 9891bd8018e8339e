"""Issue 15 item 10: `mechlib.solve` leaves the Mechanism it is given unchanged (event
activations, element states live in the solve's own state): solving the same mechanism
twice gives identical results."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import mechlib as ml
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case

LATCH = Path(__file__).parents[2] / "loadcases/library/verification/latch_spring.case.yaml"


def _solve(built, end: float):
    analysis = ml.Dynamic(end=end, step=0.01, tolerance=1e-7)
    return ml.solve(
        built.mechanism,
        analysis,
        requests=built.requests,
        initial=built.initial,
        events=built.events,
        throw=False,
    )


def test_event_activation_does_not_leak_into_the_next_solve() -> None:
    """The latch is switched on by an event at 90 deg (0.52 s at 3 rad/s): after a solve the
    mechanism still has it off, and a second solve repeats the first exactly."""
    built = build_run(load_case(LATCH))
    first = _solve(built, 0.8)
    assert first.status == "ok", first.message
    assert [e.name for e in first.events] == ["engage"]
    assert built.mechanism.forces["latch"].active is False
    second = _solve(built, 0.8)
    assert second.status == "ok", second.message
    assert [e.time for e in second.events] == [e.time for e in first.events]
    assert first.channels.keys() == second.channels.keys()
    for name, values in first.channels.items():
        np.testing.assert_array_equal(second.channels[name], values, err_msg=name)
