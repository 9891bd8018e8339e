"""A set's `mass_properties:`: the case built as `loads run` builds it and solved with
three point requests per rigid body (its cm and points 0.1 m from it along the design x
and y axes) instead of its own; at the output time nearest `at`, each body's rotation from
its design position (from those points, orthonormalised) and centre of mass give its mass
properties there (`loadcases.report.mass_properties`). Flexible bodies are left out (their
FE mass properties: `loads flex check`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

import mechlib as ml
from loadcases.build.model import build_run
from loadcases.inputs.loader import CaseFile, load_case
from loadcases.report.mass_properties import (
    MASS_FILE,
    BodyMass,
    MassRow,
    inertia_tensor,
    mass_rows,
    posed,
    write_mass_csv,
)
from loadcases.schema.mechanism import FlexibleBody

__all__ = ["MassTable", "body_masses_at", "mass_table"]

_ARM = 0.1  # m: the marker points' distance from the cm
_PREFIX = "__mass_"
_OFFSETS = (("c", np.zeros(3)), ("x", _ARM * np.eye(3)[0]), ("y", _ARM * np.eye(3)[1]))


def _rotation(cm: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """The rotation whose first two columns are the directions cm -> px and cm -> py
    (Gram-Schmidt: round-off of the solved positions does not skew it)."""
    ex = (px - cm) / np.linalg.norm(px - cm)
    ey = py - cm - ((py - cm) @ ex) * ex
    ey /= np.linalg.norm(ey)
    return np.column_stack([ex, ey, np.cross(ex, ey)])


def body_masses_at(cf: CaseFile, at: float) -> tuple[list[BodyMass], float, str]:
    """The rigid bodies of a case where its run puts them at the output time nearest `at`
    (s): (bodies, that time, the solve's status message). ValueError if it failed before."""
    design = {
        name: BodyMass(name, float(b.mass), np.asarray(b.cm, float), inertia_tensor(b.inertia))
        for name, b in cf.mechanism.bodies.items()
        if not isinstance(b, FlexibleBody)
    }
    built = build_run(cf)
    requests = []
    for k, body in enumerate(design.values()):
        for tag, offset in (
            ("c", np.zeros(3)),
            ("x", _ARM * np.eye(3)[0]),
            ("y", _ARM * np.eye(3)[1]),
        ):
            point = f"{_PREFIX}{k}{tag}"
            built.mechanism.add_point(point, body=body.name, at=tuple(body.cm + offset))
            requests.append(ml.PointKinematics(point, point, "position"))
    solution = built.solve(requests=requests)
    time = np.asarray(solution.time)
    if time.size == 0 or (not solution.ok and at > time[-1]):
        raise ValueError(f"{cf.case.case} did not reach t = {at:g} s: {solution.message}")
    i = int(np.argmin(np.abs(time - at)))

    def where(k: int, tag: str) -> np.ndarray:
        return np.array([solution.channels[f"{_PREFIX}{k}{tag}.{c}"][i] for c in "xyz"])

    bodies = [
        posed(body, _rotation(where(k, "c"), where(k, "x"), where(k, "y")), where(k, "c"))
        for k, body in enumerate(design.values())
    ]
    return bodies, float(time[i]), solution.message


class MassTable:
    """The rows of a set's mass properties, what they are about, and their CSV."""

    def __init__(self, rows: list[MassRow], axis: Any | None, where: str) -> None:
        self.rows, self.axis, self.where = rows, axis, where

    @property
    def axis_name(self) -> str | None:
        return None if self.axis is None else str(self.axis.name)

    def write_csv(self, directory: Path) -> Path:
        return write_mass_csv(self.rows, self.axis_name, self.where, directory / MASS_FILE)


def mass_table(compiled: Any) -> MassTable:
    """The mass properties a compiled set asks for (its `mass_properties:`), in the first
    run of the case (with the set's parameters and first swept values); without rows
    (and `where` saying why) when the case's solve fails before the time asked for."""
    wanted = compiled.set_file.model.mass_properties
    spec = next(r for r in compiled.runs if r.family == wanted.case)  # checked at load
    cf = load_case(spec.case_path, overrides=dict(spec.parameters))
    try:
        bodies, time, _ = body_masses_at(cf, float(wanted.at))
    except ValueError as error:  # the case failed before `at`: said on the sheet and CSV
        return MassTable([], wanted.axis, f"not computed: {error}")
    where = f"run {spec.name} at t = {time:.6g} s (output time nearest {float(wanted.at):g} s)"
    if wanted.axis is not None:
        a, n = wanted.axis.at, wanted.axis.direction
        where += f"; axis {wanted.axis.name}: through {tuple(a)} m along {tuple(n)}"
    return MassTable(mass_rows(bodies, wanted.axis), wanted.axis, where)
