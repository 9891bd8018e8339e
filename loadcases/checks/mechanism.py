"""Semantic checks of a validated mechanism: names, references and physical sense."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from loadcases.checks.common import GROUND, Expected, Names, check_expressions, unknown
from loadcases.checks.dimensions import table_dimension_problems
from loadcases.expressions.dimensions import DimensionScope
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import Body, FlexibleBody, MechanismModel
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = ["check_mechanism", "mechanism_names", "node_bodies"]

_SECTIONS = (
    "bodies",
    "points",
    "frames",
    "joints",
    "forces",
    "contacts",
    "sections",
    "limits",
    "tables",
    "events",
)
_RESERVED_PARAMETERS = ("t", "pi")  # bare names the expression language defines itself
_TINY = 1.0e-12  # |vector| below this is a zero vector
_PARALLEL = 1.0e-6  # |sin(angle)| below this: parallel axes
_INERTIA_TOL = 1.0e-9  # relative tolerance of positivity and triangle inequality


def mechanism_names(model: MechanismModel) -> Names:
    """Known names of a mechanism by section (bodies include ground)."""
    return Names(
        bodies={GROUND, *model.bodies},
        points=model.points,
        frames=model.frames,
        joints=model.joints,
        forces=model.forces,
        contacts=model.contacts,
        sections=model.sections,
        limits=model.limits,
        tables=model.tables,
        events=model.events,
    )


def node_bodies(model: MechanismModel) -> set[str]:
    """`BODY.POINT` for each interface point of a flexible body: the rigid body of that
    node, which carries points given anywhere (an offset attachment)."""
    return {
        f"{name}.{point}"
        for name, body in model.bodies.items()
        if isinstance(body, FlexibleBody)
        for point in body.flexible.points()
    }


def _unique(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """Names unique across sections; `ground` is not defined by the user."""
    found: list[Diagnostic] = []
    first: dict[str, str] = {}
    for section in _SECTIONS:
        for name in getattr(model, section):
            if name == GROUND:
                found.append(
                    at.diagnostic(
                        (section, name),
                        "'ground' is the fixed body and needs no definition",
                        hint="use another name",
                    )
                )
            elif name in first:
                found.append(
                    at.diagnostic(
                        (section, name),
                        f"name '{name}' is already used in {first[name]}",
                        hint="names of bodies, points, "
                        "joints, forces, contacts, limits, tables and events must "
                        "be unique",
                    )
                )
            else:
                first[name] = section
    for name in model.parameters:
        if name in _RESERVED_PARAMETERS:
            found.append(
                at.diagnostic(
                    ("parameters", name),
                    f"'{name}' is a reserved name of expressions",
                    hint="rename the parameter",
                )
            )
    return found


def _refs(
    at: Locator, items: Iterable[tuple[KeyPath, str]], what: str, known: set[str]
) -> list[Diagnostic]:
    return [unknown(at, path, what, name, known) for path, name in items if name not in known]


def _body_refs(model: MechanismModel) -> list[tuple[KeyPath, str]]:
    refs: list[tuple[KeyPath, str]] = []
    for section in ("points", "frames"):
        refs += [((section, n, "body"), item.body) for n, item in getattr(model, section).items()]
    for section in ("joints", "forces", "contacts"):
        for name, item in getattr(model, section).items():
            for index, body in enumerate(getattr(item, "bodies", None) or ()):
                refs.append(((section, name, "bodies", index), body))
            if getattr(item, "body", None):
                refs.append(((section, name, "body"), item.body))
    return refs


def _references(model: MechanismModel, at: Locator, names: Names) -> list[Diagnostic]:
    """Every name a mechanism refers to must exist."""
    points: list[tuple[KeyPath, str]] = []
    joints: list[tuple[KeyPath, str]] = []
    tables: list[tuple[KeyPath, str]] = []
    for name, force in model.forces.items():
        points += [
            (("forces", name, "points", i), p) for i, p in enumerate(getattr(force, "points", ()))
        ]
        if point := getattr(force, "point", None):
            points.append((("forces", name, "point"), point))
        if joint_name := getattr(force, "joint", None):
            joints.append((("forces", name, "joint"), joint_name))
        if law := getattr(force, "law", None):
            tables.append((("forces", name, "law"), law))
    joints += [(("limits", name, "joint"), limit.joint) for name, limit in model.limits.items()]
    for name, joint in model.joints.items():
        if joint.type in ("coupler", "gear"):
            joints += [(("joints", name, "joints", i), j) for i, j in enumerate(joint.joints)]
    carried = names.get("bodies") | node_bodies(model)
    frames = carried | names.get("frames")
    found = _refs(at, _body_refs(model), "body", carried)
    found += _refs(at, points, "point", names.get("points"))
    found += _refs(at, joints, "joint", names.get("joints"))
    found += _refs(at, tables, "table", names.get("tables"))
    found += _refs(
        at,
        [
            (("forces", n, "frame"), frame)
            for n, f in model.forces.items()
            if (frame := getattr(f, "frame", None))
        ],
        "frame",
        frames,
    )
    return found


def _events(
    model: MechanismModel, at: Locator, names: Names, motions: Iterable[str] | None
) -> list[Diagnostic]:
    """Event targets: elements/contacts (or case motions) to switch, joints to release/lock."""
    switchable = (
        names.get("forces") | names.get("contacts") | names.get("limits") | set(motions or ())
    )
    found = []
    for name, event in model.events.items():
        for index, action in enumerate(event.then):
            path = ("events", name, "then", index)
            if action.target is None:
                continue  # `stop` has no target
            if action.action in ("release", "lock") and action.target not in names.get("joints"):
                found.append(unknown(at, path, "joint", action.target, names.get("joints")))
            elif action.action in ("activate", "deactivate") and action.target not in switchable:
                found.append(
                    unknown(
                        at,
                        path,
                        "element",
                        action.target,
                        switchable,
                        severity="error" if motions is not None else "warning",
                    )
                )
    return found


def _vector_checks(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """Zero axes and normals, parallel universal axes, joints joining a body to itself."""
    found = []
    for name, joint in model.joints.items():
        for key in ("axis", "normal"):
            problem = _direction_problem(key, getattr(joint, key, None))
            if problem:
                found.append(at.diagnostic(("joints", name, key), problem))
        axes = getattr(joint, "axes", None)
        if axes is not None:
            found += _axes_checks(at, ("joints", name, "axes"), joint.type, *axes)
        curve = getattr(joint, "curve", None)
        if curve is not None:
            found += _curve_checks(at, ("joints", name, "curve"), curve)
        bodies = getattr(joint, "bodies", None)
        if bodies is not None and bodies[0] == bodies[1]:
            found.append(
                at.diagnostic(
                    ("joints", name, "bodies"), f"joint joins body '{bodies[0]}' to itself"
                )
            )
    for name, frame in model.frames.items():
        found += _axes_checks(at, ("frames", name), "frame", frame.x, frame.y)
    for name, contact in model.contacts.items():
        problem = _direction_problem("normal", getattr(contact.geometry, "normal", None))
        if problem:
            found.append(at.diagnostic(("contacts", name, "geometry", "normal"), problem))
        if contact.bodies[0] == contact.bodies[1]:
            found.append(
                at.diagnostic(
                    ("contacts", name, "bodies"),
                    f"contact joins body '{contact.bodies[0]}' to itself",
                )
            )
    return found


def _direction_problem(key: str, vector: tuple[float, ...] | None) -> str | None:
    """Why a direction cannot be normalised (zero, or so long that its length overflows)."""
    if vector is None:
        return None
    with np.errstate(over="ignore"):
        length = float(np.linalg.norm(vector))
    if not np.isfinite(length):
        return f"{key} is too long to normalise (its length overflows); give a unit vector"
    if length < _TINY:
        return f"{key} is a zero vector"
    return None


def _curve_checks(at: Locator, path: KeyPath, curve) -> list[Diagnostic]:
    """A curve's points follow one another at non-zero distances."""
    steps = np.linalg.norm(np.diff(np.asarray(curve, dtype=float), axis=0), axis=1)
    return [
        at.diagnostic(
            (*path, int(i) + 1),
            f"point {i + 1} repeats point {i}: the curve needs distinct consecutive points",
        )
        for i in np.flatnonzero(steps < _TINY)
    ]


def _axes_checks(
    at: Locator, path: KeyPath, kind: str, a1: tuple[float, ...], a2: tuple[float, ...]
) -> list[Diagnostic]:
    problem = _direction_problem("axis", a1) or _direction_problem("axis", a2)
    if problem:
        return [at.diagnostic(path, problem.replace("axis is", "an axis is"))]
    n1, n2 = np.linalg.norm(a1), np.linalg.norm(a2)
    if np.linalg.norm(np.cross(a1, a2)) / (n1 * n2) < _PARALLEL:
        return [
            at.diagnostic(
                path,
                f"the axes of the {kind} are parallel",
                hint="give two axes at an angle (usually perpendicular)",
            )
        ]
    return []


def _inertia(at: Locator, name: str, inertia: tuple[float, ...]) -> list[Diagnostic]:
    """Positive definite, and each principal moment <= the sum of the other two."""
    if len(inertia) == 3:
        tensor = np.diag(inertia)
    else:
        ixx, iyy, izz, ixy, ixz, iyz = inertia
        tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    moments = np.linalg.eigvalsh(tensor)
    scale = max(float(np.max(np.abs(moments))), _TINY)
    path = ("bodies", name, "inertia")
    if moments[0] <= _INERTIA_TOL * scale:
        return [
            at.diagnostic(
                path,
                "inertia is not positive definite (principal moments "
                + ", ".join(f"{m:.6g}" for m in moments)
                + ")",
            )
        ]
    if moments[2] > moments[0] + moments[1] + _INERTIA_TOL * scale:
        return [
            at.diagnostic(
                path,
                "principal moments break the triangle inequality "
                f"({moments[2]:.6g} > {moments[0]:.6g} + {moments[1]:.6g})",
                hint="each principal moment must be <= the sum of the others",
            )
        ]
    return []


def _bodies(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    found = []
    for name, body in model.bodies.items():
        if not isinstance(body, Body):
            continue  # a flexible body: mass properties from its FE model
        if body.mass <= 0.0:
            found.append(at.diagnostic(("bodies", name, "mass"), "mass must be positive"))
        found += _inertia(at, name, body.inertia)
    return found


def check_mechanism(
    model: MechanismModel,
    at: Locator,
    motions: Iterable[str] | None = None,
    parameters: Iterable[str] = (),
    scope: DimensionScope | None = None,
) -> list[Diagnostic]:
    """All semantic problems of a mechanism; `motions` are the case's motion names (events
    may switch them), None when the mechanism is checked on its own; `parameters` are extra
    parameter names a case defines; `scope` the dimensions of names (expressions are
    dimension-checked when given)."""
    from loadcases.checks.elements import check_elements
    from loadcases.checks.limits import check_limits
    from loadcases.checks.planar import check_plane
    from loadcases.checks.plausible import density_warnings

    names = mechanism_names(model)
    found = _unique(model, at) + _references(model, at, names) + _events(model, at, names, motions)
    found += _vector_checks(model, at) + _bodies(model, at) + check_elements(model, at)
    found += check_plane(model, at) + check_limits(model, at)
    found += density_warnings(model, at, scope)
    found += table_dimension_problems(
        at, at.data.get("tables") if isinstance(at.data, dict) else None
    )
    expressions: list[tuple[KeyPath, str]] = [
        (("events", n, "when"), e.when) for n, e in model.events.items() if e.when is not None
    ]
    expected: dict[KeyPath, Expected] = {}
    for name, force in model.forces.items():
        for i, v in enumerate(getattr(force, "value", ())):
            expressions.append((("forces", name, "value", i), v))
            if force.type in ("force", "torque"):
                expected[("forces", name, "value", i)] = (force.type, "error")
        command = getattr(force, "command", None)  # a servo actuator's stroke demand
        if command is not None:
            expressions.append((("forces", name, "command"), command))
            expected[("forces", name, "command")] = ("length", "error")
    known = {*model.parameters, *parameters}
    return found + check_expressions(at, expressions, names, known, scope, expected)
