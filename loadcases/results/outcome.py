"""The outcome of one run of a case: its name, provenance and the mechlib solution."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from loadcases.foundation.diagnostics import Diagnostic
from mechlib.core.outcome import Solution

__all__ = ["RunOutcome"]


@dataclass
class RunOutcome:
    """One solved run.

    `name` is the case name (a `/` in it makes sub-folders of the output directory);
    `column_units` maps each result column (`REQUEST.COMPONENT`) to its SI unit text
    (`N`, `N*m`, `rad/s` ...), `request_kinds` each request's kind (`reaction`, `friction`,
    ...: `loadcases.build.requests.request_kinds`); `input_sha256` hashes the case, its
    mechanism file and the parameters of the run (`overrides`: those `--set` changed);
    `warnings` are the input's (validation and build) warnings, as data (the solver's are
    on the solution).
    """

    name: str
    case_file: Path
    analysis: str
    solution: Solution
    input_sha256: str
    column_units: dict[str, str] = field(default_factory=dict)
    warnings: list[Diagnostic] = field(default_factory=list)
    parameters: dict[str, float] = field(default_factory=dict)
    overrides: dict[str, float] = field(default_factory=dict)  # `--set` what-ifs (SI)
    checks: dict = field(default_factory=dict)  # e.g. {"torque_margin": {...}} for the summary
    request_kinds: dict[str, str] = field(default_factory=dict)  # {request: kind}
    input_error: bool = False  # not solved: the run's parameter values make its input invalid
    level: str = "limit"  # the level of the case's applied loads: "limit" or "ultimate"
    unwritten: str = ""  # why its files could not be written (then none is): a failed run

    @property
    def all_warnings(self) -> list[str]:
        """The input's warnings (each with its key) then the solver's: the summary's
        `warnings` (a reused run of a set prints these)."""
        return [*(d.keyed_message() for d in self.warnings), *self.solution.warnings]
