"""Exudyn's reduced flexible body from a `loads` modal component, and the pieces the
flexible bench models share in Exudyn (issue 40; `benchmarks.flexible_exudyn`,
`benchmarks.flexible_exudyn_crank`).

The reduced object's constant matrices are Zwoelfer and Gerstmayr's (Exudyn's
`ObjectFFRFreducedOrderInterface`): with M the FE mass matrix, Phit the translation field,
xRefTilde the rigid-rotation field and PsiTilde_j the rotation field of mode j's
translations, mPsiTildePsi = PsiTilde^T M Psi, and so on. Exudyn builds them for 3-DOF nodes;
here they come from the beam's own consistent mass matrix, whose rotational DOF enter the
fields as in `mechlib.flexible.invariants` (xRefTilde = -R0, PsiTilde_j = -R_j: rotation rows
I and 0). So both codes integrate one kinetic energy, one modal stiffness, one frame (the
centre of mass, modes orthogonal to rigid motion). Mesh nodes are massless (the inertia is
in the matrices): they only place markers. All SI.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mechlib.flexible.craig_bampton import free_modes
from mechlib.flexible.fe_model import FEModel

__all__ = [
    "ARM",
    "FFRFTerms",
    "FlexRun",
    "add_held_body",
    "add_reduced_body",
    "ffrf_terms",
    "mesh_marker",
    "node_modes",
    "solver_settings",
]

ARM = 0.05  # m, distance of a node's orientation (arm) nodes from the node


@dataclass(frozen=True)
class FFRFTerms:
    """The constant matrices of Exudyn's ObjectFFRFreducedOrder (SI, mass-normalised
    modes): `mass` kg, `inertia` (3, 3) kg m^2 and `center_of_mass` (3,) m about the frame
    origin `origin` (3,) m in the FE model's axes; the rest as Exudyn names them;
    `omega` (n,) rad/s the modes' frequencies, `psi` (ndof, n) the modes."""

    origin: np.ndarray
    mass: float
    inertia: np.ndarray
    center_of_mass: np.ndarray
    mass_reduced: np.ndarray
    stiffness_reduced: np.ndarray
    m_psi_tilde_psi: np.ndarray
    m_psi_tilde_psi_tilde: np.ndarray
    m_phit_t_psi: np.ndarray
    m_phit_t_psi_tilde: np.ndarray
    m_xref_tilde_psi: np.ndarray
    m_xref_tilde_psi_tilde: np.ndarray
    omega: np.ndarray
    psi: np.ndarray

    def as_exudyn(self) -> dict[str, Any]:
        """The keyword arguments of ObjectFFRFreducedOrder they set."""
        return {
            "mass": self.mass,
            "inertia": self.inertia,
            "centerOfMass": self.center_of_mass,
            "mPsiTildePsi": self.m_psi_tilde_psi,
            "mPsiTildePsiTilde": self.m_psi_tilde_psi_tilde,
            "mPhitTPsi": self.m_phit_t_psi,
            "mPhitTPsiTilde": self.m_phit_t_psi_tilde,
            "mXRefTildePsi": self.m_xref_tilde_psi,
            "mXRefTildePsiTilde": self.m_xref_tilde_psi_tilde,
        }


def ffrf_terms(model: FEModel, modes: int) -> FFRFTerms:
    """Exudyn's reduced-FFRF matrices of `model`'s lowest `modes` Craig-Bampton modes
    (`loads`'s reduction, `modes` fixed-interface modes), frame at the centre of mass."""
    omega, psi = free_modes(model, modes)
    omega, psi = omega[:modes], psi[:, :modes]
    mass, origin, _ = model.rigid_properties()
    m = model.mass
    phit = model.translation_field()
    xref_tilde = -model.skew_field(model.coordinates - origin, rotations=True)
    nodes, trans = model.dof_map[:, 0], model.dof_map[:, 1] < 3
    psi_tilde = np.zeros((len(model.dof_map), 3 * modes))
    for j in range(modes):
        shape = np.zeros((len(model.node_ids), 3))
        shape[nodes[trans], model.dof_map[trans, 1]] = psi[trans, j]
        psi_tilde[:, 3 * j : 3 * j + 3] = -model.skew_field(shape, rotations=False)
    m_psi, m_psi_tilde = m @ psi, m @ psi_tilde
    first = phit.T @ (m @ xref_tilde)  # m skew(c): c about the origin
    return FFRFTerms(
        origin=origin,
        mass=mass,
        inertia=xref_tilde.T @ (m @ xref_tilde),
        center_of_mass=np.array([first[2, 1], first[0, 2], first[1, 0]]) / mass,
        mass_reduced=psi.T @ m_psi,
        stiffness_reduced=psi.T @ (model.stiffness @ psi),
        m_psi_tilde_psi=psi_tilde.T @ m_psi,
        m_psi_tilde_psi_tilde=psi_tilde.T @ m_psi_tilde,
        m_phit_t_psi=phit.T @ m_psi,
        m_phit_t_psi_tilde=phit.T @ m_psi_tilde,
        m_xref_tilde_psi=xref_tilde.T @ m_psi,
        m_xref_tilde_psi_tilde=xref_tilde.T @ m_psi_tilde,
        omega=omega,
        psi=psi,
    )


def node_modes(model: FEModel, psi: np.ndarray, node: int) -> tuple[np.ndarray, np.ndarray]:
    """(translations (3, n), rotations (3, n)) of `psi` at FE node index `node`."""
    out = np.zeros((6, psi.shape[1]))
    for dof in np.flatnonzero(model.dof_map[:, 0] == node):
        out[model.dof_map[dof, 1]] = psi[dof]
    return out[:3], out[3:]


@dataclass
class FlexRun:
    """One Exudyn run: output times (s), the compared signal (m: Kane's tip lag in the hub
    frame, the slider-crank's slider x), CPU s of SolveDynamic, steps."""

    time: np.ndarray
    signal: np.ndarray
    cpu_seconds: float
    steps: int


def add_reduced_body(
    exu: Any,
    mbs: Any,
    terms: FFRFTerms,
    mesh_nodes: tuple[np.ndarray, np.ndarray],
    velocity: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> int:
    """Add the ObjectFFRFreducedOrder of `terms` with `mesh_nodes` (reference positions
    (k, 3) m from the frame origin, mode basis (3 k, n)), its frame moving at `velocity`
    (m/s) and at rest otherwise; returns the object."""
    from exudyn.utilities import (
        NodeGenericODE2,
        NodeRigidBodyEP,
        ObjectFFRFreducedOrder,
        VObjectFFRFreducedOrder,
    )

    n = len(terms.omega)
    frame = mbs.AddNode(
        NodeRigidBodyEP(
            referenceCoordinates=[*terms.origin, 1.0, 0.0, 0.0, 0.0],
            initialVelocities=[*velocity, 0.0, 0.0, 0.0, 0.0],
        )
    )
    modal = mbs.AddNode(
        NodeGenericODE2(
            numberOfODE2Coordinates=n,
            referenceCoordinates=[0.0] * n,
            initialCoordinates=[0.0] * n,
            initialCoordinates_t=[0.0] * n,
        )
    )
    positions, basis = mesh_nodes
    stiffness, mass = exu.MatrixContainer(), exu.MatrixContainer()
    stiffness.SetWithDenseMatrix(terms.stiffness_reduced, useDenseMatrix=False)
    mass.SetWithDenseMatrix(terms.mass_reduced, useDenseMatrix=False)
    return int(
        mbs.AddObject(
            ObjectFFRFreducedOrder(
                nodeNumbers=[frame, modal],
                massMatrixReduced=mass,
                stiffnessMatrixReduced=stiffness,
                modeBasis=basis,
                referencePositions=positions.ravel(),
                computeFFRFterms=True,
                visualization=VObjectFFRFreducedOrder(show=False),
                **terms.as_exudyn(),
            )
        )
    )


def mesh_marker(mbs: Any, body: int, node: int) -> int:
    """A position marker on mesh node `node` of the reduced body `body`."""
    from exudyn.utilities import MarkerSuperElementPosition

    return int(
        mbs.AddMarker(
            MarkerSuperElementPosition(
                bodyNumber=body, meshNodeNumbers=[node], weightingFactors=[1.0]
            )
        )
    )


def assembled(
    exu: Any, mbs: Any, sensor: Any, pre_step: Any, step: float, end: float, output_step: float
) -> tuple[int, Any]:
    """Set the pre-step function (it receives the time of the step's end: a driven offset
    set for t + step led by one step), add `sensor` (an Exudyn sensor item), assemble;
    (sensor number, solver_settings)."""
    mbs.SetPreStepUserFunction(pre_step)
    number = mbs.AddSensor(sensor)
    mbs.Assemble()
    return number, solver_settings(exu, step, end, output_step)


def solver_settings(exu: Any, step: float, end: float, output_step: float) -> Any:
    """Generalized-alpha (spectral radius 0.9, index 3, sparse solver: the suite's
    settings) at the fixed `step` (s) to `end` (s), sensors every `output_step` (s)."""
    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    ti.numberOfSteps = round(end / step)
    ti.endTime = end
    ti.verboseMode = 0
    ti.generalizedAlpha.spectralRadius = 0.9
    ti.generalizedAlpha.computeInitialAccelerations = True
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = output_step
    settings.show.statistics = False
    settings.show.computationTime = False
    settings.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    return settings


def add_held_body(
    mbs: Any,
    position: Any,
    held: tuple[int, ...],
    velocity: tuple[float, ...] = (0.0,) * 6,
    mass: float = 1.0,
    inertia: tuple[float, ...] = (1.0, 1.0, 1.0),
) -> tuple[int, int, list[int]]:
    """A rigid body (node [x, y, z, rx, ry, rz], at `position` m, rates `velocity`, `mass` kg,
    principal `inertia` kg m^2) whose coordinates `held` are tied to the ground by
    coordinate constraints (their offsets drive them); returns (node, body, constraints)."""
    from exudyn.utilities import (
        MarkerNodeCoordinate,
        NodePointGround,
        NodeRigidBodyRxyz,
        ObjectConnectorCoordinate,
        ObjectRigidBody,
    )

    node = mbs.AddNode(
        NodeRigidBodyRxyz(
            referenceCoordinates=[*position, 0.0, 0.0, 0.0], initialVelocities=list(velocity)
        )
    )
    body = mbs.AddObject(ObjectRigidBody(nodeNumber=node, mass=mass, inertia=[*inertia, 0, 0, 0]))
    fixed = mbs.AddNode(NodePointGround())
    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=fixed, coordinate=0))
    constraints = []
    for c in held:
        coordinate = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=c))
        constraints.append(
            mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[ground, coordinate]))
        )
    return int(node), int(body), constraints
