"""Mass properties of a mechanism in one configuration: every rigid body's mass, centre of
mass and inertia about its centre (global axes), its moment of inertia about a named axis,
and the assembly's totals (the seed's Table 1 check of inertias between tools).

A body given at its design position (`cm`, `inertia` about the cm in global axes) and
moved by a rotation R and to a centre c has the inertia R I R^T about c. About an axis
through the point a with unit direction n: I_n = n^T I_c n + m (|r|^2 - (r . n)^2), r = c - a
(parallel axis theorem). The assembly: mass sum m_i, centre sum m_i c_i / m, inertia about
that centre sum (I_i + m_i (|d_i|^2 E - d_i d_i^T)), d_i = c_i - c. Inertia products follow
the mechanism file's convention, Ixy = -integral of x y dm (the tensor's off-diagonal).
Units: kg, m, kg*m^2 (SI), in `mass-properties.csv` and the workbook's `Mass properties`.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.build.sections import inertia_tensor
from loadcases.foundation.atomic import atomic_write_text
from loadcases.foundation.clip import visible_fields
from loadcases.report.number_format import SIGNIFICANT_DIGITS, number_format

__all__ = [
    "ASSEMBLY",
    "MASS_FILE",
    "MASS_SHEET",
    "BodyMass",
    "MassRow",
    "assembly",
    "inertia_tensor",
    "mass_csv_text",
    "mass_rows",
    "mass_sheet",
    "moment_about_axis",
    "posed",
    "write_mass_csv",
]

MASS_FILE = "mass-properties.csv"
MASS_SHEET = "Mass properties"
ASSEMBLY = "assembly"


@dataclass(frozen=True)
class BodyMass:
    """One body: `mass` kg, `cm` (3,) m and `inertia` (3, 3) kg*m^2 about the cm, global axes."""

    name: str
    mass: float
    cm: np.ndarray
    inertia: np.ndarray


def posed(body: BodyMass, rotation: np.ndarray, centre: np.ndarray) -> BodyMass:
    """The body turned by `rotation` (3, 3) from its design position, its cm at `centre`."""
    r = np.asarray(rotation, dtype=float)
    return BodyMass(body.name, body.mass, np.asarray(centre, float), r @ body.inertia @ r.T)


def moment_about_axis(body: BodyMass, point: np.ndarray, direction: np.ndarray) -> float:
    """kg*m^2: the body's moment of inertia about the axis through `point` along
    `direction` (any length)."""
    n = np.asarray(direction, float) / np.linalg.norm(direction)
    r = body.cm - np.asarray(point, float)
    return float(n @ body.inertia @ n + body.mass * (r @ r - (r @ n) ** 2))


def assembly(bodies: Sequence[BodyMass]) -> BodyMass:
    """The bodies as one: total mass, its centre, its inertia about that centre."""
    mass = sum(b.mass for b in bodies)
    cm = sum(b.mass * b.cm for b in bodies) / mass if mass > 0.0 else np.zeros(3)
    inertia = np.zeros((3, 3))
    for b in bodies:
        d = b.cm - cm
        inertia += b.inertia + b.mass * (d @ d * np.eye(3) - np.outer(d, d))
    return BodyMass(ASSEMBLY, float(mass), np.asarray(cm, float), inertia)


@dataclass(frozen=True)
class MassRow:
    """One line of the table (SI): a body, or the assembly."""

    body: str
    mass: float
    cm: tuple[float, float, float]
    inertia: tuple[float, float, float, float, float, float]  # Ixx Iyy Izz Ixy Ixz Iyz
    about_axis: float | None


def _row(body: BodyMass, axis: Any | None) -> MassRow:
    i = body.inertia
    about = None if axis is None else moment_about_axis(body, axis.at, axis.direction)
    six = (i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2])
    return MassRow(
        body.name,
        body.mass,
        tuple(float(v) for v in body.cm),  # type: ignore[arg-type]
        tuple(float(v) for v in six),  # type: ignore[arg-type]
        about,
    )


def mass_rows(bodies: Sequence[BodyMass], axis: Any | None = None) -> list[MassRow]:
    """A row per body, then the assembly's; `axis` (`at`, `direction`, `name`) or None."""
    return [_row(b, axis) for b in bodies] + [_row(assembly(bodies), axis)]


def _header(axis_name: str | None) -> list[str]:
    header = ["body", "mass [kg]", "cm x [m]", "cm y [m]", "cm z [m]"]
    header += [f"{c} [kg*m^2]" for c in ("Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz")]
    if axis_name is not None:
        header.append(f"I about {axis_name} [kg*m^2]")
    return header


def _cells(row: MassRow, with_axis: bool) -> list[object]:
    cells: list[object] = [row.body, row.mass, *row.cm, *row.inertia]
    return cells + ([row.about_axis] if with_axis else [])


def mass_csv_text(rows: Sequence[MassRow], axis_name: str | None, where: str) -> str:
    """`mass-properties.csv`: the table, its last column `configuration` saying where the
    bodies are (the case, the time, the axis)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(visible_fields([*_header(axis_name), "configuration"]))
    for row in rows:
        writer.writerow(visible_fields([*_cells(row, axis_name is not None), where]))
    return buffer.getvalue()


def write_mass_csv(rows: Sequence[MassRow], axis_name: str | None, where: str, path: Path) -> Path:
    """Write `mass-properties.csv` atomically."""
    return atomic_write_text(path, mass_csv_text(rows, axis_name, where))


def mass_sheet(
    sheet: Any,
    rows: Sequence[MassRow],
    axis_name: str | None,
    where: str,
    digits: int = SIGNIFICANT_DIGITS,
) -> None:
    """The workbook's `Mass properties` sheet: where, then the table (assembly in bold),
    each column with `digits` significant digits of its largest magnitude."""
    sheet.cell(row=1, column=1, value=where).style = "loads label"
    for k, title in enumerate(_header(axis_name), start=1):
        sheet.cell(row=2, column=k, value=title).style = "loads header"
    table = [_cells(row, axis_name is not None) for row in rows]
    formats = [
        number_format((v for v in column if isinstance(v, float)), digits) for column in zip(*table)
    ]
    for r, (row, cells) in enumerate(zip(rows, table), start=3):
        for k, value in enumerate(cells, start=1):
            cell = sheet.cell(row=r, column=k, value=value)
            if k > 1:
                cell.style = "loads number"
                cell.number_format = formats[k - 1]
        if row.body == ASSEMBLY:
            sheet.cell(row=r, column=1).style = "loads label"
    sheet.freeze_panes = "B3"
    sheet.column_dimensions["A"].width = 24
