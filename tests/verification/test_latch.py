"""Latch engaging by event, through `loads` (issue 3 item 11): peak latch moment from the
energy balance, I w^2 / 2 = k theta^2 / 2 -> M = w sqrt(I k) (0.1 %); the event lands at
(pi/2) / w within 1e-6 s (free spin before it, exact)."""

from __future__ import annotations

import math

import numpy as np


def test_latch_peak_moment_and_event_time(run_case) -> None:
    outcome = run_case("latch_spring.case.yaml")
    solution = outcome.solution
    w, inertia, k = 3.0, 0.5, 400.0
    assert [e.name for e in solution.events] == ["engage"]
    assert abs(solution.events[0].time - (math.pi / 2) / w) < 1e-6
    moment = solution.channels["latch.value"]
    assert np.all(moment[solution.time < solution.events[0].time - 1e-9] == 0.0)
    assert abs(np.abs(moment).max() - w * math.sqrt(inertia * k)) < 1e-3 * w * math.sqrt(
        inertia * k
    )
