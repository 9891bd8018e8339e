"""Checks that the eigen-solvers after an import will work, made on the SI matrices before
any of them sees them (`loads flex check`'s free-free modes, the Craig-Bampton reduction):

- K positive semi-definite, with the six rigid-body modes of a free-free component;
- K and M positive definite on the interior DOF (the interface held): the constraint modes
  need K_ii^-1 and the fixed-interface modes the eigenproblem (K_ii, M_ii); a failure names
  the DOF that carries it;
- mass on the translations, and a translational mass of a mechanism part's scale;
- M positive definite off the rigid-body motions on the interface-reduced space (the
  constraint modes' basis): the free-free modes and the reduction's eigenproblem need it.

Each returns why the model fails, or None."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.checks import negative_pivots
from loadcases.flexible.summary import mass_properties, rigid_fields, rigid_modes
from mechlib.flexible.craig_bampton import ReductionError
from mechlib.flexible.craig_bampton import elastic_mass_problem as _guyan
from mechlib.flexible.fe_model import FEModel

__all__ = [
    "MASS_RANGE",
    "RIGID_BODY_MODES",
    "elastic_mass_problem",
    "interior_problem",
    "rigid_body_problem",
    "translation_mass_problem",
]

RIGID_BODY_MODES = 6  # of a free-free component in space
MASS_RANGE = (1e-9, 1e12)  # kg: translational mass of a mechanism part (1 ug to 1e9 t)
SINGULAR = 1e-12  # lowest eigenvalue of the matrix scaled to a unit diagonal, at least
_DENSE_LIMIT = 1500  # interior DOF up to which the lowest eigenvector is computed
_COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")


def _dof(model: FEModel, row: int) -> str:
    """`node 202 rz`: the node id and component of a DOF row."""
    node, component = model.dof_map[row]
    return f"node {model.node_ids[node]} {_COMPONENTS[component]}"


def interior_problem(model: FEModel, matrix: sp.spmatrix, what: str) -> str | None:
    """Why `matrix` (K or M) is not positive definite on the interior DOF (the interface
    nodes held), naming the DOF of a zero diagonal term or the largest term of the
    eigenvector of the lowest eigenvalue (scaled to a unit diagonal), or None."""
    interior = np.flatnonzero(~np.isin(model.dof_map[:, 0], model.interface))
    if interior.size == 0:
        return None
    sub = sp.csr_matrix(matrix)[interior][:, interior]
    diagonal = sub.diagonal()
    held = "with the interface nodes held"
    empty = np.flatnonzero(diagonal <= 0.0)
    if empty.size:
        return f"{what} is singular {held}: no term on {_dof(model, interior[empty[0]])}"
    scale = sp.diags(1.0 / np.sqrt(diagonal))
    scaled = scale @ sub @ scale
    if interior.size <= _DENSE_LIMIT:
        from scipy.linalg import eigh

        dense = scaled.toarray()
        values, vectors = eigh(0.5 * (dense + dense.T), subset_by_index=[0, 0])
        if values[0] >= SINGULAR:
            return None
        row = interior[int(np.argmax(np.abs(vectors[:, 0])))]
        return (
            f"{what} is singular {held} (lowest eigenvalue {values[0]:.3g} of the matrix scaled "
            f"to a unit diagonal), the deformation mostly on {_dof(model, row)}"
        )
    negative = negative_pivots(scaled - SINGULAR * sp.identity(interior.size))
    if not negative:  # None: off-diagonal pivots, no inertia to tell (the reduction says)
        return None
    return (
        f"{what} is not positive definite {held}: {negative} eigenvalues below {SINGULAR:g} "
        "of the matrix scaled to a unit diagonal"
    )


def rigid_body_problem(model: FEModel) -> str | None:
    """Why K does not leave the six rigid-body motions unloaded (a free-free component:
    a DOF constrained or a spring to ground in the FE model), or None."""
    found = rigid_modes(model)
    if found == RIGID_BODY_MODES:
        return None
    return (
        f"the stiffness matrix has {found} rigid-body modes where a free-free component has "
        f"{RIGID_BODY_MODES}: export it without constraints (SPC) or springs to ground"
    )


def translation_mass_problem(model: FEModel) -> str | None:
    """Why the translational mass (kg per direction) is absent or outside MASS_RANGE, or
    a rigid-body motion has no inertia (the 6 x 6 rigid-body mass matrix about the nodes'
    centroid, scaled to a unit diagonal, singular: a line of nodes without torsional
    inertia), or None."""
    mass = mass_properties(model).mass
    low, high = MASS_RANGE
    if not np.all(mass > 0.0):
        shown = ", ".join(f"{m:.3g}" for m in mass)
        return f"the mass matrix has no mass on translations ({shown} kg along x, y, z)"
    if not np.all((mass >= low) & (mass <= high)):
        return (
            f"the translational mass {np.max(mass):.3g} kg is outside {low:g}-{high:g} kg, "
            "the scale of a mechanism part: check the units of the header (and wtmass)"
        )
    return _rigid_inertia_problem(model)


_MOTIONS = ("x", "y", "z", "about x", "about y", "about z")


def _rigid_inertia_problem(model: FEModel) -> str | None:
    """Why a rigid-body motion (or a combination) has no kinetic energy, or None."""
    gamma, r0 = rigid_fields(model)
    centroid = np.mean(model.coordinates, axis=0)
    fields = np.hstack([gamma, r0 - gamma @ np.cross(np.eye(3), centroid).T])
    rigid = fields.T @ (sp.csr_matrix(model.mass) @ fields)
    diagonal = np.diag(rigid)
    if np.all(diagonal > 0.0):
        d = 1.0 / np.sqrt(diagonal)
        values, vectors = np.linalg.eigh(d[:, None] * rigid * d[None, :])
        if values[0] >= SINGULAR:
            return None
        worst = int(np.argmax(np.abs(vectors[:, 0])))
    else:
        worst = int(np.flatnonzero(diagonal <= 0.0)[0])
    motion = ("translation " if worst < 3 else "rotation ") + _MOTIONS[worst]
    return (
        f"the mass matrix gives the rigid-body {motion} no inertia: give the rotational "
        "inertia of the nodes (a line of nodes needs it about its axis)"
    )


def elastic_mass_problem(model: FEModel) -> str | None:
    """Why M is not positive definite off the six rigid-body motions on the interface DOF
    with the interior following them statically (Guyan), naming the DOF that moves most in
    a deformation without kinetic energy; or None (`craig_bampton.elastic_mass_problem`)."""
    try:
        return _guyan(model)
    except ReductionError as error:  # K with the interface held checked before: a safeguard
        return str(error)
