"""One entry point: `solve(mechanism, analysis, *, requests, ...) -> Solution`."""

from __future__ import annotations

import functools
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from mechlib.checks.model_check import MechanismCheck, check_model, inspect_mechanism
from mechlib.checks.singularity import toggle_warnings
from mechlib.core.outcome import (
    ModelError,
    RunStatus,
    Solution,
    SolverFailure,
    SolverStats,
    Status,
    interrupt_of,
)
from mechlib.core.work import tally
from mechlib.flexible.guards import (
    deformation_warnings,
    spin_warnings,
    unresolved_mode_warnings,
)
from mechlib.model.analysis import (
    BranchCheck,
    Dynamic,
    Kinematic,
    Phases,
    QuasiStatic,
    Static,
    Trajectory,
)
from mechlib.model.mechanism import Mechanism
from mechlib.outputs.requests import JointCoordinate, JointReaction, evaluate_requests
from mechlib.solvers.assembly import Assembled, assemble
from mechlib.solvers.branches import BranchChange, orientation_changes, row_changes
from mechlib.solvers.contract import Stepper
from mechlib.solvers.dense import step_bound
from mechlib.solvers.finite import check_recorded_state, explain_failure, nonfinite_channel
from mechlib.solvers.genalpha.stepper import GeneralizedAlphaStepper
from mechlib.solvers.kinematic import KinematicStepper
from mechlib.solvers.march import march
from mechlib.solvers.modes import ModalResult, Modes, modal_channels, normal_modes
from mechlib.solvers.phases import PhaseRecord, phase_spans, run_phases
from mechlib.solvers.solve_copy import solve_copy
from mechlib.solvers.solve_memo import SolveMemo
from mechlib.solvers.static.analyses import QuasiStaticStepper, run_static
from mechlib.solvers.static_start import settle_modes
from mechlib.system.planar import make_system
from mechlib.system.system import System

__all__ = ["MechanismCheck", "check_model", "inspect_mechanism", "solve"]

Analysis = Kinematic | Static | QuasiStatic | Dynamic | Modes | Phases


def _stepper(
    system: System, analysis: Kinematic | QuasiStatic | Dynamic, stats: SolverStats
) -> Stepper:
    """The stepper of an analysis in time (mechlib.solvers.contract)."""
    if isinstance(analysis, Kinematic):
        return KinematicStepper(system, analysis, stats)
    if isinstance(analysis, QuasiStatic):
        return QuasiStaticStepper(system, analysis, stats)
    if analysis.integrator == "radau":
        if system.states:  # its right-hand side holds q and qd only: the states would freeze
            names = ", ".join(f"'{e.name}'" for e in system.states.owners)
            raise ModelError(
                [
                    (
                        "",
                        f"the element states of {names} need the generalized-alpha "
                        "integrator: drop 'integrator: radau'",
                    )
                ]
            )
        from mechlib.solvers.radau import RadauStepper  # scipy.integrate, only for this integrator

        return RadauStepper(system, analysis, stats)
    return GeneralizedAlphaStepper(system, analysis, stats)


def _check_events(analysis: Analysis, events: Sequence) -> None:
    if isinstance(analysis, Phases):
        for phase in analysis.phases:
            if not isinstance(phase.analysis, Static):  # a static phase has none to watch
                _check_events(phase.analysis, events)
        return
    if events and isinstance(analysis, Static):
        raise ModelError(
            [("", "events need an analysis in time (a static analysis solves one instant)")]
        )
    if events and isinstance(analysis, Dynamic) and analysis.integrator == "radau":
        raise ModelError(
            [
                (
                    "",
                    "events are located by the generalized-alpha integrator: "
                    "drop 'integrator: radau' or the events",
                )
            ]
        )


@dataclass(frozen=True)
class _Segment:
    """A stretch of a run checked on its own: a phase's name ("" for an unphased run), its
    analysis, its rows and the steps its integrator accepted."""

    name: str
    analysis: Analysis
    rows: Trajectory
    steps: int


@dataclass
class _Run:
    """What an analysis produced: rows (or modes), events, status and message."""

    trajectory: Trajectory
    stats: SolverStats
    events: list
    modes: ModalResult | None = None
    result: Status = Status.SUCCESSFUL
    message: str = "finished"
    phases: list[PhaseRecord] = field(default_factory=list)

    def segments(self, analysis: Analysis) -> list[_Segment]:
        """Each phase of a phased run as it ran, else the run itself as one segment."""
        if not self.phases:
            return [_Segment("", analysis, self.trajectory, self.stats.steps)]
        assert isinstance(analysis, Phases)
        return [
            _Segment(r.name or str(i + 1), p.analysis, r.trajectory, r.steps)
            for i, (p, r) in enumerate(zip(analysis.phases, self.phases))
        ]


def _analyse(
    system: System,
    analysis: Analysis,
    run: _Run,
    initial,
    events,
    progress,
    warnings: list[str],
    branches: BranchCheck,
    memo: SolveMemo | None = None,
) -> None:
    """Assemble (notes on the initial values and branch changes to `warnings`; a branch
    change fails the run when `branches.error`; the start `memo` keeps, when given), then
    run the analysis into `run`; SolverFailure leaves what was computed."""
    start = getattr(analysis, "start", getattr(analysis, "time", 0.0))
    with tally(run.stats):
        assembled = _assembled(system, analysis, start, initial, branches, run.stats, memo)
        warnings += assembled.notes
        _branch_outcome(assembled.branches, branches, warnings)
        system.begin(system.kin(assembled.q, assembled.qd, start))
        run.stats.newton_iterations += assembled.newton_iterations
        _check_events(analysis, events)
        if isinstance(analysis, Modes):
            run.modes = normal_modes(system, assembled.q, analysis.time, run.stats).first(
                analysis.count
            )
            system.commit(system.kin(run.modes.q, None, analysis.time))
        elif isinstance(analysis, Static):
            run_static(system, analysis, assembled.q, run.trajectory, run.stats)
        elif isinstance(analysis, Phases):
            run.result = run_phases(
                system,
                analysis,
                assembled.q,
                assembled.qd,
                stats=run.stats,
                stepper=_stepper,
                trajectory=lambda: _new_phase(system, run),
                records=run.phases,
                events=events,
                event_log=run.events,
                progress=progress,
            )
        else:
            run.result = march(
                _stepper(system, analysis, run.stats),
                assembled.q,
                assembled.qd,
                run.trajectory,
                progress=progress,
                events=events,
                event_log=run.events,
            )


def _assembled(
    system: System,
    analysis: Analysis,
    start: float,
    initial,
    branches: BranchCheck,
    stats: SolverStats,
    memo: SolveMemo | None,
) -> Assembled:
    """The initial state at `start` (s): assembled, its flexible bodies' modes settled for a
    dynamic run (equilibrium analyses find the deflection anyway); kept by `memo`."""

    def found() -> Assembled:
        assembled = assemble(system, start, initial, branches)
        if isinstance(analysis, Dynamic):
            assembled = settle_modes(system, assembled, start, initial)
        return assembled

    if memo is None:
        return found()
    return memo.assembled((isinstance(analysis, Dynamic), start), stats, found)


def _checked(
    system: System, analysis: Analysis, redundant: str, memo: SolveMemo | None
) -> list[str]:
    """The model check's warnings (mechlib.checks.model_check; kept by `memo` per analysis
    kind and start time, s)."""
    if memo is None:
        return check_model(system, analysis, redundant=redundant)
    key = (type(analysis).__name__, getattr(analysis, "start", 0.0))
    return memo.checked(system, key, lambda: check_model(system, analysis, redundant=redundant))


def _new_phase(system: System, run: _Run) -> Trajectory:
    """The trajectory of a phase about to begin, made the run's current one."""
    run.trajectory = Trajectory(
        snapshot=system.snapshot, check=functools.partial(check_recorded_state, system)
    )
    return run.trajectory


def _channels(system: System, run: _Run, requests) -> tuple[np.ndarray, dict]:
    """Output times and channels: one row per mode for modes, else per recorded state (the
    phases of a phased run one after the other, each evaluated as its analysis ran)."""
    if run.modes is not None:
        return (
            np.full(len(run.modes.frequencies), run.modes.time),
            modal_channels(system, run.modes, requests),
        )
    parts = [r.trajectory for r in run.phases if len(r.trajectory)] or [run.trajectory]
    times, columns = [], []
    for rows in parts:
        space, trajectory = system.in_space(rows)  # a planar one lifted to 3-D
        columns.append(evaluate_requests(space, trajectory, requests) if len(trajectory) else {})
        times.append(np.array(rows.time, dtype=float))
    if len(parts) == 1:
        return times[0], columns[0]
    return np.concatenate(times), {k: np.concatenate([c[k] for c in columns]) for k in columns[0]}


def _position_warnings(system: System, segment: _Segment) -> list[str]:
    """Warnings from the recorded positions: toggles, deformation, spin, unresolved modes
    (the mean step of the segment: its duration over its own steps)."""
    warnings: list[str] = []
    analysis, trajectory = segment.analysis, segment.rows
    if not isinstance(analysis, Modes):
        warnings += toggle_warnings(system, trajectory)
        warnings += deformation_warnings(system, trajectory)
        warnings += spin_warnings(system, trajectory)
    if isinstance(analysis, Dynamic) and len(trajectory):
        duration = trajectory.time[-1] - trajectory.time[0]
        unresolved = unresolved_mode_warnings(system, duration, segment.steps)
        where = f"phase {segment.name}: " if segment.name else ""
        warnings += [where + w for w in unresolved]
    return warnings


def _branch_outcome(changes: list[BranchChange], check: BranchCheck, warnings: list[str]) -> None:
    """Branch changes as warnings, or (`check.error`) as the failure of the run."""
    if not changes:
        return
    if check.error:
        first = changes[0]
        raise SolverFailure(
            "; ".join(c.message() for c in changes) + " (`branches: {on_change: error}`)",
            time=first.time,
            where=tuple(j for j, _, _ in first.joints),
            status=Status.BRANCH_CHANGED,
        )
    warnings += [c.message() for c in changes]


def _row_branches(
    system: System, analysis: Analysis, trajectory: Trajectory, events: list, check: BranchCheck
) -> list:
    """Snap-throughs between the recorded rows of a quasi-static or kinematic run."""
    if not isinstance(analysis, Kinematic | QuasiStatic) or len(trajectory) < 2:
        return []
    joints = [joint for joint, kind in system.measures if kind == "angle"]
    if not joints:
        return []
    space, lifted = system.in_space(trajectory)
    requests = [JointCoordinate(f"branch {j}", j, "angle") for j in joints]
    channels = evaluate_requests(space, lifted, requests)
    angles = {j: channels[f"branch {j}.value"] for j in joints}
    times = np.array(trajectory.time)
    changes = row_changes(times, angles, check, [e.time for e in events])
    if not events and _square(system, times[0], trajectory.q[0]):
        turned = orientation_changes(system, times, np.array(trajectory.q), angles)
        seen = {c.time for c in changes}
        changes += [c for c in turned if c.time not in seen]
        changes.sort(key=lambda c: c.time)
    return changes


def _square(system: System, t: float, q: np.ndarray) -> bool:
    """The constraints, motions included, as many as the coordinates (no freedom left)."""
    rows, columns = system.phi_q(system.kin(q, None, float(t))).shape
    return bool(rows == columns)


def _check_rows(
    system: System,
    analysis: Analysis,
    run: _Run,
    warnings: list[str],
    *,
    checks: bool,
    branches: BranchCheck,
    throw: bool,
) -> None:
    """The checks of the recorded positions (`checks`) and of branch changes between rows,
    phase by phase; a branch change under `branches.error` fails the run."""
    segments = run.segments(analysis)
    if checks:
        for segment in segments:
            warnings += _position_warnings(system, segment)
    if (checks or branches.error) and run.result.ok:
        try:
            for segment in segments:
                changes = _row_branches(
                    system, segment.analysis, segment.rows, run.events, branches
                )
                _branch_outcome(changes, branches, warnings)
        except SolverFailure as failure:
            if throw:
                raise
            run.result, run.message = failure.status, str(failure)


def _dropped_rows(analysis: Analysis) -> np.ndarray | None:
    """Output times (s) whose rows the results leave out: an accuracy companion solved
    beside its run records a row at each of the run's output times, and keeps those its
    estimate reads (mechlib.model.step_feed.GrowingGrid.dropped_rows)."""
    grid = getattr(analysis, "grid", None)
    return None if grid is None else grid.dropped_rows()


def _summary_status(result: Status) -> RunStatus:
    """`ok`, `interrupted` or `failed` (the summary's status)."""
    if result.ok:
        return "ok"
    return "interrupted" if result is Status.INTERRUPTED else "failed"


def _requests_at_rows(
    system: System, analysis: Analysis, run: _Run, requests: Sequence, throw: bool
) -> tuple[np.ndarray, dict]:
    """The requests at the run's rows (`_channels`). A request that cannot be evaluated
    fails the run with the columns that could be. A signal while they are evaluated stops
    the run there (`interrupted`, all its rows kept) and they are evaluated again: they are
    the run's wrap-up, which a second signal stops."""
    try:
        return _channels(system, run, requests)
    except SolverFailure as failure:  # a request that cannot be evaluated (expression error)
        if throw:
            raise
        run.result, run.message = failure.status, f"requests: {failure}"
        channels = getattr(failure, "channels", {})  # the columns that did not fail
        return np.array(run.trajectory.time), channels
    except (KeyboardInterrupt, SystemError) as stop:
        if run.result is Status.INTERRUPTED:
            raise
        _stopped_by(stop, analysis, run, throw)
        return _requests_at_rows(system, analysis, run, requests, throw)


def _stopped_by(stop: BaseException, analysis: Analysis, run: _Run, throw: bool) -> None:
    """The run marked interrupted by the signal behind `stop` (raised again where there is
    none, or with `throw`)."""
    interrupt = interrupt_of(stop)
    if throw or interrupt is None:
        raise stop
    run.result = Status.INTERRUPTED
    run.message = _interrupted_message(analysis, run.trajectory, str(interrupt))


def _interrupted_message(analysis: Analysis, trajectory: Trajectory, signal_name: str) -> str:
    """Where an interrupt stopped the run, and what was kept."""
    by = f" by {signal_name}" if signal_name else ""
    if not len(trajectory):
        return f"{analysis.name} analysis interrupted{by} before its first output"
    end = getattr(analysis, "end", None)
    of = f" of {end:g} s" if isinstance(end, int | float) else ""
    return (
        f"{analysis.name} analysis interrupted{by} at t = {trajectory.time[-1]:.6g} s{of}; "
        f"the {len(trajectory)} rows computed so far are kept"
    )


def solve(
    mechanism: Mechanism,
    analysis: Analysis,
    *,
    requests: Sequence = (),
    initial: Sequence = (),
    redundant: str = "error",
    throw: bool = True,
    events: Sequence = (),
    progress: Callable[[float, float], None] | None = None,
    checks: bool = True,
    branches: BranchCheck | None = None,
    memo: SolveMemo | None = None,
) -> Solution:
    """Check, assemble and solve; channels `REQUEST.COMPONENT` at the output times.

    `checks` False leaves out the checks of the recorded positions after the run (toggles,
    deformation, spin, unresolved modes: their warnings only) for a run whose warnings are
    not kept, e.g. an accuracy companion; times, channels and status are the same.

    `branches` (default BranchCheck()): when the assembly, or a quasi-static or kinematic
    run, is said to leave the branch of the drawn geometry (mechlib.solvers.branches);
    a warning, or with `error` a failed run that keeps its rows.

    The `mechanism` is left unchanged (the solve works on its own copy of the force
    elements): solving it twice gives the same results. Raises ModelError for an ill-posed
    model (always). A numerical failure raises SolverFailure when `throw`, else returns a
    failed Solution holding what was computed (`Solution.result` says which failure,
    `message` when, where and why). A non-finite state or column is such a failure.

    `memo` (mechlib.solvers.solve_memo): the model check and the assembled start of the
    first solve given it, reused by the next ones of the same mechanism, initial values,
    branch check and `redundant` (a run's accuracy companion): the same results.
    """
    cpu0 = _time.thread_time()  # this solve's: a companion may be solved beside it
    branch_check = branches or BranchCheck()
    system = make_system(solve_copy(mechanism))  # events and memories never change the caller's
    if memo is not None and not memo.serves(mechanism, initial, branches, redundant):
        memo = None
    if memo is not None:
        memo.patterns.attach(system)
    warnings = _checked(system, analysis, redundant, memo)
    warnings += system.output_notes(any(isinstance(r, JointReaction) for r in requests))
    feed = getattr(analysis, "feed", None)  # a companion beside the run follows its steps
    run = _Run(
        Trajectory(snapshot=system.snapshot, check=functools.partial(check_recorded_state, system)),
        SolverStats() if feed is None else SolverStats(step_ends=feed.ends),
        [] if feed is None else feed.events,
    )
    if isinstance(analysis, Modes):
        events = ()  # nothing moves: events have nothing to watch
    try:
        _analyse(system, analysis, run, initial, events, progress, warnings, branch_check, memo)
    except SolverFailure as failure:
        if throw:
            raise
        run.result = failure.status
        run.message = explain_failure(system, run.trajectory, failure)
    except (KeyboardInterrupt, SystemError) as stop:  # SIGINT/SIGTERM: keep the rows
        run.trajectory.trim()  # a row half-appended when the signal came
        _stopped_by(stop, analysis, run, throw)
    dropped = _dropped_rows(analysis)
    if dropped is not None:
        run.trajectory = run.trajectory.without(dropped)
    times, channels = _requests_at_rows(system, analysis, run, requests, throw)
    bad = nonfinite_channel(times, channels) if run.result.ok else None
    if bad is not None:
        run.result = Status.NOT_FINITE
        run.message = f"column {bad[0]} is not finite ({bad[2]:g}) at t = {bad[1]:.6g} s"
    try:
        _check_rows(
            system, analysis, run, warnings, checks=checks, branches=branch_check, throw=throw
        )
    except (KeyboardInterrupt, SystemError) as stop:  # a signal: the run kept, unchecked
        _stopped_by(stop, analysis, run, throw)
    run.stats.cpu_seconds = _time.thread_time() - cpu0
    message = run.message
    if run.events:
        message += "; events: " + ", ".join(f"{e.name} at t = {e.time:.6g} s" for e in run.events)
    return Solution(
        _summary_status(run.result),
        message,
        analysis.name,
        times,
        channels,
        run.stats,
        warnings,
        run.events,
        run.result,
        step_bound(system, analysis) if isinstance(analysis, Dynamic) else None,
        phase_spans(run.phases),
    )
