"""The force elements of a case's model: springs, torsion springs, point forces and torques
here, the domain elements through `ELEMENT_MAKERS`; those the case's loads or effects leave
out are not built."""

from __future__ import annotations

import mechlib as ml
from loadcases.build.context import NOT_YET, Builder
from loadcases.build.elements import ELEMENT_EFFECTS, ELEMENT_MAKERS
from loadcases.expressions import parse
from mechlib.elements.series import SeriesLaw, series_stiffness

__all__ = ["add_forces"]


def add_forces(b: Builder, m: ml.Mechanism) -> None:
    """The force elements the case loads (all of them without a case) whose effect is on."""
    chosen = b.loads
    for name, f in b.mech.forces.items():
        if chosen is not None and name not in chosen:
            continue
        if not b.effects.get(ELEMENT_EFFECTS.get(f.type, ""), True):
            continue  # its effect is switched off: not simulated at all
        element = _element(b, name, f)
        if element is not None:
            element.active = f.active  # `active: false`: built, switched on by an event
            m.add_force(element)


def _element(b: Builder, name: str, f):
    """The mechlib element of force element `name`, or None (after an error, or a load that
    is zero throughout)."""
    if f.type in ("spring", "torsion_spring"):
        return _spring(b, name, f)
    if f.type in ("force", "torque"):
        return _point_load(b, name, f)
    maker = ELEMENT_MAKERS.get(f.type)
    if maker is not None:
        return maker(b, name, f)
    b.error("mechanism", f"forces.{name}", f"{f.type} elements {NOT_YET}")
    return None


def _spring(b: Builder, name: str, f) -> ml.Spring | ml.TorsionSpring | None:
    """A spring between two points or a torsion spring on a joint: linear, or by a table
    law (`law:`), a torsion spring in series with its structure (`series_stiffness`)."""
    law: ml.TableLaw | SeriesLaw | None = None
    if f.law is not None:
        if f.stiffness:  # the table replaces the linear term: both would be ambiguous
            b.error("mechanism", f"forces.{name}.law", "give 'stiffness' or 'law', not both")
            return None
        law = ml.TableLaw(b.tables[f.law], name)
    damping = f.damping if b.effects.get("damping", True) else 0.0
    if f.type == "spring":
        p1, p2 = (b.mech.points[p] for p in f.points)
        pts = ((p1.body, p1.at), (p2.body, p2.at))
        return ml.Spring(
            name, pts, f.stiffness, damping, f.free_length, f.preload or 0.0, f.tension_only, law
        )
    stiffness = f.stiffness
    if f.series_stiffness is not None:  # eq. 2.7: structure and hinge in series
        if law is not None:
            law = SeriesLaw(law, f.series_stiffness)
        elif stiffness:
            stiffness = series_stiffness(f.series_stiffness, stiffness)
    return ml.TorsionSpring(
        name, f.joint, stiffness, damping, f.angle0 or 0.0, f.preload or 0.0, law
    )


def _point_load(b: Builder, name: str, f):
    """A force at a point or a torque on a body, its three components expressions; None for
    a constant zero load nothing else names."""
    expressions = [parse(str(v)) for v in f.value]
    parts = [b.compile_tree(e, f"forces.{name}.value[{i}]") for i, e in enumerate(expressions)]
    reads = set().union(*(e.measures() for e in expressions))  # its columns' bodies
    if all(p.compiled.is_constant for p in parts):
        x, y, z = (p.compiled.value or 0.0 for p in parts)  # constants: values set
        constant = (x, y, z)
        if not any(constant) and name not in b.kept:
            return None  # zero throughout (a load switched off by its parameters)

        def value(t: float, view) -> tuple[float, float, float]:
            return constant
    else:

        def value(t: float, view) -> tuple[float, float, float]:
            return (parts[0](t, view), parts[1](t, view), parts[2](t, view))

    if f.type == "torque":
        return ml.PointTorque(name, f.body, value, f.frame, reads=reads)
    body, at = _application(b, f)
    return ml.PointForce(name, body, at, value, f.frame, reads=reads)


def _application(b: Builder, f) -> tuple[str, tuple]:
    """The body and point (m) a force acts at: its point, its `at`, else the body's centre
    of mass."""
    if f.point is not None:
        p = b.mech.points[f.point]
        return p.body, p.at
    if f.at is not None:
        return f.body, f.at
    body = b.mech.bodies.get(f.body)
    return f.body, getattr(body, "cm", None) or (0.0, 0.0, 0.0)
