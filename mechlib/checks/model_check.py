"""The checks of a model before solving: redundant equations and degrees of freedom at the
design position, by joint and direction (`check_model`, `inspect_mechanism`).

Apart from `mechlib.solve` and its steppers: `loads validate` runs these checks without
loading the solvers or SciPy's linear algebra.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechlib.core.outcome import ModelError
from mechlib.kinematics.kin import Kin
from mechlib.linalg.rank import degrees_of_freedom, find_redundant
from mechlib.linalg.sparse_rows import SparseRows
from mechlib.model.analysis import Dynamic, Kinematic, Modes, Phases, QuasiStatic, Static
from mechlib.model.mechanism import Mechanism
from mechlib.system.planar import make_system, out_of_plane_rows
from mechlib.system.system import System

__all__ = ["MechanismCheck", "check_model", "inspect_mechanism"]

Analysis = Kinematic | Static | QuasiStatic | Dynamic | Modes | Phases


def _jacobian(system: System, k: Kin) -> SparseRows:
    """The constraint Jacobian at `k` as its non-zeros (a 3-D system never builds the
    dense matrix; a planar one reduces its dense rows)."""
    return system.phi_q_sparse(k)


def _redundant(system: System, jac: SparseRows) -> list:
    """The dependent equations of the constraint Jacobian `jac`, named joint by joint."""
    return find_redundant(
        jac, system.labels, system.owners, set(system.body_names), owner_rank=system.owner_rank
    )


def _redundant_in_plane(system: System, k: Kin, found: list) -> list:
    """`found` less the redundant equations out of the plane of a planar mechanism built
    in 3-D (flexible bodies), which are dropped: the planar formulation has none."""
    idle = out_of_plane_rows(system, k)
    if not any(r.row in idle for r in found):
        return found
    system.drop_rows(sorted(r.row for r in found if r.row in idle))
    return _redundant(system, _jacobian(system, k))


def check_model(system: System, analysis: Analysis, *, redundant: str = "error") -> list[str]:
    """Redundant equations and degrees of freedom, before any solving.

    Raises ModelError naming joints and directions; with redundant="drop" removes the
    dependent rows instead and returns warnings saying those reactions are not unique. A
    planar mechanism built in 3-D (flexible bodies) first drops, without a word, the
    redundant equations out of its plane: the planar formulation has none of them.
    """
    if isinstance(analysis, Modes) and system.mechanism.plane:
        raise ModelError([("", "a modes analysis needs the 3-D model: remove `plane`")])
    k = system.kin(system.design_q(), None, getattr(analysis, "start", 0.0))
    jac = _jacobian(system, k)
    found = _redundant_in_plane(system, k, _redundant(system, jac))
    warnings = []
    if found and redundant != "drop":
        raise ModelError([(r.owner, "redundant constraint: " + r.describe()) for r in found])
    if found:
        system.drop_rows([r.row for r in found])
        warnings = [
            f"redundant constraint dropped: {r.describe()}; the reactions of "
            f"{', '.join((r.owner,) + r.depends_on)} are not unique"
            for r in found
        ]
    if isinstance(analysis, Kinematic):
        dof = degrees_of_freedom(_jacobian(system, k))
        if dof != 0:
            raise ModelError([("", _kinematic_dof_message(system, dof))])
    return warnings


def _kinematic_dof_message(system: System, dof: int) -> str:
    """Why a kinematic analysis cannot run: `dof` free coordinates after the motions, and
    which of them are the modes of flexible bodies (no motion can drive those)."""
    motions = ", ".join(system.mechanism.motions) or "none"
    text = (
        f"kinematic analysis needs 0 degrees of freedom after the motions ({motions}), "
        f"but the mechanism has {dof}"
    )
    if not system.flexible:
        return text + ": add motions or use a dynamic or quasi-static analysis"
    modal = ", ".join(f"{a.name} ({a.body.n})" for a in system.flexible)
    return (
        f"{text}, {system.nz} of them the modal coordinates of flexible bodies "
        f"[{modal}]: a flexible body deforms under its loads, which a kinematic analysis "
        "does not solve; use a quasi-static analysis (deflection under loads, inertia "
        "ignored) or a dynamic one, or switch the flexibility off (effects: {flexibility: false})"
    )


@dataclass(frozen=True)
class MechanismCheck:
    """What a mechanism is at its design position: sizes, mobility and redundancy."""

    bodies: int
    equations: int
    degrees_of_freedom: int
    redundant: tuple[str, ...]
    assembled: bool


def inspect_mechanism(mechanism: Mechanism) -> MechanismCheck:
    """Degrees of freedom and redundant equations (by joint and direction) at design."""
    system = make_system(mechanism)
    k = system.kin(system.design_q(), None, 0.0)
    found = _redundant_in_plane(system, k, _redundant(system, _jacobian(system, k)))
    jac = _jacobian(system, k)
    assembled = bool(np.abs(system.phi(k)).max(initial=0.0) < 1e-9)
    return MechanismCheck(
        system.nb,
        len(system.labels) - system.normalisations,
        degrees_of_freedom(jac),
        tuple(r.describe() for r in found),
        assembled,
    )
