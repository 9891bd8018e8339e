"""The outcome of an analysis: how it ended, statistics, and the requested channels."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from mechlib.contract import Status

__all__ = ["EventRecord", "RunStatus", "Solution", "SolverFailure", "SolverStats"]

RunStatus = Literal["ok", "failed", "interrupted"]


@dataclass
class SolverStats:
    """Work counters of one analysis (docs/analyses.md, Statistics, says what each counts
    per analysis): accepted and rejected steps, Newton iterations, matrix factorisations
    (LU, sparse LU, least squares), Jacobian evaluations (the derivatives a Newton or
    integrator matrix is made of), and the processor time of the whole solve (s)."""

    steps: int = 0
    rejected_steps: int = 0
    newton_iterations: int = 0
    factorizations: int = 0
    jacobian_evaluations: int = 0
    cpu_seconds: float = 0.0

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
    message) and its `status` (mechlib.contract.Status)."""

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
class Solution:
    """Result of `mechlib.solve`.

    `time` has shape (n,) in s; `channels` maps a column name (`REQUEST.COMPONENT`) to an
    array of shape (n,) in SI units. On failure, `status == "failed"`, `message` says when,
    where and why, and the arrays hold what was computed up to the failure; a run stopped
    by SIGINT or SIGTERM is `"interrupted"`, with the rows computed before. `result`: the
    run's Status (mechlib.contract), next to the message.
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

    @property
    def ok(self) -> bool:
        return self.status == "ok"
