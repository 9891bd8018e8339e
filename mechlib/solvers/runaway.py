"""Runaway and stalled runs: a step size that keeps collapsing, stopped long before
`max_steps`; a step size below its floor, stopped at once (`stall`).

A load that grows without bound (a force exp(100 t), an unstable controller) makes the
error-controlled step shrink as the motion speeds up; the run would grind on until its step
limit, minutes later. `StepCollapse` watches the accepted steps: once the rest of the run
at the current step size would need more steps than `max_steps` leaves, and the step keeps
shrinking over the next COLLAPSE_STEPS accepted steps (an impact resolves in far fewer, and
the step then grows again), the run fails naming the force element whose load grew most.

A run stalls when the step size falls below STALL_FLOOR times the time scale max(1, |end|)
s: time no longer advances (a motion driven beyond a dead point, a singular position the
integrator cannot pass). `stall` makes the failure that says when and which joints: the
equations closest to dependence there (mechlib.checks.singularity.weakest_equations).
"""

from __future__ import annotations

import numpy as np

from mechlib.checks.singularity import weakest_equations
from mechlib.core.outcome import SolverFailure, Status

__all__ = [
    "COLLAPSE_STEPS",
    "NAMED_MEASURE",
    "STALL_FLOOR",
    "StepCollapse",
    "fell_to",
    "stall",
    "step_floor",
]

COLLAPSE_STEPS = 1000  # accepted steps over which a step too small for the limit must shrink
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
    last = f"; last attempt: {why}" if str(why) else ""
    return SolverFailure(
        f"{analysis} analysis stalled at t = {t:.6g} s: no progress, {how}; {where}{last}. "
        "A motion driven beyond a dead point, a singular position the integrator cannot "
        "pass, or a load it cannot follow: the rows up to there are kept",
        time=getattr(why, "time", None) or t,
        status=Status.STALLED,
    )


def element_loads(system, view) -> dict[str, float]:
    """Largest force (N) or torque (N*m) component of each active force element at `view`."""
    loads = {}
    for element in system.elements:
        if element.active:
            F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
            element.apply(view, F, N)
            loads[element.name] = float(max(np.abs(F).max(), np.abs(N).max()))
    return loads


class StepCollapse:
    """Watches (t, h) of the accepted steps of a run from `start` to `end` (s)."""

    def __init__(self, analysis: str, end: float, max_steps: int):
        self.analysis, self.end, self.max_steps = analysis, end, max_steps
        self.since: tuple[int, float, dict[str, float]] | None = None

    def watch(self, taken: int, t: float, h: float, loads) -> None:
        """After an accepted step of size h (s) ending at t (s), `taken` steps so far;
        `loads()` gives `element_loads` now. Raises SolverFailure on a collapse."""
        need = (self.end - t) / h
        if taken + need <= self.max_steps:
            self.since = None
            return
        if self.since is None:
            self.since = (taken, h, loads())
            return
        n0, h0, loads0 = self.since
        if taken - n0 < COLLAPSE_STEPS:
            return
        if h >= h0:  # not shrinking any more: watch a new window
            self.since = (taken, h, loads())
            return
        raise SolverFailure(
            f"{self.analysis} analysis failed at t = {t:.6g} s: the step size collapsed to "
            f"{h:.3g} s (from {h0:.3g} s {taken - n0} steps before); the remaining "
            f"{self.end - t:.3g} s would need {need:.3g} more steps, beyond analysis.max_steps "
            f"= {self.max_steps}: {_grown(loads0, loads())}",
            time=t,
            status=Status.STEP_COLLAPSE,
        )


def _grown(before: dict[str, float], now: dict[str, float]) -> str:
    """The likely cause: the element whose load grew the most, or what else to check."""
    ratios = {
        name: now[name] / before[name]
        for name in now
        if before.get(name, 0.0) > 0.0 and now[name] > before[name]
    }
    if not ratios:
        return (
            "no force element grows: the motion speeds up without bound (an unstable "
            "model, a motion or initial value out of range?)"
        )
    name = max(ratios, key=ratios.__getitem__)
    return (
        f"the force '{name}' grew from {before[name]:.3g} to {now[name]:.3g} (SI) over "
        "those steps: does it grow without bound?"
    )
