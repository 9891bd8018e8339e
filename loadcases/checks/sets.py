"""Semantic checks of a validated set: sweeps, zips, allowables, report; parameter names."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from loadcases.checks.common import unknown
from loadcases.checks.paths import check_name, check_report_paths
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.limits import pattern_problem, runs_problem
from loadcases.foundation.units import UnitError, describe_dimension, quantity_dimension
from loadcases.schema import SetModel
from loadcases.schema.setfile import matches
from loadcases.yamlfiles.source import Locator

__all__ = ["check_set", "check_set_cases"]


def _pattern_diagnostics(at: Locator, patterns: Sequence[str]) -> list[Diagnostic]:
    """pattern_problem of each `cases:` entry, at its position."""
    return [
        at.diagnostic(("cases", index), problem)
        for index, pattern in enumerate(patterns)
        if (problem := pattern_problem(pattern)) is not None
    ]


def check_set(model: SetModel, at: Locator) -> list[Diagnostic]:
    """Problems of a set file on its own."""
    found = [
        at.diagnostic(("sweep", n), "expected at least 1 value")
        for n, values in model.sweep.items()
        if not values
    ]
    found += [
        at.diagnostic(("zip", n), "a parameter cannot be in both sweep and zip")
        for n in model.zip
        if n in model.sweep
    ]
    lengths = {len(v) for v in model.zip.values()}
    if len(lengths) > 1:
        found.append(
            at.diagnostic(
                ("zip",),
                "zip lists must have equal lengths, got "
                + ", ".join(str(len(v)) for v in model.zip.values()),
            )
        )
    for name, limits in model.allowables.items():
        if limits.max is not None and limits.min is not None and limits.max < limits.min:
            found.append(at.diagnostic(("allowables", name), "max is below min"))
    found += [
        at.diagnostic(("factors", n), "factor must be positive")
        for n, f in model.factors.items()
        if f <= 0.0
    ]
    if model.report is not None and not model.report.output.lower().endswith(".xlsx"):
        found.append(at.diagnostic(("report", "output"), "expected an .xlsx file name"))
    if model.report is not None:
        found += check_report_paths(at, model.report.output, model.report.template)
    problem = runs_problem(list(model.sweep.values()), min(lengths, default=0))
    if problem is not None:
        found.append(at.diagnostic(("sweep",) if model.sweep else ("zip",), problem))
    return found + check_name(at, "set", model.set) + _pattern_diagnostics(at, model.cases)


ULTIMATE = "ultimate"  # the key of the ultimate factor in `factors:`
ABSCISSA = "abscissa"  # the request name of a case's abscissa in the results of a set


def check_set_cases(model: SetModel, at: Locator, cases: Sequence[Any]) -> list[Diagnostic]:
    """Sweep, zip and parameter names must be parameters of at least one of the `cases`
    (loaded CaseFile objects with `.parameters`); factor and allowable keys, charted
    (`report.charts`) and compared columns must name a request (`REQUEST` or
    `REQUEST.COMPONENT`) of one of them; case names are unique."""
    if not cases:
        return []
    known = {name for case in cases for name in case.parameters}
    found = []
    for section in ("parameters", "sweep", "zip"):
        found += [
            unknown(at, (section, name), "parameter", name, known)
            for name in getattr(model, section)
            if name not in known
        ]
    found += _value_dimensions(at, cases)
    requests = {name for case in cases for name in case.case.requests} | {ABSCISSA}
    for section in ("factors", "allowables"):
        found += [
            unknown(at, (section, key), "request", key.split(".")[0], requests)
            for key in getattr(model, section)
            if key != ULTIMATE and key.split(".")[0] not in requests
        ]
    charted = model.report.charts if model.report is not None else []
    found += [
        unknown(at, ("report", "charts", i), "request", key.split(".")[0], requests)
        for i, key in enumerate(charted)
        if key.split(".")[0] not in requests
    ]
    for name, comparison in model.comparisons.items():
        found += [
            unknown(at, ("comparisons", name, "columns", i), "request", request, requests)
            for i, key in enumerate(comparison.columns)
            for request in (side.strip(" -").split(".")[0] for side in key.split("="))
            if request not in requests
        ]
    found += _unfactored_levels(model, at, cases)
    names = {case.case.case for case in cases}
    wanted = model.mass_properties
    if wanted is not None and wanted.case not in names:
        found.append(unknown(at, ("mass_properties", "case"), "case", wanted.case, names))
    return found + _duplicate_names(at, cases) + _unmatched_case_factors(model, at, cases)


def _unfactored_levels(model: SetModel, at: Locator, cases: Sequence[Any]) -> list[Diagnostic]:
    """An ultimate-level case in a set without an ultimate factor: its limit loads cannot be
    told from its ultimate ones (both are shown as computed)."""
    if ULTIMATE in model.factors:
        return []
    return [
        at.diagnostic(
            ("cases",),
            f"case '{case.case.case}' gives its loads at ultimate level but the set has no "
            "ultimate factor: its limit loads are shown equal to its ultimate loads",
            hint="add factors: {ultimate: 1.5} (or the factor that applies)",
            severity="warning",
        )
        for case in cases
        if case.case.level == ULTIMATE
    ]


def _value_dimensions(at: Locator, cases: Sequence[Any]) -> list[Diagnostic]:
    """A value of the set's `parameters`, `sweep` or `zip` written with a unit must have the
    dimension of the parameter where a case defines it with a unit (the rule of `--set`)."""
    defined: dict[str, tuple[str, dict]] = {}
    for case in cases:
        for name, dims in getattr(case, "parameter_dims", {}).items():
            if dims is not None:
                defined.setdefault(name, (case.case.case, dict(dims)))
    found = []
    data = at.data if isinstance(at.data, dict) else {}
    for section in ("parameters", "sweep", "zip"):
        raw = data.get(section)
        for name, values in raw.items() if isinstance(raw, dict) else ():
            if name not in defined:
                continue
            items = values if isinstance(values, list) else [values]
            key = (section, name) if not isinstance(values, list) else None
            for index, value in enumerate(items):
                problem = _dimension_problem(value, *defined[name], name)
                if problem is not None:
                    found.append(at.diagnostic(key or (section, name, index), problem))
    return found


def _dimension_problem(value: Any, case: str, want: dict, name: str) -> str | None:
    """Why `value` as written cannot be parameter `name` of dimension `want`, or None."""
    if not isinstance(value, str):
        return None
    try:
        dims = quantity_dimension(value)
    except UnitError:
        return None  # an unreadable value is reported by the schema
    if dims is None or dict(dims) == want:
        return None
    return (
        f"expected {describe_dimension(want)} (parameter '{name}' of case '{case}'), "
        f"got '{value}' ({describe_dimension(dict(dims))})"
    )


def _unmatched_case_factors(model: SetModel, at: Locator, cases: Sequence[Any]) -> list[Diagnostic]:
    """A `case_factors` pattern must match a case name (one with `[` may name runs of a
    sweep: `door[clearance=0.0001]`, matched against the case name up to its `[`)."""
    names = [case.case.case for case in cases]
    return [
        unknown(at, ("case_factors", pattern), "case", pattern, set(names))
        for pattern in model.case_factors
        if not any(matches(name, pattern.split("[")[0] + "*" * ("[" in pattern)) for name in names)
    ]


def _duplicate_names(at: Locator, cases: Sequence[Any]) -> list[Diagnostic]:
    """Two case files with one `case:` name would write the same result files."""
    first: dict[str, str] = {}
    found = []
    for case in cases:
        name = case.case.case
        if name in first and first[name] != case.path:
            found.append(
                at.diagnostic(
                    ("cases",),
                    f"case name '{name}' is used by both {first[name]} and {case.path}",
                    hint="give each case file its own `case:` name",
                )
            )
        first.setdefault(name, case.path)
    return found
