"""One entry point: `solve(mechanism, analysis, *, requests, ...) -> Solution`."""
from __future__ import annotations

import functools
import time as _time
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from mechlib.analysis import Dynamic, Kinematic, QuasiStatic, Static, Trajectory
from mechlib.assembly import assemble
from mechlib.check import ModelError, degrees_of_freedom, find_redundant
from mechlib.finite import check_recorded_state, explain_failure, nonfinite_channel
from mechlib.genalpha import run_generalized_alpha
from mechlib.kinematic import run_kinematic
from mechlib.modes import Modes, modal_channels, normal_modes
from mechlib.model import Mechanism
from mechlib.radau import run_radau
from mechlib.requests import evaluate_requests
from mechlib.solution import Solution, SolverFailure, SolverStats
from mechlib.solve_copy import solve_copy
from mechlib.singularity import toggle_warnings
from mechlib.static import run_quasi_static, run_static
from mechlib.system import System

__all__ = ["solve", "check_model", "MechanismCheck", "inspect_mechanism"]

Analysis = Kinematic | Static | QuasiStatic | Dynamic | Modes


def check_model(system: System, analysis: Analysis, *, redundant: str = "error") -> list[str]:
    """Redundant equations and degrees of freedom, before any solving.

    Raises ModelError naming joints and directions; with redundant="drop" removes the
    dependent rows instead and returns warnings saying those reactions are not unique.
    """
    k = system.kin(system.design_q(), None, getattr(analysis, "start", 0.0))
    jac = system.phi_q(k)
    found = find_redundant(jac, system.labels, system.owners, set(system.body_names),
                           owner_rank=system.owner_rank)
    warnings = []
    if found and redundant != "drop":
        raise ModelError([(r.owner, "redundant constraint: " + r.describe()) for r in found])
    if found:
        system.drop_rows([r.row for r in found])
        warnings = [f"redundant constraint dropped: {r.describe()}; the reactions of "
                    f"{', '.join((r.owner,) + r.depends_on)} are not unique" for r in found]
    if isinstance(analysis, Kinematic):
        dof = degrees_of_freedom(system.phi_q(k))
        if dof != 0:
            motions = ", ".join(system.mechanism.motions) or "none"
            raise ModelError([("", f"kinematic analysis needs 0 degrees of freedom after the "
                                   f"motions ({motions}), but the mechanism has {dof}: add "
                                   "motions or use a dynamic or quasi-static analysis")])
    return warnings


@dataclass(frozen=True)
class MechanismCheck:
    """What a mechanism is at its design position: sizes, mobility and redundancy."""

    bodies: int
    equations: int
    degrees_of_freedom: int
    redundant: tuple[str, ...]
    assembled: bool


def inspect_mechanism(mechanism: Mechanism) -> MechanismCheck:
    """Degrees of freedom and redundant equations (by joint and direction) at design."""
    system = System(mechanism)
    k = system.kin(system.design_q(), None, 0.0)
    jac = system.phi_q(k)
    found = find_redundant(jac, system.labels, system.owners, set(system.body_names),
                           owner_rank=system.owner_rank)
    assembled = bool(np.abs(system.phi(k)).max(initial=0.0) < 1e-9)
    return MechanismCheck(system.nb, len(system.labels) - system.nb,
                          degrees_of_freedom(jac), tuple(r.describe() for r in found), assembled)


def _run_modes(system: System, analysis: Modes, q0, trajectory, stats) -> None:
    """One row per mode at the equilibrium time; the shapes go to `trajectory.modes`."""
    q, freq, shapes = normal_modes(system, q0, analysis.time, stats)
    count = len(freq) if analysis.count is None else min(analysis.count, len(freq))
    zeros = np.zeros(len(system.labels))
    system.commit(system.kin(q, None, analysis.time))
    for _ in range(count):
        trajectory.record(analysis.time, q, np.zeros_like(q), np.zeros_like(q), zeros)
    stats.steps += 1
    trajectory.modes = (q, freq[:count], shapes[:count])


def _run(system: System, analysis: Analysis, q0, qd0, trajectory, stats, progress,
         events=(), event_log=None) -> None:
    if isinstance(analysis, Modes):
        _run_modes(system, analysis, q0, trajectory, stats)
    elif isinstance(analysis, Kinematic):
        run_kinematic(system, analysis, q0, qd0, trajectory, stats, progress, events,
                      event_log)
    elif isinstance(analysis, Static):
        run_static(system, analysis, q0, trajectory, stats, progress)
    elif isinstance(analysis, QuasiStatic):
        run_quasi_static(system, analysis, q0, trajectory, stats, progress, events,
                         event_log)
    elif analysis.integrator == "radau":
        run_radau(system, analysis, q0, qd0, trajectory, stats, progress)
    else:
        run_generalized_alpha(system, analysis, q0, qd0, trajectory, stats, progress,
                              events, event_log)


def solve(mechanism: Mechanism, analysis: Analysis, *, requests: Sequence = (),
          initial: Sequence = (), redundant: str = "error", throw: bool = True,
          events: Sequence = (),
          progress: Callable[[float, float], None] | None = None) -> Solution:
    """Check, assemble and solve; channels `REQUEST.COMPONENT` at the output times.

    The `mechanism` is left unchanged (the solve works on its own copy of the force
    elements): solving it twice gives the same results. Raises ModelError for an ill-posed
    model (always). A numerical failure raises
    SolverFailure when `throw`, else returns a failed Solution holding what was computed.
    """
    cpu0 = _time.process_time()
    system = System(solve_copy(mechanism))  # events and memories never change the caller's
    warnings = check_model(system, analysis, redundant=redundant)
    stats, trajectory = SolverStats(), Trajectory(
        snapshot=system.snapshot, check=functools.partial(check_recorded_state, system))
    event_log: list = []
    status, message = "ok", "finished"
    start = getattr(analysis, "start", getattr(analysis, "time", 0.0))
    if isinstance(analysis, Modes) and events:
        events = ()  # nothing moves: events have nothing to watch
    try:
        assembled = assemble(system, start, initial)
        warnings += assembled.notes
        system.begin(system.kin(assembled.q, assembled.qd, start))
        stats.newton_iterations += assembled.newton_iterations
        if events and isinstance(analysis, Static):
            raise ModelError([("", "events need an analysis in time (a static analysis "
                                   "solves one instant)")])
        if events and isinstance(analysis, Dynamic) and analysis.integrator == "radau":
            raise ModelError([("", "events are located by the generalized-alpha integrator: "
                                   "drop 'integrator: radau' or the events")])
        _run(system, analysis, assembled.q, assembled.qd, trajectory, stats, progress,
             events, event_log)
    except SolverFailure as failure:
        if throw:
            raise
        status, message = "failed", explain_failure(system, trajectory, failure)
    try:
        if isinstance(analysis, Modes) and len(trajectory):
            channels = modal_channels(system, *trajectory.modes[:1], analysis.time,
                                      *trajectory.modes[1:], requests)
        else:
            channels = evaluate_requests(system, trajectory, requests) if len(trajectory) else {}
    except SolverFailure as failure:  # a request that cannot be evaluated (expression error)
        if throw:
            raise
        status, message = "failed", f"requests: {failure}"
        channels = getattr(failure, "channels", {})  # the columns that did not fail
    bad = nonfinite_channel(np.asarray(trajectory.time), channels) if status == "ok" else None
    if bad is not None:
        status = "failed"
        message = f"column {bad[0]} is not finite ({bad[2]:g}) at t = {bad[1]:.6g} s"
    if not isinstance(analysis, Modes):
        warnings += toggle_warnings(system, trajectory)
    stats.cpu_seconds = _time.process_time() - cpu0
    if event_log:
        message = message + "; events: " + ", ".join(f"{e.name} at t = {e.time:.6g} s"
                                                      for e in event_log)
    return Solution(status, message, analysis.name, np.array(trajectory.time), channels,
                    stats, warnings, event_log)
