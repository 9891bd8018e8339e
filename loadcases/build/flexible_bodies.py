"""Flexible bodies in a case's model: the modal component added (or its rigid stand-in), its
interface points, what may attach to it, its requests and the note on its approximation."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import mechlib as ml
from loadcases.build.context import Builder
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import CaseFile
from loadcases.schema import FlexibleBody

__all__ = [
    "add_flexible_body",
    "at_interface",
    "flexible_notes",
    "flexible_output_units",
    "flexible_request",
]


def add_flexible_body(b: Builder, m: ml.Mechanism, name: str, f) -> None:
    """A flexible body (its interface points are points `NAME.POINT` of the schema
    model), or an error at its key."""
    from loadcases.build.flexible import flexible_component
    from mechlib.flexible.attached import node_at  # scipy.sparse: only with flexible bodies

    key = f"bodies.{name}.flexible"
    try:
        component = flexible_component(f, Path(b.where("mechanism", key)[0]).parent)
    except InputError as error:  # the files of an imported model
        b.problems += error.diagnostics
        return
    except ValueError as error:  # ReductionError too
        b.error("mechanism", key, str(error))
        return
    if b.effects.get("flexibility", True):
        flexible = m.add_flexible_body(name, component, linear_limit=f.linear_limit)
        for point, at in f.points().items():  # `BODY.POINT`: that node's rigid body
            m.add_alias(f"{name}.{point}", node_at(flexible, at))
    else:  # `effects: {flexibility: false}`: the same body, rigid
        inertia = component.invariants.I7
        m.add_body(name, mass=component.mass, cm=component.origin, inertia=inertia)
        for point in f.points():
            m.add_alias(f"{name}.{point}", name)


def at_interface(b: Builder, body: str, at, key: str) -> None:
    """An error at `key` when `at` (m) is on flexible `body` but at none of its interface
    or load points: attachments and loads act at kept nodes only."""
    flexible = b.mech.bodies.get(body)
    if not isinstance(flexible, FlexibleBody):
        return
    gaps = {
        name: float(np.linalg.norm(np.subtract(at, point)))
        for name, point in flexible.flexible.points().items()
    }
    nearest = min(gaps, key=gaps.__getitem__)
    if gaps[nearest] > 1e-6:
        b.error(
            "mechanism",
            key,
            f"{body} is a flexible body: a point of it is at one of its interface or load points "
            f"or carried by one (nearest: {body}.{nearest}, {gaps[nearest]:.3g} m away; "
            f"to attach this point to that node by a rigid arm, name the body "
            f"'{body}.{nearest}')",
        )


def flexible_request(b: Builder, name: str, r):
    """The output of a `flexible:` request, or None after an error at its key."""
    body = b.mech.bodies.get(r.flexible)
    if not isinstance(body, FlexibleBody):
        b.error("case", f"requests.{name}.flexible", f"'{r.flexible}' is no flexible body")
        return None
    if r.quantity == "deformation" and (
        r.point is None or r.point.removeprefix(f"{r.flexible}.") not in body.flexible.points()
    ):
        b.error(
            "case",
            f"requests.{name}.point",
            f"a deformation needs one of the points of {r.flexible}: "
            + ", ".join(f"{r.flexible}.{p}" for p in body.flexible.points()),
        )
        return None
    return ml.FlexibleOutput(name, r.flexible, r.quantity, r.point)


def flexible_output_units(req: ml.FlexibleOutput, b: Builder) -> dict[str, str]:
    """The units of a flexible output's columns: a deformation in m, modal coordinates in
    kg^0.5*m (one per mode of the body as built)."""
    if req.quantity == "deformation":
        return dict.fromkeys("xyz", "m")
    built = getattr(b, "built", None)
    flexible = built.flexible.get(req.body) if built is not None else None
    count = flexible.component.count if flexible is not None else 0
    return {f"q{j + 1}": "kg^0.5*m" for j in range(count)}


def flexible_notes(cf: CaseFile, mechanism: ml.Mechanism) -> list[Diagnostic]:
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
