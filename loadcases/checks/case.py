"""Semantic checks of a validated case against its mechanism; joint coordinates to SI."""

from __future__ import annotations

import math
from collections.abc import Mapping

from loadcases.checks.analysis import analysis_problems
from loadcases.checks.common import GROUND, Expected, Names, check_expressions, unknown
from loadcases.checks.mechanism import mechanism_names
from loadcases.checks.paths import check_name
from loadcases.checks.phases import check_phase_names, check_phases
from loadcases.expressions.dimensions import DimensionScope
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.units import UnitError, to_si
from loadcases.schema import (
    COORDINATE_DIMENSION,
    KNOWN_EFFECTS,
    CaseModel,
    FlexibleBody,
    MechanismModel,
)
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = ["check_case", "check_case_alone", "resolve_initial"]

_RATE = {"angle": "angular_velocity", "length": "velocity"}
_TIME_ANALYSES = ("kinematic", "quasi-static", "dynamic")


def resolve_initial(
    case: CaseModel, mechanism: MechanismModel, at: Locator, units: Mapping[str, str]
) -> tuple[CaseModel, list[Diagnostic]]:
    """The case with `initial` joint `value`/`rate` in SI (rad, rad/s or m, m/s by joint type).

    Entries naming no single-coordinate joint are left as written (check_case reports them).
    """
    found: list[Diagnostic] = []
    initial = dict(case.initial)
    for name, entry in case.initial.items():
        joint = mechanism.joints.get(name)
        dimension = COORDINATE_DIMENSION.get(joint.type) if joint is not None else None
        if joint is None or dimension is None:
            continue
        update = {}
        for key, dim in (("value", dimension), ("guess", dimension), ("rate", _RATE[dimension])):
            raw = getattr(entry, key)
            if raw is None:
                continue
            try:
                update[key] = to_si(raw, dim, units)
            except UnitError as error:
                found.append(
                    at.diagnostic(("initial", name, key), f"{error} for a {joint.type} joint")
                )
        initial[name] = entry.model_copy(update=update)
    return case.model_copy(update={"initial": initial}), found


def _motions(
    case: CaseModel, mechanism: MechanismModel, at: Locator, names: Names
) -> list[Diagnostic]:
    found: list[Diagnostic] = []
    driven: dict[str, str] = {}
    for name, motion in case.motions.items():
        path = ("motions", name, "joint")
        joint = mechanism.joints.get(motion.joint)
        if joint is None:
            found.append(unknown(at, path, "joint", motion.joint, names.get("joints")))
        elif joint.type not in COORDINATE_DIMENSION:
            found.append(
                at.diagnostic(
                    path,
                    f"joint '{motion.joint}' is {joint.type}: a "
                    "motion needs a revolute, screw, cylindrical or "
                    "prismatic joint",
                )
            )
        elif motion.joint in driven:
            found.append(
                at.diagnostic(
                    path,
                    f"joint '{motion.joint}' is already driven by motion '{driven[motion.joint]}'",
                )
            )
        else:
            driven[motion.joint] = name
    return found


_JOINT_KEYS = {"value", "guess", "rate"}
_BODY_KEYS = {"omega", "velocity"}
_MODAL_KEYS = {"modes", "rates", "deformed"}


def _node_body(mechanism: MechanismModel, name: str) -> bool:
    """`BODY.POINT`: the node body of interface point POINT of flexible body BODY."""
    body, _, point = name.partition(".")
    entry = mechanism.bodies.get(body)
    return isinstance(entry, FlexibleBody) and point in entry.flexible.interface


def _initial_entry(
    mechanism: MechanismModel, name: str, given: set[str], at: Locator
) -> list[Diagnostic]:
    """The keys an entry gives against what its name is: a joint, a rigid body, a flexible
    body or a flexible body's node body."""
    joint, body = mechanism.joints.get(name), mechanism.bodies.get(name)
    flexible = isinstance(body, FlexibleBody)
    if joint is not None:
        wrong, allowed = given - _JOINT_KEYS, "'value', 'guess' and/or 'rate'"
        what = "a joint"
    elif flexible:
        wrong, allowed = given - _BODY_KEYS - _MODAL_KEYS, "'omega', 'velocity', 'modes'"
        allowed, what = allowed + ", 'rates' and/or 'deformed'", "a flexible body"
    elif body is not None:
        wrong, allowed = given - _BODY_KEYS, "'omega' and/or 'velocity'"
        what = "a rigid body" if given & _MODAL_KEYS else "a body"
    else:  # the node body of an interface point
        wrong, allowed = given - _BODY_KEYS, "'omega' and/or 'velocity'"
        what = "an interface point's node body"
    if wrong:
        key = ("initial", name, sorted(wrong)[0]) if wrong & _MODAL_KEYS else ("initial", name)
        return [at.diagnostic(key, f"'{name}' is {what}: give {allowed}")]
    if {"modes", "deformed"} <= given:
        return [
            at.diagnostic(
                ("initial", name, "deformed"),
                "give either 'modes' or 'deformed: static' (the modal coordinates it finds)",
            )
        ]
    if joint is not None and joint.type not in COORDINATE_DIMENSION:
        return [
            at.diagnostic(
                ("initial", name),
                f"joint '{name}' is {joint.type}: it has no single coordinate to set",
            )
        ]
    return []


def _modal_values(entry, name: str, at: Locator) -> list[Diagnostic]:
    """Modal coordinates and rates: finite numbers."""
    found = []
    for key in ("modes", "rates"):
        values = getattr(entry, key)
        if values is not None and not all(math.isfinite(v) for v in values):
            found.append(at.diagnostic(("initial", name, key), "must be finite numbers"))
    return found


def _initial(
    case: CaseModel, mechanism: MechanismModel, at: Locator, names: Names
) -> list[Diagnostic]:
    found = []
    for name, entry in case.initial.items():
        keys = _JOINT_KEYS | _BODY_KEYS | _MODAL_KEYS
        given = {k for k in keys if getattr(entry, k) is not None}
        known = name in mechanism.joints or name in mechanism.bodies
        if not known and not _node_body(mechanism, name):
            found.append(
                unknown(
                    at,
                    ("initial", name),
                    "joint or body",
                    name,
                    names.get("joints") | (names.get("bodies") - {GROUND}),
                )
            )
            continue
        found += _initial_entry(mechanism, name, given, at) + _modal_values(entry, name, at)
        if name in mechanism.joints and entry.guess is not None:
            found += _idle_guess(case, name, "value" in given, at)
    return found


def _idle_guess(case: CaseModel, joint: str, valued: bool, at: Locator) -> list[Diagnostic]:
    """A guess the joint's own `value` or a motion of it already fixes does nothing."""
    driven = [m for m, motion in case.motions.items() if motion.joint == joint]
    if not valued and not driven:
        return []
    by = "its 'value'" if valued else f"motion '{driven[0]}'"
    return [
        at.diagnostic(
            ("initial", joint, "guess"),
            f"the guess of joint '{joint}' does nothing: {by} sets its coordinate",
            hint="give a guess for a joint the assembly solves for (a knee, a follower)",
            severity="warning",
        )
    ]


def _loads(case: CaseModel, at: Locator, names: Names) -> list[Diagnostic]:
    elements = names.get("forces") | names.get("contacts")
    limits = names.get("limits")
    found = [
        at.diagnostic(
            ("loads", i),
            f"'{name}' is a limit: limits are not loads, they act unless "
            "`effects: {contact: false}` or an `active: false` keeps them off",
            hint=f"remove '{name}' from loads",
        )
        if name in limits
        else unknown(at, ("loads", i), "force element", name, elements)
        for i, name in enumerate(case.loads or ())
        if name not in elements
    ]
    return found


def _parameters(case: CaseModel, mechanism: MechanismModel, at: Locator) -> list[Diagnostic]:
    """A case parameter close to, but not, a mechanism parameter is probably a typo."""
    found = []
    for name in case.parameters:
        hint = (
            did_you_mean(name, mechanism.parameters) if name not in mechanism.parameters else None
        )
        if hint:
            found.append(
                at.diagnostic(
                    ("parameters", name),
                    f"'{name}' is not a parameter of the mechanism (a new one is defined)",
                    hint=hint,
                    severity="warning",
                )
            )
    return found


def check_case_alone(case: CaseModel, at: Locator) -> list[Diagnostic]:
    """The problems of a case that do not need its mechanism (analysis, effects)."""
    return (
        (check_phases(case, at) if case.phases else analysis_problems(case.analysis, at))
        + check_name(at, "case", case.case)
        + [
            unknown(at, ("effects", name), "effect", name, KNOWN_EFFECTS, severity="warning")
            for name in case.effects
            if name not in KNOWN_EFFECTS
        ]
    )


def check_case(
    case: CaseModel,
    mechanism: MechanismModel,
    at: Locator,
    scope: DimensionScope | None = None,
) -> list[Diagnostic]:
    """All semantic problems of a case against its (valid) mechanism; `scope` the dimensions
    of names (expressions are dimension-checked when given)."""
    from loadcases.checks.planar import check_plane_initial
    from loadcases.checks.requests import check_requests, unit_problems

    names = mechanism_names(mechanism)
    parameters = {*mechanism.parameters, *case.parameters}
    found = _motions(case, mechanism, at, names) + _initial(case, mechanism, at, names)
    found += check_case_alone(case, at) + _loads(case, at, names)
    found += check_phase_names(case, mechanism, at)
    found += check_plane_initial(case, mechanism, at)
    found += _parameters(case, mechanism, at) + check_requests(case, mechanism, at, names)
    expressions: list[tuple[KeyPath, str]] = [
        (("motions", n, "value"), m.value) for n, m in case.motions.items()
    ]
    expressions += [
        (("requests", n, "expression"), r.expression)
        for n, r in case.requests.items()
        if hasattr(r, "expression")
    ]
    if case.abscissa is not None:
        expressions.append((("abscissa",), case.abscissa))
    expected: dict[KeyPath, Expected] = {}
    for name, motion in case.motions.items():
        joint = mechanism.joints.get(motion.joint)
        if joint is not None and joint.type in ("revolute", "prismatic"):
            # a warning: a motion written in plain SI numbers (`value: t`) is common and
            # runs as written
            expected[("motions", name, "value")] = (COORDINATE_DIMENSION[joint.type], "warning")
    found += check_expressions(at, expressions, names, parameters, scope, expected)
    return found + (unit_problems(case, at, scope) if scope is not None else [])
