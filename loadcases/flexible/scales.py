"""The units an imported file declares (`"units": {"length": "mm", "force": "N", ...}`) and
the conversion of its matrices to SI.

A stiffness term K_ij is a generalised force per generalised displacement: force or moment
(force*length) per length or radian, so K_si = (F/L) * D K D with D = diag(L^r_i), r_i = 1
for a rotational DOF and 0 for a translational one; mass terms likewise M_si = m * D M D.
Rotations are always in radians (what every FE code writes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.header import Header
from loadcases.foundation.units import UnitError, check_unit_name, to_si

__all__ = ["UNIT_KEYS", "Scales", "read_scales", "to_si_matrix"]

UNIT_KEYS = ("length", "mass", "force", "time")
_CONSISTENT = 1e-6  # relative: mass unit against force*time^2/length (t against N*s^2/mm)


@dataclass(frozen=True)
class Scales:
    """SI size of one file unit of each kind (`length` 0.001 for mm) and the names given."""

    length: float
    force: float
    mass: float
    time: float
    names: tuple[tuple[str, str], ...]

    def text(self) -> str:
        """`length mm, force N, time s` as declared."""
        return ", ".join(f"{kind} {name}" for kind, name in self.names)


def read_scales(header: Header) -> Scales | None:
    """The `units` of the header: `length` always, `force` or `mass` (both: they must agree
    with each other through length and time), `time` (default s). None with problems on
    the header if they are missing, unknown or inconsistent."""
    units = header.data.get("units")
    if not isinstance(units, dict):
        header.problem(
            ("units",),
            'expected the units of the file, e.g. {"length": "mm", "force": "N", "time": "s"}',
        )
        return None
    sizes: dict[str, float] = {}
    for kind, name in units.items():
        if kind not in UNIT_KEYS:
            header.problem(
                ("units", kind), f"unknown unit kind '{kind}' (use {', '.join(UNIT_KEYS)})"
            )
            continue
        try:
            sizes[kind] = to_si(f"1 {check_unit_name(name, kind)}", kind)
        except UnitError as error:
            header.problem(("units", kind), str(error))
            continue
        if not 0.0 < sizes[kind] < math.inf:  # '0 s', 'mm*0', 's/1e400': conversions divide by it
            header.problem(
                ("units", kind),
                f"the unit '{str(name)[:40]}' is {sizes[kind]:g} in SI: expected a positive size",
            )
    if "length" not in units:
        header.problem(("units",), "missing unit: length")
    if "force" not in units and "mass" not in units:
        header.problem(("units",), "missing unit: force or mass (or both)")
    if header.errors:
        return None
    return _complete(header, sizes, units)


def _complete(header: Header, sizes: dict[str, float], units: dict[str, str]) -> Scales | None:
    """Scales with the unit not given derived from the others (F = m L / T^2)."""
    length, time = sizes["length"], sizes.get("time", 1.0)
    derived_mass = sizes["force"] * time**2 / length if "force" in sizes else None
    mass = sizes.get("mass", derived_mass)
    assert mass is not None
    if derived_mass is not None and not math.isclose(mass, derived_mass, rel_tol=_CONSISTENT):
        header.problem(
            ("units", "mass"),
            f"units not consistent: 1 {units['mass']} = {mass:.6g} kg but 1 {units['force']}"
            f"*{units.get('time', 's')}^2/{units['length']} = {derived_mass:.6g} kg",
            hint="give the force, length and time the matrices are written in and leave mass "
            "out (NASTRAN weight units: give wtmass)",
        )
        return None
    force = sizes.get("force", mass * length / time**2)
    names = tuple((k, str(units[k]).strip()) for k in UNIT_KEYS if k in units)
    return Scales(length, force, mass, time, names)


def to_si_matrix(
    matrix: sp.spmatrix, rotational: np.ndarray, scales: Scales, kind: str
) -> sp.csr_matrix:
    """`matrix` (file units) in SI; `rotational[i]` True where DOF i is a rotation; `kind`
    "stiffness" or "mass"."""
    factor = scales.force / scales.length if kind == "stiffness" else scales.mass
    d = sp.diags(np.where(rotational, scales.length, 1.0))
    return sp.csr_matrix(factor * (d @ sp.csr_matrix(matrix, dtype=float) @ d))
