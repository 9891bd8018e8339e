"""The settings of one analysis (a case's `analysis`, or a phase's)."""

from __future__ import annotations

from loadcases.foundation.accuracy_target import target_problem
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.limits import MIN_TOLERANCE, rows_problem
from loadcases.schema.case import AccuracyTarget
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = ["TIME_ANALYSES", "analysis_problems"]

TIME_ANALYSES = ("kinematic", "quasi-static", "dynamic")
_TIME_ANALYSES = TIME_ANALYSES


def analysis_problems(analysis, at: Locator, where: KeyPath = ("analysis",)) -> list[Diagnostic]:
    """The problems of an analysis's settings (at `where`: `analysis` or a phase's)."""
    found: list[Diagnostic] = []
    kind = analysis.type
    if kind in _TIME_ANALYSES:
        for key in ("end", "step"):
            value = getattr(analysis, key)
            if value is None:
                found.append(at.diagnostic((*where, key), f"a {kind} analysis needs '{key}' (s)"))
            elif value <= 0.0:
                found.append(at.diagnostic((*where, key), "must be positive"))
        if analysis.max_steps is not None and analysis.max_steps <= 0:
            found.append(
                at.diagnostic((*where, "max_steps"), "must be a positive whole number of steps")
            )
        if analysis.end and analysis.step and analysis.step > analysis.end:
            found.append(at.diagnostic((*where, "step"), "step is longer than end"))
        elif (
            analysis.end is not None
            and analysis.end > 0.0
            and analysis.step is not None
            and analysis.step > 0.0
            and (problem := rows_problem(analysis.end, analysis.step)) is not None
        ):
            found.append(at.diagnostic((*where, "step"), problem))
    else:
        found += _does_nothing(analysis, at, where, ("end", "step", "max_steps"))
    found += [
        at.diagnostic((*where, key), "must be positive")
        for key in ("tolerance", "max_step")
        if isinstance(getattr(analysis, key), int | float) and getattr(analysis, key) <= 0.0
    ]
    tolerance = analysis.tolerance
    if isinstance(tolerance, int | float) and 0.0 < tolerance < MIN_TOLERANCE:
        found.append(
            at.diagnostic(
                (*where, "tolerance"),
                f"must be at least {MIN_TOLERANCE:g} (got {tolerance:g}): below, round-off "
                "of the state decides, not the tolerance",
            )
        )
    if kind != "dynamic":
        found += _does_nothing(
            analysis,
            at,
            where,
            ("tolerance", "integrator", "max_step", "accuracy", "rho_inf", "output"),
        )
    if analysis.rho_inf is not None and not 0.0 <= analysis.rho_inf <= 1.0:
        found.append(at.diagnostic((*where, "rho_inf"), "must be between 0 and 1"))
    return found + _accuracy_target(analysis, at, where)


def _does_nothing(analysis, at: Locator, where: KeyPath, keys: tuple[str, ...]) -> list[Diagnostic]:
    """A warning at each of `keys` given in an analysis whose type does not use it."""
    return [
        at.diagnostic(
            (*where, key),
            f"does nothing for a {analysis.type} analysis",
            severity="warning",
            of_value=False,
        )
        for key in keys
        if getattr(analysis, key) is not None
    ]


def _accuracy_target(analysis, at: Locator, where: KeyPath) -> list[Diagnostic]:
    """`accuracy: TARGET` or `{target, budget: {cpu, steps, refinements}}`: the target
    within its bounds (those of `loads accuracy --target`), a positive CPU time and step
    count, refinements not negative."""
    accuracy = analysis.accuracy
    path = (*where, "accuracy")
    if isinstance(accuracy, int | float):
        problem = target_problem(accuracy)
        return [] if problem is None else [at.diagnostic(path, problem)]
    if not isinstance(accuracy, AccuracyTarget):
        return []
    found = []
    if (problem := target_problem(accuracy.target)) is not None:
        found.append(at.diagnostic((*path, "target"), problem))
    budget = accuracy.budget
    if budget is not None:
        found += [
            at.diagnostic((*path, "budget", key), "must be positive")
            for key in ("cpu", "steps")
            if getattr(budget, key) is not None and getattr(budget, key) <= 0
        ]
        if budget.refinements is not None and budget.refinements < 0:
            found.append(at.diagnostic((*path, "budget", "refinements"), "must be 0 or more"))
    return found
