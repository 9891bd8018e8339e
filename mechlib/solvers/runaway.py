"""Runaway and stalled runs: a step size that keeps collapsing, stopped long before
`max_steps`; a step size below its floor, stopped at once (`stall`).

A load that grows without bound (a force exp(100 t), an unstable controller) makes the
error-controlled step shrink as the motion speeds up; the run would grind on until its step
limit, minutes later. `StepCollapse` watches the pace of the accepted steps: once the rest
of the run at the current step size would need more steps than `max_steps` leaves, the mean
step of each following window of COLLAPSE_STEPS accepted steps is compared with that of the
first window; when it has fallen below COLLAPSE_RATIO of it (the steps really shrink, not
merely vary over a swing, and an impact resolves in far fewer steps), the run fails naming
what grew over those steps: a force element's load, the motion's speed, or neither. A run
whose pace is steady but too slow for `max_steps` (a long run of a swinging pendulum) is
not a collapse: it goes on to its step limit, whose failure says so.

A run stalls when the step size falls below STALL_FLOOR times the time scale max(1, |end|)
s: time no longer advances (a motion driven beyond a dead point, a singular position the
integrator cannot pass). `stall` makes the failure that says when and which joints: the
equations closest to dependence there (mechlib.checks.singularity.weakest_equations).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mechlib.checks.singularity import weakest_equations
from mechlib.core.outcome import SolverFailure, Status

__all__ = [
    "COLLAPSE_STEPS",
    "NAMED_MEASURE",
    "STALL_FLOOR",
    "Snapshot",
    "StepCollapse",
    "fell_to",
    "snapshot",
    "stall",
    "step_floor",
]

COLLAPSE_STEPS = 1000  # accepted steps per window whose mean step the watch compares
COLLAPSE_RATIO = 0.5  # a window's mean step below this fraction of the first's: collapsing
SPED_UP = 2.0  # the largest coordinate rate grown this much: the motion speeds up
STALL_FLOOR = 1e-12  # smallest step, relative to the time scale max(1, |end|) s
NAMED_MEASURE = 0.5  # toggle measure (mechlib.checks.singularity) below which a stall names joints


def fell_to(h: float, floor: float) -> str:
    """How a stall stopped: the step h (s) below its floor (s)."""
    return f"the step size fell to {h:.3g} s (floor {floor:.3g} s)"


def step_floor(end: float) -> float:
    """The smallest step size (s) of a run ending at `end` (s)."""
    return STALL_FLOOR * max(1.0, abs(end))


def stall(
    system, analysis: str, t: float, q: np.ndarray, how: str, why: SolverFailure | str
) -> SolverFailure:
    """The failure of a run that cannot progress from the position q at t (s): `how` it
    stopped (the step size below its floor), `why` the last attempt's failure (its time,
    the attempt's end, is the failure's). Names the joints of the equations closest to
    dependence there when the position is nearer to singular than NAMED_MEASURE; away
    from singular positions the attempt's own failure (`why`) is returned as it is."""
    measure, equations = weakest_equations(system, system.kin(q, None, t))
    if measure >= NAMED_MEASURE and isinstance(why, SolverFailure):
        return why  # no singular position: the attempt's own failure says more
    where = (
        f"near-singular position (toggle or dead point, measure {measure:.2g}): {equations}"
        if measure < NAMED_MEASURE
        else "no near-singular position there"
    )
    last = f"; last attempt: {_attempt(why, measure)}" if str(why) else ""
    return SolverFailure(
        f"{analysis} analysis stalled at t = {t:.6g} s: no progress, {how}; {where}{last}. "
        "A motion driven beyond a dead point, a singular position the integrator cannot "
        "pass, or a load it cannot follow: the rows up to there are kept",
        time=getattr(why, "time", None) or t,
        status=Status.STALLED,
    )


def _attempt(why: SolverFailure | str, measure: float) -> str:
    """The last attempt's failure as a stall reports it: a singular matrix at a position
    nearer to singular than NAMED_MEASURE is that position (named before it), not the
    generic "a body with no mass or stiffness" of mechlib.linalg.factor.singular_failure."""
    if measure < NAMED_MEASURE and getattr(why, "status", None) is Status.SINGULAR:
        at = getattr(why, "time", None)
        when = f" at t = {at:.6g} s" if at is not None else ""
        return f"singular system matrix{when}, at that near-singular position"
    return str(why)


def element_loads(system, view) -> dict[str, float]:
    """Largest force (N) or torque (N*m) component of each active force element at `view`."""
    loads = {}
    for element in system.elements:
        if element.active:
            F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
            element.apply(view, F, N)
            loads[element.name] = float(max(np.abs(F).max(), np.abs(N).max()))
    return loads


@dataclass(frozen=True)
class Snapshot:
    """What may grow while the steps shrink: each active force element's largest load
    component (N or N*m, `element_loads`) and the motion's largest coordinate rate (m/s
    or, for the rotation parameters, 1/s)."""

    loads: dict[str, float]
    speed: float


def snapshot(system, view, qd: np.ndarray) -> Snapshot:
    """The `Snapshot` of the state seen by `view`, with coordinate rates qd."""
    return Snapshot(element_loads(system, view), float(np.max(np.abs(qd), initial=0.0)))


@dataclass(frozen=True)
class _Window:
    """The start of a window of accepted steps: steps taken, time (s), what may grow."""

    taken: int
    t: float
    seen: Snapshot


class StepCollapse:
    """Watches (t, h) of the accepted steps of a run from `start` to `end` (s)."""

    def __init__(self, analysis: str, end: float, max_steps: int):
        self.analysis, self.end, self.max_steps = analysis, end, max_steps
        self.first: _Window | None = None  # where the steps were first too short
        self.since: _Window | None = None  # the start of the current window
        self.pace = 0.0  # mean step (s) of the first full window

    def watch(self, taken: int, t: float, h: float, seen: Callable[[], Snapshot]) -> None:
        """After an accepted step of size h (s) ending at t (s), `taken` steps so far;
        `seen()` gives the `Snapshot` now. Raises SolverFailure on a collapse."""
        if self.since is None:
            if taken + (self.end - t) / h <= self.max_steps:
                return
            self.first = self.since = _Window(taken, t, seen())
            return
        start = self.since
        if taken - start.taken < COLLAPSE_STEPS:
            return
        mean = (t - start.t) / (taken - start.taken)
        if taken + (self.end - t) / mean <= self.max_steps:  # the pace fits the limit again
            self.first, self.since, self.pace = None, None, 0.0
            return
        self.since = _Window(taken, t, start.seen)
        if not self.pace:
            self.pace = mean
            return
        if mean >= COLLAPSE_RATIO * self.pace:  # steady or varying over a swing: go on
            return
        assert self.first is not None, "set with since"
        raise SolverFailure(
            f"{self.analysis} analysis failed at t = {t:.6g} s: the step size collapsed to "
            f"{mean:.3g} s on average over the last {COLLAPSE_STEPS} steps (from "
            f"{self.pace:.3g} s over the first {COLLAPSE_STEPS} after t = "
            f"{self.first.t:.6g} s); the remaining "
            f"{self.end - t:.3g} s would need {(self.end - t) / mean:.3g} more steps, beyond "
            f"analysis.max_steps = {self.max_steps}: {_grown(self.first.seen, seen())}",
            time=t,
            status=Status.STEP_COLLAPSE,
        )


def _grown(before: Snapshot, now: Snapshot) -> str:
    """The likely cause: the element whose load grew the most, the motion's speed, or
    what else to check."""
    ratios = {
        name: now.loads[name] / before.loads[name]
        for name in now.loads
        if before.loads.get(name, 0.0) > 0.0 and now.loads[name] > before.loads[name]
    }
    if ratios:
        name = max(ratios, key=ratios.__getitem__)
        return (
            f"the force '{name}' grew from {before.loads[name]:.3g} to "
            f"{now.loads[name]:.3g} (SI) over those steps: does it grow without bound?"
        )
    if now.speed > SPED_UP * before.speed:
        return (
            f"no force element grows, the motion speeds up (its largest coordinate rate "
            f"from {before.speed:.3g} to {now.speed:.3g}, SI): an unstable model, a motion "
            "or initial value out of range?"
        )
    return (
        "neither a force element's load nor the motion's speed grows: a stiffness, a "
        "singular position or a discontinuity the steps cannot follow?"
    )
