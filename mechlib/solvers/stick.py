"""Exact stick of joint friction in dynamic analyses.

A regularised Coulomb law alone lets a joint loaded below its friction capacity creep (at a
speed proportional to its threshold speed), and a steep law is too stiff for large steps.
So a sliding joint whose slip rate passes through zero over an accepted step is tried held:
an equation of its own freezes its coordinate, and the consistent state tells the effort
that equation needs. Within the friction capacity mu r |F_r| + preload it stays held (the
velocity projection makes the stop plastic, as friction does); beyond it the joint slips on,
with the full friction against the way the load pushes it from the first instant. A held
joint lets go at the first accepted state where the effort exceeds the capacity. After any
switch the integration restarts from a consistent state.
"""

from __future__ import annotations

from collections.abc import Callable

from mechlib.core.outcome import SolverFailure
from mechlib.solvers.events import locate

__all__ = ["slip_stop", "switch_sticking"]

_HOLD_MARGIN = 1e-9  # relative: an effort equal to the capacity still holds


def switch_sticking(system, q, qd, t: float, view, consistent: Callable) -> bool:
    """Stick or free the joint frictions at the accepted state (q, qd, t) whose consistent
    view (velocities and multipliers) is `view`; `consistent(system, q, qd, t)` gives
    (qd, qdd, lam). True when the model changed (the caller restarts)."""
    frictions = [  # a locked joint cannot slip: its friction neither sticks nor lets go
        e for e in system.elements if e.active and getattr(e, "can_stick", False) and not e.locked
    ]
    switched = stale = False
    for e in frictions:
        if stale:  # an earlier joint stuck or let go: the multipliers' rows have changed
            fresh_qd, _, lam = consistent(system, q, qd, t)
            view, stale = system.view(system.kin(q, fresh_qd, t), lam), False
        if e.stuck:
            effort = e.stick_effort(view)
            if abs(effort) > e.capacity(view) * (1.0 + _HOLD_MARGIN):
                e.slip(effort)
                switched = stale = True
        elif e.may_stick(view):
            e.stick(system.kin(q, qd, t))
            try:
                held_qd, _, lam = consistent(system, q, qd, t)
            except SolverFailure:  # already held by other equations (a motion, a stuck
                e.unstick()  # joint of the same loop): nothing to hold
                continue
            held = system.view(system.kin(q, held_qd, t), lam)
            effort = e.stick_effort(held)
            if abs(effort) > e.capacity(held) * (1.0 + _HOLD_MARGIN):
                before = e.impending
                e.slip(effort)
                switched = switched or e.impending != before
            else:
                switched = stale = True
    return switched


def slip_stop(
    system, t0: float, t1: float, view0, view1, view_at: Callable[[float], object]
) -> float | None:
    """The earliest time in (t0, t1] at which a sliding joint friction's slip rate passes
    through zero, or a held one's effort passes its capacity (located as events are), or
    None; `view_at(t)` re-solves the step to t. Either is a switch of the model, which the
    step then ends at (switch_sticking carries it out)."""
    first = None
    for e in system.elements:
        if not (e.active and getattr(e, "can_stick", False)) or e.locked:
            continue
        located = _let_go if e.stuck else _slip_reversal
        t = located(e, t0, t1, view0, view1, view_at)
        if t is not None:
            first = t if first is None else min(first, t)
    return first


def _slip_reversal(e, t0: float, t1: float, view0, view1, view_at) -> float | None:
    """When the sliding friction `e`'s slip rate passes through zero within (t0, t1]. A
    slide starting from within the regularised band has none: its stick was tried at t0,
    an accepted state (`may_stick`; after an event's restart it is tried at t1, the rate
    having changed sign), and the zero of its start rate's noise (2e-8 rad/s) was a sliver
    of a step (4e-10 s) whose velocity read the position round-off
    (tests/mechlib/test_slip_stop.py)."""
    r0, r1 = e.slip_rate(view0), e.slip_rate(view1)
    if r0 * r1 >= 0.0 or abs(r0) < e.v_threshold:
        return None  # no reversal, or a slide starting from within the regularised band
    sign = -1.0 if r0 > 0.0 else 1.0
    return locate(sign * r0, sign * r1, t0, t1, lambda tt: sign * e.slip_rate(view_at(tt)))


def _let_go(e, t0: float, t1: float, view0, view1, view_at) -> float | None:
    """When the held friction `e`'s effort first exceeds its capacity within (t0, t1]: the
    instant it lets go, instead of the step's end (a step of 30 ms held a wheel 20 ms past
    it). Located just past the crossing, so that switch_sticking lets go there."""

    def excess(view) -> float:
        return abs(e.stick_effort(view)) - e.capacity(view) * (1.0 + 2.0 * _HOLD_MARGIN)

    g0, g1 = excess(view0), excess(view1)
    if g0 >= 0.0 or g1 < 0.0:
        return None  # within its capacity at the step's end, or already beyond at its start
    return locate(g0, g1, t0, t1, lambda tt: excess(view_at(tt)))
