"""Build a `mechlib` model from a validated case: only the elements and effects it calls for.

Everything here is already validated (schema and checks); what the engine cannot simulate
yet is reported as a diagnostic at its key, never ignored. The families of the model are
built by the modules beside this one (bodies and joints, forces, contacts, motions,
requests, analysis, events); this one puts them together into a run.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import mechlib as ml
from loadcases.build.analysis import branch_check, build_analysis, initial_values
from loadcases.build.bodies import add_bodies, add_joints
from loadcases.build.contacts import add_contacts
from loadcases.build.context import Builder
from loadcases.build.events import build_events
from loadcases.build.flexible_bodies import flexible_notes
from loadcases.build.forces import add_forces
from loadcases.build.hydraulics import servo_problems
from loadcases.build.limits import add_limits
from loadcases.build.motions import add_motions
from loadcases.build.requests import (
    abscissa_request,
    build_requests,
    modal_requests,
    request_kinds,
)
from loadcases.build.sections import split_sections
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import CaseFile
from loadcases.schema.case import SectionRequest

__all__ = ["BuiltRun", "build_mechanism", "build_run"]


@dataclass
class BuiltRun:
    """A mechlib model ready for `mechlib.solve`, with the case's requests and settings."""

    mechanism: ml.Mechanism
    analysis: Any
    requests: list
    initial: list
    redundant: str
    column_units: dict[str, str] = field(default_factory=dict)
    warnings: list[Diagnostic] = field(default_factory=list)
    events: list = field(default_factory=list)
    request_kinds: dict[str, str] = field(default_factory=dict)  # requests.request_kinds
    branches: ml.BranchCheck = field(default_factory=ml.BranchCheck)
    # the model check and assembled start of the first solve, for the companion and tighter
    # runs (the same mechanism and initial values: mechlib.solvers.solve_memo)
    memo: ml.SolveMemo = field(default_factory=ml.SolveMemo)

    def solve(
        self,
        analysis: Any = None,
        *,
        requests: list | None = None,
        progress: Any = None,
        checks: bool = True,
    ) -> ml.Solution:
        """`mechlib.solve` of this run (a failure is a failed Solution, never raised; an
        ill-posed model raises ml.ModelError); `analysis` replaces the case's, `requests`
        its requests; `checks` False: no position checks after the run (mechlib.solve).
        Every solve after the first reuses its model check and assembled start (`memo`)."""
        return ml.solve(
            self.mechanism,
            self.analysis if analysis is None else analysis,
            requests=self.requests if requests is None else requests,
            initial=self.initial,
            redundant=self.redundant,
            throw=False,
            events=self.events,
            progress=progress,
            checks=checks,
            branches=self.branches,
            memo=self.memo,
        )


def _mechanism(b: Builder) -> ml.Mechanism:
    """The mechlib mechanism: bodies, points and frames, joints, force elements, contacts,
    limits and the case's motions, in this order (so are the diagnostics)."""
    gravity = b.mech.gravity if b.effects.get("gravity", True) else (0.0, 0.0, 0.0)
    m = ml.Mechanism(name=b.mech.name or "mechanism", gravity=gravity, plane=b.mech.plane)
    b.built = m
    add_bodies(b, m)
    add_joints(b, m)
    add_forces(b, m)
    add_contacts(b, m)
    add_limits(b, m)
    add_motions(b, m)
    return m


def build_mechanism(mf) -> ml.Mechanism:
    """The mechlib model of a mechanism file alone (no motions, all elements active)."""
    b = Builder(mf.model, dict(mf.model.parameters), lambda kind, key: mf.where(key))
    mechanism = _mechanism(b)
    if b.problems:
        raise InputError(b.problems)
    return mechanism


def _case_warning(cf: CaseFile, key: str, message: str, *, keyed: bool = True) -> Diagnostic:
    """A warning at `key` of the case file (`keyed=False`: placed there, named by no key)."""
    file, line, column = cf.where("case", key)
    return Diagnostic(file, line, column, key if keyed else "", message, "warning")


def _modal_notes(cf: CaseFile, dropped: list[str]) -> list[Diagnostic]:
    """The requests a modes analysis does not report, one warning each."""
    return [
        _case_warning(
            cf,
            f"requests.{name}",
            "no modal meaning (a modes analysis "
            "reports point displacements and joint coordinates of each "
            "mode): not reported",
        )
        for name in dropped
    ]


def _events_note(cf: CaseFile, events: list, analysis) -> Diagnostic:
    """The events of a mechanism wait for an analysis in time: not active in this one."""
    return _case_warning(
        cf,
        "analysis",
        f"events ({', '.join(e.name for e in events)})"
        f" need an analysis in time: not active in this "
        f"{analysis.name} analysis",
        keyed=False,
    )


def build_run(cf: CaseFile, *, abscissa: bool = False) -> BuiltRun:
    """The mechlib model, analysis, requests and initial values of a case; InputError lists
    everything the engine cannot build. With `abscissa`, the case's `abscissa:` expression
    (if any) becomes one more request, column `abscissa.value`."""
    b = Builder(cf.mechanism, cf.parameters, cf.where, cf.case)
    cut = [
        r.section
        for r in cf.case.requests.values()
        if isinstance(r, SectionRequest) and r.section in cf.mechanism.sections
    ]
    if cut:  # the bodies cut only for a case that asks (loadcases.build.sections)
        b.mech = split_sections(b.mech, cut, lambda key, text: b.error("mechanism", key, text))
    mechanism = _mechanism(b)
    analysis = build_analysis(b)
    requests, units = build_requests(b, cf.expression_units)
    if abscissa:
        abscissa_request(b, requests, units)
    initial = initial_values(b, mechanism)
    b.problems += servo_problems(cf, mechanism, analysis)
    if b.problems:
        raise InputError(b.problems)
    events = build_events(b)
    if b.problems:
        raise InputError(b.problems)
    notes = list(cf.warnings)  # validation warnings travel along
    if isinstance(analysis, ml.Modes):
        requests, units, dropped = modal_requests(requests, units)
        notes += _modal_notes(cf, dropped)
    if events and isinstance(analysis, (ml.Static, ml.Modes)):
        # a mechanism serves static and dynamic cases alike: its events wait for one in time
        notes.append(_events_note(cf, events, analysis))
        events = []
    notes += flexible_notes(cf, mechanism)
    return BuiltRun(
        mechanism,
        analysis,
        requests,
        initial,
        cf.case.analysis.redundant,
        units,
        notes,
        events,
        request_kinds(b),
        branch_check(b),
    )
