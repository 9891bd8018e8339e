"""Build a `mechlib` model from a validated case: only the elements and effects it calls for.

Everything here is already validated (schema and checks); what the engine cannot simulate
yet is reported as a diagnostic at its key, never ignored.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import mechlib as ml
from loadcases.build.contacts import CONTACT_COMPONENTS, CONTACT_MAKERS, CONTACT_UNITS
from loadcases.build.elements import ELEMENT_EFFECTS, ELEMENT_MAKERS
from loadcases.build.events import build_events
from loadcases.expressions import CompiledExpression, ExpressionError, parse
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import CaseFile
from loadcases.schema import FlexibleBody
from mechlib.elements.hydraulics import ServoActuator
from mechlib.elements.series import SeriesLaw, series_stiffness
from mechlib.model.joints import ROTATIONAL, TRANSLATIONAL
from mechlib.model.tables import Table, TableRangeError

__all__ = [
    "ABSCISSA_COLUMN",
    "ABSCISSA_REQUEST",
    "BuiltRun",
    "ExpressionMotion",
    "build_mechanism",
    "build_run",
]

NOT_YET = "is not simulated by this version of loads yet"
_EFFECT_OF = ELEMENT_EFFECTS  # force element type -> effect switching it
_MEASURE_JOINTS = {
    "angle": ROTATIONAL,
    "omega": ROTATIONAL,
    "travel": TRANSLATIONAL,
    "speed": TRANSLATIONAL,
}
# A run of a set records the case's `abscissa:` expression as one more result column, so
# envelopes and curves over it can be made from the saved results alone.
ABSCISSA_REQUEST = "abscissa"
ABSCISSA_COLUMN = f"{ABSCISSA_REQUEST}.value"
# Unit of an abscissa that is one state measure, e.g. `angle(hinge)` -> rad.
_MEASURE_UNITS = {
    "angle": "rad",
    "omega": "rad/s",
    "travel": "m",
    "speed": "m/s",
    "dist": "m",
    "x": "m",
    "y": "m",
    "z": "m",
    "vx": "m/s",
    "vy": "m/s",
    "vz": "m/s",
    "t": "s",
}
_MEASURE = re.compile(r"^\s*(\w+)\s*(\(\s*\w+\s*(,\s*\w+\s*)?\))?\s*$")
_JOINT_KEYS = ("at", "axis", "axes", "normal", "pitch", "joints", "ratio")


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

    def solve(
        self, analysis: Any = None, *, progress: Any = None, checks: bool = True
    ) -> ml.Solution:
        """`mechlib.solve` of this run (a failure is a failed Solution, never raised; an
        ill-posed model raises ml.ModelError); `analysis` replaces the case's; `checks`
        False: no position checks after the run (mechlib.solve)."""
        return ml.solve(
            self.mechanism,
            self.analysis if analysis is None else analysis,
            requests=self.requests,
            initial=self.initial,
            redundant=self.redundant,
            throw=False,
            events=self.events,
            progress=progress,
            checks=checks,
        )


def _named_elsewhere(mechanism, case) -> set[str]:
    """Force elements a request or an event names: built even when their load is zero."""
    events = list(mechanism.events.values())
    if case is not None:
        events += list(case.events.values())
    names = {a.target for e in events for a in e.then if a.target}
    if case is not None:
        names |= {getattr(r, "force", None) for r in case.requests.values()}
    return names


class Guarded:
    """The compiled expression `compiled`, its run-time errors (math, table range) turned
    into a solver failure that says which input and when."""

    def __init__(self, compiled: CompiledExpression, what: str):
        self.compiled, self.what = compiled, what

    def __call__(self, t: float, state=None) -> float:
        try:
            return self.compiled(t, state)
        except (ExpressionError, TableRangeError, ZeroDivisionError, OverflowError) as exc:
            raise ml.SolverFailure(
                f"{self.what}: {exc} at t = {t:.6g} s", time=t, where=(self.what,)
            ) from None


class ExpressionMotion:
    """A motion's coordinate f(t) (rad or m) with exact d/dt and d2/dt2 of its expression."""

    def __init__(self, compiled, what: str = "motion"):
        self._f = Guarded(compiled, what)
        self._d1 = Guarded(compiled.derivative(), what)
        self._d2 = Guarded(compiled.derivative().derivative(), what)

    def value(self, t: float) -> float:
        return self._f(t)

    def rate(self, t: float) -> float:
        return self._d1(t)

    def accel(self, t: float) -> float:
        return self._d2(t)


class _Builder:
    """Builds from a mechanism model and, when given, the case that uses it."""

    def __init__(self, mechanism, parameters: dict[str, float], where: Callable, case=None):
        self.case, self.mech, self.parameters, self.where = case, mechanism, parameters, where
        self.problems: list[Diagnostic] = []
        effects = dict(case.effects) if case is not None else {}
        self.effects = {"gravity": True, "damping": True} | effects
        self.loads = case.loads if case is not None else None
        self.tables = {
            n: Table(n, t.x, t.y, t.interpolation, t.extrapolate)
            for n, t in self.mech.tables.items()
        }
        self.kept = _named_elsewhere(mechanism, case)

    def error(self, kind: str, key: str, message: str) -> None:
        file, line, col = self.where(kind, key)
        self.problems.append(Diagnostic(file, line, col, key, message))

    def compile(self, text: str, what: str, kind: str = "mechanism") -> Guarded:
        return self.compile_tree(parse(text), what, kind)

    def compile_tree(self, expression, what: str, kind: str = "mechanism") -> Guarded:
        """A parsed expression (or part of one) compiled and guarded."""
        self._check_measures(expression, what, kind)
        try:
            compiled = expression.compile(self.parameters, self.tables)
        except ExpressionError as error:  # a constant part that overflows or divides by 0
            self.error(
                kind, what, f"invalid expression: {error.message} at character {error.offset + 1}"
            )
            compiled = parse("0").compile()
        return Guarded(compiled, what)

    def _check_measures(self, expression, what: str, kind: str) -> None:
        """angle/omega need a rotational joint, travel/speed a translational one, effort a
        motion of the case."""
        for measure, args in expression.measures():
            if measure == "effort" and args[0] not in (self.case.motions if self.case else {}):
                self.error(kind, what, f"effort({args[0]}): no motion '{args[0]}' in this case")
                continue
            types = _MEASURE_JOINTS.get(measure)
            joint = self.mech.joints.get(args[0]) if types else None
            if joint is not None and types and joint.type not in types:
                self.error(
                    kind,
                    what,
                    f"{measure}({args[0]}): joint '{args[0]}' is "
                    f"{joint.type}; {measure} needs a {' or '.join(types)} joint",
                )

    # ---- mechanism --------------------------------------------------------------------
    def mechanism(self) -> ml.Mechanism:
        gravity = self.mech.gravity if self.effects.get("gravity", True) else (0.0, 0.0, 0.0)
        m = ml.Mechanism(name=self.mech.name or "mechanism", gravity=gravity, plane=self.mech.plane)
        self.built = m
        for name, b in self.mech.bodies.items():
            if isinstance(b, FlexibleBody):
                self._flexible(m, name, b.flexible)
            else:
                m.add_body(name, mass=b.mass, cm=b.cm, inertia=b.inertia)
        for name, p in self.mech.points.items():
            self._at_interface(p.body, p.at, f"points.{name}.at")
            m.add_point(name, body=p.body, at=p.at)
        for name, f in self.mech.frames.items():
            m.add_frame(name, body=f.body, x=f.x, y=f.y, at=f.at)
        for name, j in self.mech.joints.items():
            self._joint(m, name, j)
        self._forces(m)
        for name, c in self.mech.contacts.items() if self.effects.get("contact", True) else ():
            maker = CONTACT_MAKERS.get(c.type)
            element = maker(self, name, c) if maker else None
            if element is not None:
                element.active = c.active  # `active: false`: built, switched on by an event
            if maker is None:
                self.error("mechanism", f"contacts.{name}", f"{c.type} contacts {NOT_YET}")
            elif element is not None:
                m.add_force(element)
        for name, motion in (self.case.motions if self.case else {}).items():
            fn = self.compile(motion.value, f"motions.{name}.value", "case").compiled
            if not fn.time_only:
                self.error(
                    "case",
                    f"motions.{name}.value",
                    "a motion must be a function of "
                    "time only (use a force element for state-dependent loads)",
                )
                continue
            try:
                function = ExpressionMotion(fn, f"motions.{name}.value")
            except ExpressionError as error:  # its rate or acceleration divides by 0
                self.error(
                    "case",
                    f"motions.{name}.value",
                    f"invalid expression: {error.message} in its time derivative",
                )
                continue
            m.add_motion(name, joint=motion.joint, function=function)
        return m

    def _flexible_request(self, name: str, r):
        body = self.mech.bodies.get(r.flexible)
        if not isinstance(body, FlexibleBody):
            self.error("case", f"requests.{name}.flexible", f"'{r.flexible}' is no flexible body")
            return None
        if r.quantity == "deformation" and (
            r.point is None or r.point.removeprefix(f"{r.flexible}.") not in body.flexible.interface
        ):
            self.error(
                "case",
                f"requests.{name}.point",
                f"a deformation needs one of the interface points of {r.flexible}: "
                + ", ".join(f"{r.flexible}.{p}" for p in body.flexible.interface),
            )
            return None
        return ml.FlexibleOutput(name, r.flexible, r.quantity, r.point)

    def body_owner(self, body: str) -> str:
        """The body a body name stands for: `BODY.POINT` (a flexible body's interface point,
        that node's rigid body) is on BODY."""
        for name, b in self.mech.bodies.items():
            if isinstance(b, FlexibleBody) and any(
                body == f"{name}.{point}" for point in b.flexible.interface
            ):
                return name
        return body

    def _at_interface(self, body: str, at, key: str) -> None:
        """An error at `key` when `at` (m) is on flexible `body` but at none of its interface
        points: attachments and loads act at interface nodes only."""
        b = self.mech.bodies.get(body)
        if not isinstance(b, FlexibleBody):
            return
        gaps = {
            name: float(np.linalg.norm(np.subtract(at, point)))
            for name, point in b.flexible.interface.items()
        }
        nearest = min(gaps, key=gaps.__getitem__)
        if gaps[nearest] > 1e-6:
            self.error(
                "mechanism",
                key,
                f"{body} is a flexible body: a point of it is at one of its interface points "
                f"or carried by one (nearest: {body}.{nearest}, {gaps[nearest]:.3g} m away; "
                f"to attach this point to that node by a rigid arm, name the body "
                f"'{body}.{nearest}')",
            )

    def _flexible(self, m: ml.Mechanism, name: str, f) -> None:
        """A flexible body (its interface points are points `NAME.POINT` of the schema
        model), or an error at its key."""
        from loadcases.build.flexible import flexible_component
        from mechlib.flexible.attached import node_at  # scipy.sparse: only with flexible bodies

        key = f"bodies.{name}.flexible"
        try:
            component = flexible_component(f, Path(self.where("mechanism", key)[0]).parent)
        except InputError as error:  # the files of an imported model
            self.problems += error.diagnostics
            return
        except ValueError as error:  # ReductionError too
            self.error("mechanism", key, str(error))
            return
        if self.effects.get("flexibility", True):
            flexible = m.add_flexible_body(name, component, linear_limit=f.linear_limit)
            for point, at in f.interface.items():  # `BODY.POINT`: that node's rigid body
                m.add_alias(f"{name}.{point}", node_at(flexible, at))
        else:  # `effects: {flexibility: false}`: the same body, rigid
            inertia = component.invariants.I7
            m.add_body(name, mass=component.mass, cm=component.origin, inertia=inertia)
            for point in f.interface:
                m.add_alias(f"{name}.{point}", name)

    def _joint(self, m: ml.Mechanism, name: str, j) -> None:
        if j.type == "point_on_curve":
            m.add_joint(
                name,
                j.type,
                bodies=tuple(j.bodies),
                at=j.at,
                curve=j.curve,
                interpolation=j.interpolation,
            )
            return
        keys = {k: getattr(j, k) for k in _JOINT_KEYS if getattr(j, k, None) is not None}
        bodies = tuple(getattr(j, "bodies", (ml.GROUND, ml.GROUND)))
        for body in bodies:
            self._at_interface(body, keys.get("at", (0.0, 0.0, 0.0)), f"joints.{name}.at")
        if j.type == "orientation" and keys.get("at") is None:
            keys.pop("at", None)
        m.add_joint(name, j.type, bodies=bodies, **keys)

    def _forces(self, m: ml.Mechanism) -> None:
        chosen = self.loads
        for name, f in self.mech.forces.items():
            if chosen is not None and name not in chosen:
                continue
            if not self.effects.get(_EFFECT_OF.get(f.type, ""), True):
                continue  # its effect is switched off: not simulated at all
            element = self._element(name, f)
            if element is not None:
                element.active = f.active  # `active: false`: built, switched on by an event
                m.add_force(element)

    def _element(self, name: str, f):
        damping = self.effects.get("damping", True)
        law: ml.TableLaw | SeriesLaw | None = None
        if f.type in ("spring", "torsion_spring") and f.law is not None:
            if f.stiffness:  # the table replaces the linear term: both would be ambiguous
                self.error("mechanism", f"forces.{name}.law", "give 'stiffness' or 'law', not both")
                return None
            law = ml.TableLaw(self.tables[f.law], name)
        if f.type == "spring":
            p1, p2 = (self.mech.points[p] for p in f.points)
            pts = ((p1.body, p1.at), (p2.body, p2.at))
            return ml.Spring(
                name,
                pts,
                f.stiffness,
                f.damping if damping else 0.0,
                f.free_length,
                f.preload or 0.0,
                f.tension_only,
                law,
            )
        if f.type == "torsion_spring":
            stiffness = f.stiffness
            if f.series_stiffness is not None:  # eq. 2.7: structure and hinge in series
                if law is not None:
                    law = SeriesLaw(law, f.series_stiffness)
                elif stiffness:
                    stiffness = series_stiffness(f.series_stiffness, stiffness)
            return ml.TorsionSpring(
                name,
                f.joint,
                stiffness,
                f.damping if damping else 0.0,
                f.angle0 or 0.0,
                f.preload or 0.0,
                law,
            )
        if f.type in ("force", "torque"):
            expressions = [parse(str(v)) for v in f.value]
            parts = [
                self.compile_tree(e, f"forces.{name}.value[{i}]") for i, e in enumerate(expressions)
            ]
            reads = set().union(*(e.measures() for e in expressions))  # its columns' bodies
            if all(p.compiled.is_constant for p in parts):
                x, y, z = (p.compiled.value or 0.0 for p in parts)  # constants: values set
                constant = (x, y, z)
                if not any(constant) and name not in self.kept:
                    return None  # zero throughout (a load switched off by its parameters)

                def value(t: float, view) -> tuple[float, float, float]:
                    return constant
            else:

                def value(t: float, view) -> tuple[float, float, float]:
                    return (parts[0](t, view), parts[1](t, view), parts[2](t, view))

            if f.type == "torque":
                return ml.PointTorque(name, f.body, value, f.frame, reads=reads)
            body, at = self._application(f)
            return ml.PointForce(name, body, at, value, f.frame, reads=reads)
        maker = ELEMENT_MAKERS.get(f.type)
        if maker is not None:
            return maker(self, name, f)
        self.error("mechanism", f"forces.{name}", f"{f.type} elements {NOT_YET}")
        return None

    def _application(self, f) -> tuple[str, tuple]:
        if f.point is not None:
            p = self.mech.points[f.point]
            return p.body, p.at
        if f.at is not None:
            return f.body, f.at
        body = self.mech.bodies.get(f.body)
        return f.body, getattr(body, "cm", None) or (0.0, 0.0, 0.0)

    # ---- case -------------------------------------------------------------------------
    def analysis(self):
        a = self.case.analysis
        if a.type == "modes":
            return ml.Modes(time=0.0)
        if a.type == "static":
            return ml.Static(time=0.0)
        if a.end is None or a.step is None or a.step <= 0.0 or a.end <= 0.0:
            self.error(
                "case", "analysis", f"a {a.type} analysis needs 'end' and 'step' > 0 (seconds)"
            )
            return None
        limit = {"max_steps": a.max_steps} if a.max_steps is not None else {}
        if a.type == "kinematic":
            return ml.Kinematic(end=a.end, step=a.step, **limit)
        if a.type == "quasi-static":
            return ml.QuasiStatic(end=a.end, step=a.step, **limit)
        integrator = a.integrator or "generalized-alpha"
        if integrator not in ("generalized-alpha", "radau"):
            self.error(
                "case",
                "analysis.integrator",
                f"unknown integrator '{integrator}': use generalized-alpha or radau",
            )
        options = {
            key: value
            for key, value in (("tolerance", a.tolerance), ("rho_inf", a.rho_inf))
            if value is not None
        }
        if a.output != "steps":  # dense by default: the steps do not depend on the output
            options["dense"] = True
        return ml.Dynamic(
            end=a.end, step=a.step, integrator=integrator, max_step=a.max_step, **options, **limit
        )

    def requests(self) -> tuple[list, dict[str, str]]:
        out, units = [], {}
        for name, r in self.case.requests.items():
            req = self._request(name, r)
            if req is None:
                continue
            out.append(req)
            for comp, unit in _units_of(req, self).items():
                units[f"{name}.{comp}"] = unit
        return out, units

    def _request(self, name: str, r):
        kind = type(r).__name__
        if kind == "JointRequest":
            if r.quantity == "force" and self.mech.joints[r.joint].type in ("coupler", "gear"):
                return ml.CouplerEffort(name, r.joint)
            if r.quantity == "force":
                return ml.JointReaction(name, r.joint, r.frame)
            return ml.JointCoordinate(name, r.joint, r.quantity)
        if kind == "MotionRequest":
            return ml.MotionEffort(name, r.motion)
        if kind == "PointRequest":
            return ml.PointKinematics(name, r.point, r.quantity, r.frame)
        if kind == "FlexibleRequest":
            return self._flexible_request(name, r)
        if kind == "ElementRequest":
            f = self.mech.forces.get(r.force)
            if (
                f is None
                or (self.loads is not None and r.force not in self.loads)
                or not self.effects.get(_EFFECT_OF.get(f.type, ""), True)
            ):
                self.error(
                    "case",
                    f"requests.{name}.force",
                    f"force element '{r.force}' is not active in this case",
                )
                return None
            return ml.ElementOutput(name, r.force, r.frame)
        if kind == "EnergyRequest":
            return ml.EnergyBalance(name)
        if kind == "ExpressionRequest":
            return ml.ExpressionOutput(name, self.compile(r.expression, f"requests.{name}", "case"))
        components = CONTACT_COMPONENTS.get(r.quantity)
        if r.contact in self.mech.contacts and components and self.effects.get("contact", True):
            return ml.ElementOutput(name, r.contact, r.frame, components)
        self.error(
            "case",
            f"requests.{name}",
            f"contact '{r.contact}' is not simulated in this "
            "case (switched off, or its quantity is not available)",
        )
        return None

    def initial(self) -> list:
        out: list[ml.InitialValue | ml.InitialBodyVelocity] = []
        for name, v in self.case.initial.items():
            if name in self.mech.joints:
                out.append(ml.InitialValue(name, v.value, v.rate))
            else:
                out.append(ml.InitialBodyVelocity(name, v.omega, v.velocity))
        return out


_COORDINATE_UNITS = {
    "angle": "rad",
    "omega": "rad/s",
    "alpha": "rad/s^2",
    "travel": "m",
    "speed": "m/s",
    "accel": "m/s^2",
}
_POINT_UNITS = {"position": "m", "velocity": "m/s", "acceleration": "m/s^2"}


def _units_of(req, builder: _Builder) -> dict[str, str]:
    if isinstance(req, ml.JointReaction):
        return dict(req.units)
    if isinstance(req, ml.JointCoordinate):
        return {"value": _COORDINATE_UNITS[req.quantity]}
    if isinstance(req, ml.PointKinematics):
        return dict.fromkeys("xyz", _POINT_UNITS[req.quantity])
    if isinstance(req, ml.FlexibleOutput):
        if req.quantity == "deformation":
            return dict.fromkeys("xyz", "m")
        built = getattr(builder, "built", None)
        flexible = built.flexible.get(req.body) if built is not None else None
        count = flexible.component.count if flexible is not None else 0
        return {f"q{j + 1}": "kg^0.5*m" for j in range(count)}
    if isinstance(req, ml.MotionEffort):
        joint = builder.mech.joints[builder.case.motions[req.motion].joint]
        return {"value": "N" if joint.type == "prismatic" else "N*m"}
    if isinstance(req, ml.CouplerEffort):
        ends = builder.mech.joints[req.joint].joints
        return {
            column: "N" if builder.mech.joints[j].type == "prismatic" else "N*m"
            for column, j in zip(("input", "output"), ends)
        }
    if isinstance(req, ml.ElementOutput) and req.components is not None:
        return {column: CONTACT_UNITS.get(key, "") for column, key in req.components}
    if isinstance(req, ml.ElementOutput):  # an element that failed to build: its error stands
        element = builder.built.forces.get(req.element)
        return dict(getattr(element, "output_units", {}))
    if isinstance(req, ml.EnergyBalance):
        return dict(req.units)
    return {"value": ""}


def build_mechanism(mf) -> ml.Mechanism:
    """The mechlib model of a mechanism file alone (no motions, all elements active)."""
    b = _Builder(mf.model, dict(mf.model.parameters), lambda kind, key: mf.where(key))
    mechanism = b.mechanism()
    if b.problems:
        raise InputError(b.problems)
    return mechanism


def abscissa_unit(text: str) -> str:
    """SI unit of an abscissa expression that is a single state measure, else `""`."""
    match = _MEASURE.match(text)
    if match is None or (match.group(1) != "t" and match.group(2) is None):
        return ""
    return _MEASURE_UNITS.get(match.group(1), "")


def _abscissa_request(b: _Builder, requests: list, units: dict[str, str]) -> None:
    """Append the case's abscissa as request `abscissa` (column `abscissa.value`)."""
    text = b.case.abscissa
    if text is None:
        return
    if ABSCISSA_REQUEST in b.case.requests:
        b.error(
            "case",
            f"requests.{ABSCISSA_REQUEST}",
            f"the request name "
            f"'{ABSCISSA_REQUEST}' is reserved for the case's abscissa in a set; rename it",
        )
        return
    requests.append(ml.ExpressionOutput(ABSCISSA_REQUEST, b.compile(text, "abscissa", "case")))
    units[ABSCISSA_COLUMN] = abscissa_unit(text)


def _modal_requests(requests: list, units: dict[str, str]):
    """The requests a modes analysis reports (points, joint coordinates), their units (per
    unit modal amplitude), the mode number and frequency columns, and the names dropped."""
    kept = [r for r in requests if isinstance(r, (ml.PointKinematics, ml.JointCoordinate))]
    dropped = [r.name for r in requests if r not in kept]
    names = {r.name for r in kept}
    units = {"mode.number": "", "mode.frequency": "Hz"} | {
        c: (
            "m"
            if isinstance(next(r for r in kept if r.name == c.split(".")[0]), ml.PointKinematics)
            else u
        )
        for c, u in units.items()
        if c.split(".")[0] in names
    }
    return kept, units, dropped


def _case_warning(cf: CaseFile, key: str, message: str, *, keyed: bool = True) -> Diagnostic:
    """A warning at `key` of the case file (`keyed=False`: placed there, named by no key)."""
    file, line, column = cf.where("case", key)
    return Diagnostic(file, line, column, key if keyed else "", message, "warning")


def _servo_problems(cf: CaseFile, mechanism: ml.Mechanism, analysis) -> list[Diagnostic]:
    """Servo actuators with valve dynamics in an equilibrium analysis: their chamber
    pressures follow the piston flow, which an equilibrium (piston at rest) does not have,
    so they cannot give a force there (docs/hydraulics.md, Analyses)."""
    if not isinstance(analysis, (ml.QuasiStatic, ml.Static)):
        return []
    file, line, column = cf.where("case", "analysis.type")
    return [
        Diagnostic(
            file,
            line,
            column,
            "analysis.type",
            f"servo actuator '{name}' ({element.fidelity}) cannot act in a {analysis.name} "
            "analysis: its chamber pressures follow the piston flow, and an equilibrium has "
            "the piston at rest",
            hint="use a dynamic or kinematic analysis, the actuator's fidelity lag, "
            "or effects: {hydraulics: false}",
        )
        for name, element in mechanism.forces.items()
        if isinstance(element, ServoActuator) and element.fidelity != "lag"
    ]


def _flexible_notes(cf: CaseFile, mechanism: ml.Mechanism) -> list[Diagnostic]:
    """The approximation of each flexible body, said with the results (issue 13)."""
    notes = []
    for name, body in mechanism.flexible.items():
        f = body.component.frequencies / (2.0 * np.pi)
        stiffening = (
            "geometric stiffening of the spin and the interface loads (beam axial forces)"
            if body.component.geometric is not None
            else "no geometric stiffening"
        )
        file, line, column = cf.where("mechanism", f"bodies.{name}.flexible")
        notes.append(
            Diagnostic(
                file,
                line,
                column,
                f"bodies.{name}.flexible",
                f"flexible body {name}: {len(f)} Craig-Bampton modes ({f.min():.4g} to "
                f"{f.max():.4g} Hz), linear elastic deformation in a floating frame (small "
                f"deformation, {stiffening})",
                "warning",
            )
        )
    return notes


def build_run(cf: CaseFile, *, abscissa: bool = False) -> BuiltRun:
    """The mechlib model, analysis, requests and initial values of a case; InputError lists
    everything the engine cannot build. With `abscissa`, the case's `abscissa:` expression
    (if any) becomes one more request, column `abscissa.value`."""
    b = _Builder(cf.mechanism, cf.parameters, cf.where, cf.case)
    mechanism = b.mechanism()
    analysis = b.analysis()
    requests, units = b.requests()
    if abscissa:
        _abscissa_request(b, requests, units)
    initial = b.initial()
    b.problems += _servo_problems(cf, mechanism, analysis)
    if b.problems:
        raise InputError(b.problems)
    events = build_events(b)
    if b.problems:
        raise InputError(b.problems)
    notes = list(cf.warnings)  # validation warnings travel along
    if isinstance(analysis, ml.Modes):
        requests, units, dropped = _modal_requests(requests, units)
        notes += [
            _case_warning(
                cf,
                f"requests.{name}",
                "no modal meaning (a modes analysis "
                "reports point displacements and joint coordinates of each "
                "mode): not reported",
            )
            for name in dropped
        ]
    if events and isinstance(analysis, (ml.Static, ml.Modes)):
        # a mechanism serves static and dynamic cases alike: its events wait for one in time
        notes.append(
            _case_warning(
                cf,
                "analysis",
                f"events ({', '.join(e.name for e in events)})"
                f" need an analysis in time: not active in this "
                f"{analysis.name} analysis",
                keyed=False,
            )
        )
        events = []
    notes += _flexible_notes(cf, mechanism)
    return BuiltRun(
        mechanism, analysis, requests, initial, cf.case.analysis.redundant, units, notes, events
    )
