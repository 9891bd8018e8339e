"""Events: a condition on the state becomes true, the model changes, the analysis goes on.

An event's `condition(t, view)` is a function g that is negative before the event and
>= 0 from it on (`angle(hl2) >= 90*deg` gives g = angle - 90 deg; a yes/no condition gives
-1/+1). The analyses watch g over each accepted step, locate its zero by re-solving the step
to shorter ends (Illinois regula falsi; bisection for yes/no conditions) to within
EVENT_TIME_TOLERANCE, record that state, carry out the actions and restart from there.
Actions: `activate`/`deactivate` an element or a motion, `release` a joint (its equations
go), `lock` a joint (its coordinate is frozen at the current value), `stop`.

A delayed event (`after`, `delay`) waits until the event it follows has fired at t_f; it is
then armed with g = t - (t_f + delay), located like any other, and fires `delay` s later (at
once, with the event it follows, when the delay is zero).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from mechlib.core.outcome import EventRecord
from mechlib.kinematics.view import StateView

__all__ = [
    "EVENT_TIME_TOLERANCE",
    "Action",
    "Event",
    "EventMonitor",
    "apply_actions",
    "fire",
    "first_events",
    "locate",
]

EVENT_TIME_TOLERANCE = 1e-9  # s
_MAX_LOCATE = 100
ACTIONS = ("activate", "deactivate", "release", "lock", "stop")


@dataclass(frozen=True)
class Action:
    """What an event does: `kind` in ACTIONS on `target` (None for stop)."""

    kind: str
    target: str | None = None

    def describe(self) -> str:
        return self.kind if self.target is None else f"{self.kind} {self.target}"


@dataclass(frozen=True)
class Event:
    """Fires once, when `condition(t, view)` goes from < 0 to >= 0; or, with `after`,
    `delay` s (>= 0) after the event named `after` fired (`condition` then unused: None)."""

    name: str
    condition: Callable[[float, StateView], float] | None
    actions: tuple[Action, ...]
    after: str | None = None
    delay: float = 0.0


def _timer(due: float) -> Callable[[float, StateView], float]:
    """g = t - due (s): crosses zero at the time `due`."""
    return lambda t, view: t - due


def _g(event: Event, t: float, view: StateView) -> float:
    """The condition value of an armed event (a delayed one is armed with its timer)."""
    assert event.condition is not None, f"event '{event.name}' is not armed"
    return float(event.condition(t, view))


class EventMonitor:
    """The armed events and their condition values at the last accepted state; the
    delayed events waiting for the event they follow."""

    def __init__(self, events=()):
        self.armed = [e for e in events if e.after is None]
        self.waiting = [e for e in events if e.after is not None]
        self.values: dict[str, float] = {}

    def arm(self, t: float, view: StateView) -> None:
        """Remember g of every armed event at an accepted state."""
        self.values = {e.name: _g(e, t, view) for e in self.armed}

    def crossed(self, t: float, view: StateView) -> list[Event]:
        """Armed events whose g went from < 0 to >= 0 since the last `arm`."""
        return [e for e in self.armed if self.values[e.name] < 0.0 <= _g(e, t, view)]

    def fired(self, events: list[Event], t: float) -> list[Event]:
        """Disarm `events` (fired at t, s); arm the delayed events that follow them, timed
        to fire `delay` s later; returns those due at once (a zero delay)."""
        self.armed = [e for e in self.armed if e not in events]
        names = {e.name for e in events}
        started = [e for e in self.waiting if e.after in names]
        self.waiting = [e for e in self.waiting if e.after not in names]
        timed = [replace(e, condition=_timer(t + e.delay)) for e in started]
        self.armed.extend(e for e in timed if e.delay > 0.0)
        return [e for e in timed if e.delay <= 0.0]


def locate(
    g0: float,
    g1: float,
    t0: float,
    t1: float,
    g_at: Callable[[float], float],
    tol: float = EVENT_TIME_TOLERANCE,
) -> float:
    """Earliest time in (t0, t1] where g >= 0, within `tol`: Illinois regula falsi on a
    continuous g, bisection when g jumps (yes/no conditions)."""
    lo, hi, glo, ghi = t0, t1, g0, g1
    side = 0
    for _ in range(_MAX_LOCATE):
        if hi - lo <= tol:
            break
        yes_no = abs(glo) == abs(ghi) == 1.0
        t = 0.5 * (lo + hi) if yes_no else hi - ghi * (hi - lo) / (ghi - glo)
        t = min(max(t, lo + 0.01 * (hi - lo)), hi - 0.01 * (hi - lo))
        g = g_at(t)
        if g >= 0.0:
            hi, ghi = t, g
            glo = glo * 0.5 if side == 1 else glo  # Illinois: halve the stale end
            side = 1
        else:
            lo, glo = t, g
            ghi = ghi * 0.5 if side == -1 else ghi
            side = -1
    return hi


def first_events(
    monitor: EventMonitor,
    t0: float,
    t1: float,
    view1: StateView,
    view_at: Callable[[float], StateView],
) -> tuple[float, list[Event]] | None:
    """The earliest of the armed events that fire over the step t0 -> t1 and their time, or
    None; `view1` is the state at t1 and `view_at(t)` re-solves the step to end at t."""
    fired = monitor.crossed(t1, view1)
    if not fired:
        return None
    first = {}
    for e in fired:

        def g_at(t, e=e):
            return _g(e, t, view_at(t))

        first[e.name] = locate(monitor.values[e.name], _g(e, t1, view1), t0, t1, g_at)
    t_e = min(first.values())
    return t_e, [e for e in fired if first[e.name] - t_e <= EVENT_TIME_TOLERANCE]


def switch(system, name: str | None, on: bool, k) -> None:
    """Switch an element or motion on or off at state `k`; an element switched on starts
    from that state (`start_from`: a stop already penetrating, no step in its damping)."""
    element = system.mechanism.forces.get(name)
    was_on = element is not None and element.active
    system.set_active(name, on)
    if on and not was_on and hasattr(element, "start_from"):
        element.start_from(system.view(k))


def apply_actions(system, event: Event, k) -> tuple[EventRecord, bool]:
    """Carry out an event's actions on the compiled system at the state `k` (its time is
    the event's); returns (record, stop requested)."""
    stop = False
    for action in event.actions:
        if action.kind == "stop":
            stop = True
        elif action.kind in ("activate", "deactivate"):
            switch(system, action.target, action.kind == "activate", k)
        elif action.kind == "release":
            system.release(action.target)
        elif action.kind == "lock":
            system.lock(action.target, k)
    return EventRecord(event.name, k.t, tuple(a.describe() for a in event.actions)), stop


def fire(system, monitor: EventMonitor, events: list[Event], k, log: list | None) -> bool:
    """Carry out `events` (fired together at state `k`), log them, disarm them, then the
    delayed events due at once after them; True when one of them stops the analysis."""
    stop = False
    while events:
        for e in events:
            record, stops = apply_actions(system, e, k)
            if log is not None:
                log.append(record)
            stop = stop or stops
        events = monitor.fired(events, k.t)
    return stop
