"""`loads accuracy CASE`: what accuracy costs in time, for one dynamic case.

The case is solved on a ladder of tolerances with each integrator; each solution is compared
with a reference, a much tighter run of the OTHER integrator (an independent method: its
errors are not those of the method under study). Per request column the error is measured
relative to the request's peak (the largest |value| of any component of that request in the
reference): over the whole run, at the end, and of the envelope peak (the max and min the
envelope would take). CPU time is the median of `repeats` warm runs. The cheapest setting
whose worst error meets the target is recommended.

When only one integrator can run the case (events, of its mechanism or of the case, are
located by generalized-alpha only), its own tighter run is the reference, and the study
says so; a study of Radau alone of such a case is an input error naming the events. With
both integrators the two references are also compared with each other: errors below that
agreement are not resolved.
"""

from __future__ import annotations

import dataclasses
import statistics
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import mechlib as ml
from loadcases.build.model import BuiltRun, build_run
from loadcases.build.precheck import case_problems, model_diagnostics
from loadcases.foundation.accuracy_target import DEFAULT_ACCURACY
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.foundation.limits import MIN_TOLERANCE
from loadcases.inputs.loader import CaseFile
from loadcases.run.global_error import request_of, request_peaks, shared_rows

__all__ = [
    "DEFAULT_TOLERANCES",
    "INTEGRATORS",
    "AccuracyStudy",
    "ColumnError",
    "ReferenceFailure",
    "Setting",
    "SettingResult",
    "accuracy_study",
    "check_study",
    "column_errors",
]

INTEGRATORS = ("generalized-alpha", "radau")
DEFAULT_TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)
REFERENCE_FACTOR = 1e-2  # the reference runs at the tightest tolerance x this


class ReferenceFailure(ml.SolverFailure):
    """A reference run failed: nothing can be measured against it (`loads accuracy` exits
    1 with its message, as for a solver failure)."""


@dataclass(frozen=True)
class Setting:
    """One solver setting: integrator name and its tolerance (relative local error)."""

    integrator: str
    tolerance: float

    def describe(self) -> str:
        return f"{self.integrator} at tolerance {self.tolerance:g}"


@dataclass(frozen=True)
class ColumnError:
    """Errors of one result column, fractions of its request's peak: the largest over the
    run, at the end time, and of the envelope extremes (max and min)."""

    over_time: float
    at_end: float
    of_peak: float


@dataclass
class SettingResult:
    """A setting's solution measured against the reference."""

    setting: Setting
    status: str
    message: str
    cpu_seconds: float
    stats: dict[str, float]
    errors: dict[str, ColumnError] = field(default_factory=dict)

    def worst(self, kind: str = "over_time") -> tuple[str, float]:
        """(column, error) of the largest error of `kind`; ("", nan) without errors."""
        if not self.errors:
            return "", float("nan")
        column = max(self.errors, key=lambda c: getattr(self.errors[c], kind))
        return column, getattr(self.errors[column], kind)

    def meets(self, target: float) -> bool:
        return self.status == "ok" and bool(self.errors) and self.worst()[1] <= target


@dataclass
class AccuracyStudy:
    """Every setting's result, the references used, and the recommendation."""

    case: str
    target: float
    results: list[SettingResult]
    references: dict[str, Setting]  # integrator studied -> its reference setting
    notes: list[str]
    reference_agreement: float | None = None

    @property
    def recommended(self) -> SettingResult | None:
        """The cheapest setting (CPU) meeting the target, or None."""
        good = [r for r in self.results if r.meets(self.target)]
        return min(good, key=lambda r: r.cpu_seconds) if good else None


def column_errors(solution: ml.Solution, reference: ml.Solution) -> dict[str, ColumnError]:
    """Errors of every column of `solution` against `reference`, relative to the peak of
    the column's request in the reference (columns of a request whose reference is zero
    throughout are left out: no scale to measure against). Over the run: at the output
    times both share (an event's row is at each run's own event time, not compared row by
    row with another time); at the end: the last rows when both have as many; of the
    envelope: every row of each up to the last time they share."""
    peaks = request_peaks(reference.channels)
    rows, rows_ref = shared_rows(solution.time, reference.time)
    if not len(rows):
        return {}
    same_end = len(solution.time) == len(reference.time)
    upto, upto_ref = rows[-1] + 1, rows_ref[-1] + 1
    out = {}
    for column, ref in reference.channels.items():
        peak = peaks[request_of(column)]
        mine = solution.channels.get(column)
        if mine is None or peak == 0.0:
            continue
        x, r = mine[:upto], ref[:upto_ref]
        out[column] = ColumnError(
            float(np.max(np.abs(mine[rows] - ref[rows_ref]))) / peak,
            float(abs(mine[-1] - ref[-1])) / peak if same_end else float("nan"),
            max(abs(float(x.max() - r.max())), abs(float(x.min() - r.min()))) / peak,
        )
    return out


def _dynamic_run(cf: CaseFile) -> BuiltRun:
    """The case built; an InputError at `analysis.type` unless it is dynamic."""
    built = build_run(cf)
    if not isinstance(built.analysis, ml.Dynamic):
        file, line, col = cf.where("case", "analysis.type")
        raise InputError(
            [
                Diagnostic(
                    file,
                    line,
                    col,
                    "analysis.type",
                    f"loads accuracy studies dynamic analyses (an integrator "
                    f"and its tolerance); this case's analysis is "
                    f"'{built.analysis.name}'",
                )
            ]
        )
    return built


def _solver(cf: CaseFile) -> Callable[[Setting], ml.Solution]:
    """A function solving the case with a setting (the model built anew for every run, so
    that no event or contact memory carries over from one run to the next); a model the
    engine refuses is an InputError placed as `loads run` places it."""
    _dynamic_run(cf)

    def solve(setting: Setting) -> ml.Solution:
        run = build_run(cf)
        analysis = dataclasses.replace(
            run.analysis, integrator=setting.integrator, tolerance=setting.tolerance
        )
        try:
            return run.solve(analysis)
        except ml.ModelError as error:
            raise InputError(model_diagnostics(cf, error)) from None

    return solve


def _usable(
    cf: CaseFile, events: Sequence[str], integrators: Sequence[str], notes: list[str]
) -> list[str]:
    """The integrators that can run the case: Radau locates no events (of the mechanism
    or of the case, `events` their names); Radau alone for such a case is an InputError."""
    if not events or "radau" not in integrators:
        return list(integrators)
    named = ", ".join(events)
    kept = [i for i in integrators if i != "radau"]
    if not kept:
        kind = "case" if events[0] in cf.case.events else "mechanism"
        file, line, col = cf.where(kind, f"events.{events[0]}")
        of_case = "" if Path(file) == Path(cf.path) else f" (case {cf.path})"
        raise InputError(
            [
                Diagnostic(
                    file,
                    line,
                    col,
                    f"events.{events[0]}",
                    f"loads accuracy --integrators radau: the events of this case{of_case} "
                    f"({named}) are located by generalized-alpha only: study it with "
                    "--integrators generalized-alpha",
                )
            ]
        )
    notes.append(
        f"radau left out: the case's events ({named}) are located by generalized-alpha "
        "only; its reference is its own tighter run (not independent)"
    )
    return kept


def _studied(cf: CaseFile, integrators: Sequence[str], notes: list[str]) -> list[str]:
    """The integrators that can study the case (see `_usable`); an InputError unless its
    analysis is dynamic."""
    events = [event.name for event in _dynamic_run(cf).events]  # mechanism's and case's
    return _usable(cf, events, integrators, notes)


def check_study(cf: CaseFile, integrators: Sequence[str] = INTEGRATORS) -> None:
    """Raise InputError for what a study of the case with `integrators` refuses, short of
    solving: what `loads run` refuses (loadcases.build.precheck), an analysis that is not
    dynamic, Radau alone on a case with events."""
    errors = [d for d in case_problems(cf) if d.severity == "error"]
    if errors:
        raise InputError(errors)
    _studied(cf, integrators, [])


def accuracy_study(
    cf: CaseFile,
    *,
    tolerances: Sequence[float] = DEFAULT_TOLERANCES,
    integrators: Sequence[str] = INTEGRATORS,
    target: float = DEFAULT_ACCURACY,
    repeats: int = 3,
    reference_tolerance: float | None = None,
    progress: Callable[[SettingResult], None] | None = None,
) -> AccuracyStudy:
    """Solve the case at every (integrator, tolerance) and measure each against the
    reference (see the module docstring); `progress` is called after each setting."""
    notes: list[str] = []
    methods = _studied(cf, integrators, notes)
    solve = _solver(cf)
    ref_tol = reference_tolerance or max(min(tolerances) * REFERENCE_FACTOR, MIN_TOLERANCE)
    solve(Setting(methods[0], max(tolerances)))  # warm-up: compiled kernels, caches
    ref_solutions = {m: solve(Setting(m, ref_tol)) for m in methods}
    for method, reference in ref_solutions.items():
        if not reference.ok:
            raise ReferenceFailure(
                f"the reference run ({Setting(method, ref_tol).describe()})"
                f" failed: {reference.message}"
            )
    references = {m: Setting(_other(m, methods), ref_tol) for m in methods}
    if len(methods) == 1 and not notes:
        notes.append(
            f"the reference is {methods[0]}'s own tighter run (one integrator "
            "studied): its errors are not measured by an independent method"
        )
    study = AccuracyStudy(cf.case.case, target, [], references, notes)
    if len(methods) > 1:
        a, b = (ref_solutions[m] for m in methods[:2])
        agreement = max((e.over_time for e in column_errors(a, b).values()), default=0.0)
        study.reference_agreement = agreement
        notes.append(
            f"the two references agree within {agreement:.2g} of peak: smaller "
            "errors are not resolved"
            + (
                " (the target is below that: tighten --reference-tolerance)"
                if agreement > target
                else ""
            )
        )
    for method in methods:
        for tolerance in sorted(tolerances, reverse=True):
            result = _measure(
                solve,
                Setting(method, tolerance),
                ref_solutions[references[method].integrator],
                repeats,
            )
            study.results.append(result)
            if progress:
                progress(result)
    return study


def _other(method: str, methods: Sequence[str]) -> str:
    others = [m for m in methods if m != method]
    return others[0] if others else method


def _measure(
    solve: Callable[[Setting], ml.Solution], setting: Setting, reference: ml.Solution, repeats: int
) -> SettingResult:
    runs = [solve(setting) for _ in range(max(repeats, 1))]
    solution = runs[0]
    cpu = statistics.median(r.stats.cpu_seconds for r in runs)
    stats = {k: v for k, v in solution.stats.as_dict().items() if k != "cpu_seconds"}
    return SettingResult(
        setting, solution.status, solution.message, cpu, stats, column_errors(solution, reference)
    )
