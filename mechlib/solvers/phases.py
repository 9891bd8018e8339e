"""Analyses in sequence (`Phases`): each phase starts from the state where the last ended.

A phase records into a trajectory of its own (static and quasi-static rows are read at
rest, dynamic rows are not: `Trajectory.at_rest`), so the outputs of each are evaluated as
its analysis computed them and then joined into one history.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np

from mechlib.core.outcome import PhaseSpan, SolverStats, Status
from mechlib.model.analysis import Dynamic, Phase, Phases, QuasiStatic, Static, Trajectory
from mechlib.solvers.assembly import solve_velocities
from mechlib.solvers.contract import Stepper
from mechlib.solvers.march import march
from mechlib.solvers.static.analyses import run_static
from mechlib.system.system import System

__all__ = ["PhaseRecord", "phase_spans", "run_phases"]


@dataclasses.dataclass
class PhaseRecord:
    """A phase as it ran: its name, analysis, start and end times (s), its rows and the
    steps it accepted (the run's `SolverStats.steps` counts all phases together)."""

    name: str
    analysis: str
    start: float
    end: float
    trajectory: Trajectory
    ended_by_event: bool = False
    steps: int = 0


def _timed(phase: Phase, start: float) -> Static | QuasiStatic | Dynamic:
    """The phase's analysis starting at `start` (s): where the previous phase ended, which
    an event's stop may have made earlier than the phase's own start."""
    analysis = phase.analysis
    if isinstance(analysis, Static):
        return dataclasses.replace(analysis, time=start)
    return dataclasses.replace(analysis, start=start)


def _switch_motions(system: System, phase: Phase, motions: Sequence[str], on: bool) -> None:
    """Motions not listed by the phase switched off for it (`on` False) or back on."""
    if phase.motions is None:
        return
    for name in motions:
        if name not in phase.motions:
            system.set_active(name, on)


def run_phases(
    system: System,
    spec: Phases,
    q: np.ndarray,
    qd: np.ndarray,
    *,
    stats: SolverStats,
    stepper: Callable[[System, QuasiStatic | Dynamic, SolverStats], Stepper],
    trajectory: Callable[[], Trajectory],
    records: list[PhaseRecord],
    events: Sequence = (),
    event_log: list | None = None,
    progress: Callable[[float, float], None] | None = None,
) -> Status:
    """Run the phases of `spec` from the assembled state (q, qd), appending a
    `PhaseRecord` to `records` as each begins (a failure raises SolverFailure and leaves
    what was recorded). Events are watched in the phases in time; a `stop` ends its phase."""
    motions = list(system.mechanism.motions)
    t = spec.start
    status = Status.SUCCESSFUL
    for phase in spec.phases:
        analysis = _timed(phase, t)
        rows = trajectory()
        records.append(PhaseRecord(phase.name, analysis.name, t, t, rows))
        k = system.kin(q, qd, t)
        held = [system.lock(joint, k) for joint in phase.locks]
        _switch_motions(system, phase, motions, False)
        steps_before = stats.steps
        try:
            if isinstance(analysis, Static):
                run_static(system, analysis, q, rows, stats)
            else:
                status = march(
                    stepper(system, analysis, stats),
                    q,
                    qd,
                    rows,
                    progress=progress,
                    events=events,
                    event_log=event_log,
                )
        finally:
            records[-1].steps = stats.steps - steps_before
            for row in held:
                system.let_go(row)
            _switch_motions(system, phase, motions, True)
        q, t = np.array(rows.q[-1]), float(rows.time[-1])
        records[-1].end = t
        records[-1].ended_by_event = status is Status.EVENT_STOP
        if isinstance(analysis, Dynamic):
            qd = np.array(rows.qd[-1])
        else:  # after an equilibrium the bodies are at rest: the motions' rates only
            qd = solve_velocities(system, system.kin(q, None, t))
    return status


def phase_spans(records: Sequence[PhaseRecord]) -> list[PhaseSpan]:
    """The phases as a Solution reports them: their rows counted in the joined history."""
    spans, first = [], 0
    for r in records:
        rows = len(r.trajectory)
        spans.append(PhaseSpan(r.name, r.analysis, r.start, r.end, first, rows, r.ended_by_event))
        first += rows
    return spans
