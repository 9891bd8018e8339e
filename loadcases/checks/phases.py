"""A case's `phases:`: analyses in sequence, each ending after the one before it."""

from __future__ import annotations

from loadcases.checks.analysis import analysis_problems
from loadcases.checks.common import unknown
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import CaseModel, MechanismModel
from loadcases.yamlfiles.source import Locator

__all__ = ["PHASE_ANALYSES", "check_phase_names", "check_phases", "phase_name"]

PHASE_ANALYSES = ("static", "quasi-static", "dynamic")


def phase_name(case: CaseModel, index: int) -> str:
    """The name of phase `index` (0-based): its own, else `phase1`, `phase2`, ..."""
    assert case.phases is not None
    return case.phases[index].name or f"phase{index + 1}"


def check_phases(case: CaseModel, at: Locator) -> list[Diagnostic]:
    """The problems of `phases:` that need no mechanism: the analyses and their order in
    time, names, `analysis` given beside them."""
    phases = case.phases or []
    found: list[Diagnostic] = []
    if isinstance(at.data, dict) and "analysis" in at.data:
        found.append(
            at.diagnostic(
                ("analysis",), "give `analysis` or `phases`, not both (each phase has its own)"
            )
        )
    end, seen = 0.0, set()
    for index, phase in enumerate(phases):
        where = ("phases", index, "analysis")
        a = phase.analysis
        if a.type not in PHASE_ANALYSES:
            found.append(
                at.diagnostic(
                    (*where, "type"),
                    f"a phase is a static, quasi-static or dynamic analysis, not {a.type}",
                )
            )
            continue
        found += analysis_problems(a, at, where)
        if a.type != "static" and a.end is not None and a.end > 0.0:
            if a.end <= end:
                found.append(
                    at.diagnostic(
                        (*where, "end"),
                        f"a phase ends after the one before it: end {a.end:g} s is not after "
                        f"{end:g} s (`end` is the time the phase ends at, not its length)",
                    )
                )
            end = max(end, a.end)
        if a.accuracy is not None and a.accuracy != "off":  # off asks for what a phase does
            found.append(
                at.diagnostic(
                    (*where, "accuracy"),
                    "the global error is not estimated for a phased case: set the "
                    "phase's tolerance instead",
                    severity="warning",
                    of_value=False,
                )
            )
        name = phase_name(case, index)
        if name in seen:
            found.append(at.diagnostic(("phases", index, "name"), f"phase '{name}' named twice"))
        seen.add(name)
    return found


def check_phase_names(case: CaseModel, mechanism: MechanismModel, at: Locator) -> list[Diagnostic]:
    """The joints a phase locks and the motions it drives exist."""
    found: list[Diagnostic] = []
    for index, phase in enumerate(case.phases or []):
        found += [
            unknown(at, ("phases", index, "locks", i), "joint", name, mechanism.joints)
            for i, name in enumerate(phase.locks)
            if name not in mechanism.joints
        ]
        found += [
            unknown(at, ("phases", index, "motions", i), "motion", name, case.motions)
            for i, name in enumerate(phase.motions or ())
            if name not in case.motions
        ]
    return found
