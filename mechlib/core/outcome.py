"""How an analysis ended: its status, failures, work counters, events and the requested
channels (`Solution`); the model errors found before solving. A leaf: it imports nothing of
mechlib, so every layer reports its outcome in the same terms."""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

__all__ = [
    "EventRecord",
    "ModelError",
    "RunStatus",
    "Solution",
    "SolverFailure",
    "SolverStats",
    "Status",
    "interrupt_of",
]

RunStatus = Literal["ok", "failed", "interrupted"]


class Status(enum.Enum):
    """How a step or a run ended: a code and the human text that goes with it."""

    SUCCESSFUL = ("successful", "finished")
    STEP_REJECTED = (
        "step_rejected",
        "step rejected (error test or Newton iteration): retried with a smaller step",
    )
    EVENT_STOP = ("event_stop", "stopped by an event")
    MAX_STEPS_REACHED = (
        "max_steps_reached",
        "the limit of analysis.max_steps (accepted and rejected steps) is reached",
    )
    STEP_COLLAPSE = (
        "step_collapse",
        "the step size collapsed (a load or a motion growing without bound)",
    )
    STALLED = (
        "stalled",
        "no progress: the step size fell below its floor (a singular position the motion "
        "cannot pass)",
    )
    NEWTON_FAILED = ("newton_failed", "Newton iterations did not converge")
    SINGULAR = (
        "singular",
        "singular matrix (a toggle or dead point, or a free degree of freedom without load path)",
    )
    NOT_HELD = ("not_held", "static equilibrium not found: a body is not held")
    INTEGRATOR_FAILED = ("integrator_failed", "the integrator (scipy) reported a failure")
    NOT_FINITE = ("not_finite", "a state, a force or a result value is not finite")
    EVALUATION_FAILED = (
        "evaluation_failed",
        "an expression, a force element or a request could not be evaluated",
    )
    INTERRUPTED = ("interrupted", "interrupted by the user (SIGINT or SIGTERM)")
    BRANCH_CHANGED = (
        "branch_changed",
        "the mechanism left the assembly branch of its drawn geometry (or of its guesses)",
    )

    def __init__(self, code: str, message: str):
        self.code = code
        self.message = message

    @property
    def ok(self) -> bool:
        """The run finished (at its end, or where an event stopped it)."""
        return self in (Status.SUCCESSFUL, Status.EVENT_STOP)


class ModelError(Exception):
    """The model is not well posed (redundant equations, wrong degrees of freedom).

    `problems` holds (owner, message) pairs: the joint or motion to point at, and the text.
    """

    def __init__(self, problems: list[tuple[str, str]]):
        super().__init__("; ".join(m for _, m in problems))
        self.problems = problems


@dataclass
class SolverStats:
    """Work counters of one analysis (docs/analyses.md, Statistics, says what each counts
    per analysis): accepted and rejected steps, Newton iterations, matrix factorisations
    (LU, sparse LU, least squares), Jacobian evaluations (the derivatives a Newton or
    integrator matrix is made of), and the processor time of the whole solve (s).
    `step_ends`: generalized-alpha's accepted steps' end times (s), in order, of the steps
    taken in Python and by the rigid whole-run kernel (not the modal one's, which serves
    steps landing on the output times: then fewer than `steps`); the step grid of an
    accuracy companion (mechlib.model.step_grid); not a counter."""

    steps: int = 0
    rejected_steps: int = 0
    newton_iterations: int = 0
    factorizations: int = 0
    jacobian_evaluations: int = 0
    cpu_seconds: float = 0.0
    step_ends: list[float] = field(default_factory=list, repr=False)

    def as_dict(self) -> dict[str, float]:
        return {
            "steps": self.steps,
            "rejected_steps": self.rejected_steps,
            "newton_iterations": self.newton_iterations,
            "factorizations": self.factorizations,
            "jacobian_evaluations": self.jacobian_evaluations,
            "cpu_seconds": self.cpu_seconds,
        }


@dataclass(frozen=True)
class EventRecord:
    """An event that fired: its name, the time (s) and the actions carried out."""

    name: str
    time: float
    actions: tuple[str, ...] = ()


class SolverFailure(Exception):
    """A numerical failure: when (t, s), where (constraint or element labels), why (the
    message) and its `status` (mechlib.core.outcome.Status)."""

    def __init__(
        self,
        message: str,
        *,
        time: float | None = None,
        where: tuple[str, ...] = (),
        status: Status = Status.EVALUATION_FAILED,
    ):
        super().__init__(message)
        self.time = time
        self.where = where
        self.status = status


@dataclass
class PhaseSpan:
    """A phase of a phased run (mechlib.Phases) in its Solution: name, analysis, start and
    end times (s), its rows `first_row` to `first_row + rows - 1` of the channels, and
    whether an event's stop ended it."""

    name: str
    analysis: str
    start: float
    end: float
    first_row: int
    rows: int
    ended_by_event: bool = False


@dataclass
class Solution:
    """Result of `mechlib.solve`.

    `time` has shape (n,) in s; `channels` maps a column name (`REQUEST.COMPONENT`) to an
    array of shape (n,) in SI units. On failure, `status == "failed"`, `message` says when,
    where and why, and the arrays hold what was computed up to the failure; a run stopped
    by SIGINT or SIGTERM is `"interrupted"`, with the rows computed before. `result`: the
    run's Status (mechlib.solvers.contract), next to the message. `max_step`: of a dynamic
    run, the largest step its integrator was allowed (s; `analysis.max_step`, else its
    default: mechlib.solvers.dense.step_bound), None for other analyses.
    """

    status: RunStatus
    message: str
    analysis: str
    time: np.ndarray
    channels: dict[str, np.ndarray]
    stats: SolverStats = field(default_factory=SolverStats)
    warnings: list[str] = field(default_factory=list)
    events: list[EventRecord] = field(default_factory=list)
    result: Status = Status.SUCCESSFUL
    max_step: float | None = None
    phases: list[PhaseSpan] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def interrupt_of(error: BaseException) -> KeyboardInterrupt | None:
    """The SIGINT/SIGTERM (loadcases.foundation.interrupts) behind `error`: itself, or the
    one a compiled kernel's dispatcher met while it ran (numba then raises SystemError
    "returned a result with an exception set", the interrupt as its context)."""
    seen: BaseException | None = error
    while seen is not None:
        if isinstance(seen, KeyboardInterrupt):
            return seen
        seen = seen.__cause__ or seen.__context__
    return None
