"""The step-collapse watch (mechlib.solvers.runaway.StepCollapse) on synthetic step
sequences: a step that varies over each swing is not a collapse, a step shrinking as 1/n
(a speed growing linearly with the step count, as under a torque exp(100 t)) is, and the
failure names what grew: a load, the speed, or neither."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable

import pytest

from mechlib.core.outcome import SolverFailure, Status
from mechlib.solvers.runaway import COLLAPSE_STEPS, Snapshot, StepCollapse

END, LIMIT = 1000.0, 50_000  # s, steps: every sequence below needs more than LIMIT


def _watch(steps: Iterable[float], seen: Callable[[float], Snapshot]) -> float:
    """Feed (taken, t, h) of `steps` step sizes (s) to a watch, `seen(t)` its snapshot at
    t (s); the time reached (s)."""
    watch, t = StepCollapse("dynamic", END, LIMIT), 0.0
    for n, h in enumerate(steps, start=1):
        t += h
        watch.watch(n, t, h, functools.partial(seen, t))
    return t


def test_a_step_varying_over_each_swing_is_not_a_collapse() -> None:
    """h = 5 ms +- 80 % over a period of 437 steps (not a divisor of the window): the
    instants 1000 steps apart differ by up to 9 times, the windows' means by a few %."""
    steps = (0.005 * (1.0 + 0.8 * math.sin(2 * math.pi * n / 437)) for n in range(40_000))
    assert _watch(steps, lambda t: Snapshot({}, 4.4)) == pytest.approx(200.0, rel=0.01)


@pytest.mark.parametrize(
    ("seen", "cause"),
    [
        (lambda t: Snapshot({"spin_up": math.exp(t)}, 1.0), "the force 'spin_up' grew from"),
        (lambda t: Snapshot({"spring": 3.0}, 1.0 + 10.0 * t), "no force element grows, the "),
        (lambda t: Snapshot({"spring": 3.0}, 1.0), "neither a force element's load nor"),
    ],
)
def test_a_step_shrinking_as_1_over_n_is_a_collapse_that_names_what_grew(seen, cause) -> None:
    """h = 0.1 s / n: the first window's mean step halves within a few windows; the
    failure says the mean steps, the limit and the cause its snapshots show."""
    with pytest.raises(SolverFailure) as failure:
        _watch((0.1 / n for n in range(1, 40_000)), seen)
    message = str(failure.value)
    assert failure.value.status == Status.STEP_COLLAPSE
    assert f"on average over the last {COLLAPSE_STEPS} steps" in message
    assert "beyond analysis.max_steps = 50000" in message and cause in message
