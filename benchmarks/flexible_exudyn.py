"""Exudyn's side of the flexible bench (issue 40): Kane's spin-up beam as an
`ObjectFFRFreducedOrder` carrying the same Craig-Bampton modes and the same inertia as the
`loads` model of `benchmarks.flexible` (without geometric stiffening: Exudyn's reduced FFRF
object has none, so the unstiffened beam is the like-for-like comparison).

The reduced object's constant matrices are Zwoelfer and Gerstmayr's (Exudyn's
`ObjectFFRFreducedOrderInterface`): with M the FE mass matrix, Phit the translation field,
xRefTilde the rigid-rotation field and PsiTilde_j the rotation field of mode j's
translations, mPsiTildePsi = PsiTilde^T M Psi, and so on. Exudyn builds them for 3-DOF nodes;
here they come from the beam's own consistent mass matrix, whose rotational DOF enter the
fields as in `mechlib.flexible.invariants` (xRefTilde = -R0, PsiTilde_j = -R_j: rotation rows
I and 0). So both codes integrate one kinetic energy, one modal stiffness, one frame (the
centre of mass, modes orthogonal to rigid motion).

The hub holds the beam's root node. `loads` welds a massless node body to it (position
r_n = x + A (s + Phi zeta), orientation rows (A_n f).(A (g + theta x g)) = 0 with
theta = Phi* zeta) and drives that by its revolute. The same equations here: massless mesh
nodes at `ARM` from the root along x, y, z move as the root's section (Phi + Phi* x arm), so
their offsets from the root are ARM A (g + theta x g); the root sits at the hub's origin and
each arm node g in the hub's plane normal to f (`_weld`). The hub is a rigid body whose six
coordinates are held, the angle about z set before each step to the spin-up law. Exudyn's
own way, a `MarkerSuperElementRigid` welded to the hub (`joint="marker"`), takes the root's
rotation otherwise: converged (h = 1.25 ms), its tip lag is 2.8e-3 of the range from the
weld's and 2.4e-3 from `loads`'s, against 1.3e-3 between the weld and `loads`. The
helpers (`ffrf_terms`, `add_reduced_body`, `add_held_body`, `mesh_marker`,
`solver_settings`) build the flexible slider-crank too (`benchmarks.flexible_exudyn_crank`).
All SI.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechlib.flexible.beam import Material, Section, assemble_beams
from mechlib.flexible.craig_bampton import free_modes
from mechlib.flexible.fe_model import FEModel

__all__ = [
    "ARM",
    "FFRFTerms",
    "FlexRun",
    "add_held_body",
    "add_reduced_body",
    "build_kane_exudyn",
    "ffrf_terms",
    "kane_beam_model",
    "mesh_marker",
    "node_modes",
    "run_kane_exudyn",
    "solver_settings",
]

ARM = 0.05  # m, distance of the root's orientation nodes from the root
#: the arm nodes' offsets from the root (m): +x, +y, +z (the weld's), then +-x, +-y, +-z
ARMS = ARM * np.vstack(
    [np.eye(3), np.repeat(np.eye(3), 2, axis=0) * np.tile([1.0, -1.0], 3)[:, None]]
)
TIP = 1 + len(ARMS)  # mesh node of the tip
LENGTH, ELEMENTS, MODES = 10.0, 6, 4  # m, beam elements, Craig-Bampton modes (as loads's)


def kane_beam_model() -> FEModel:
    """The FE beam of `benchmarks.flexible.spin_up_beam`: 10 m, E I = 1.4e4 N m^2,
    rho A = 1.2 kg/m, 6 elements, root node 0 the interface."""
    xyz = np.outer(np.linspace(0.0, LENGTH, ELEMENTS + 1), [1.0, 0.0, 0.0])
    section = Section(4e-4, 2e-7, 2e-7, 4e-7, None, None)
    aluminium = Material(7e10, 0.3, 3000.0)
    beams = [(i, i + 1, section, aluminium, (0.0, 1.0, 0.0)) for i in range(ELEMENTS)]
    return assemble_beams(xyz, beams, interface=(0,))


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


def ffrf_terms(model: FEModel, modes: int = MODES) -> FFRFTerms:
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


def mesh(model: FEModel, terms: FFRFTerms) -> tuple[np.ndarray, np.ndarray]:
    """(reference positions (k, 3) m from the frame origin, mode basis (3 k, n)) of the mesh
    nodes the joints and the output use: the root, the root's three arm nodes (+ARM along
    x, y, z, moved as the root's rigid section: Phi + Phi* x arm), six more arm nodes at
    +-ARM (the rigid marker's), then the tip. Massless: the inertia is in `terms`."""
    root, tip = 0, len(model.coordinates) - 1
    u_root, rot_root = node_modes(model, terms.psi, root)
    positions, basis = [model.coordinates[root] - terms.origin], [u_root]
    for arm in ARMS:
        positions.append(model.coordinates[root] - terms.origin + arm)
        basis.append(u_root + np.cross(rot_root.T, arm).T)
    positions.append(model.coordinates[tip] - terms.origin)
    basis.append(node_modes(model, terms.psi, tip)[0])
    return np.array(positions), np.vstack(basis)


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


def _add_hub(mbs: Any) -> tuple[int, int]:
    """A rigid hub at the origin, its six coordinates held (the angle about z driven; its
    mass is moot: its motion is prescribed); returns (its rigid marker, the angle's
    constraint)."""
    from exudyn.utilities import MarkerNodeRigid

    node, _, held = add_held_body(mbs, (0.0, 0.0, 0.0), tuple(range(6)))
    return mbs.AddMarker(MarkerNodeRigid(nodeNumber=node)), held[5]


def _weld(mbs: Any, body: int, hub: int) -> None:
    """`loads`'s weld and revolute equations, exactly: the root node at the hub's origin
    (spherical joint) and, for (f, g) = (y, z), (z, x), (x, y), the arm node g of the root
    kept in the hub's plane normal to f. Exudyn's generic joint takes rigid markers only, so
    each arm node carries a massless slider held to the hub's axes and free in that plane."""
    from exudyn.utilities import (
        MarkerNodeRigid,
        NodeRigidBodyEP,
        ObjectJointGeneric,
        ObjectJointSpherical,
        ObjectRigidBody,
    )

    mbs.AddObject(ObjectJointSpherical(markerNumbers=[hub, mesh_marker(mbs, body, 0)]))
    for f, g in ((1, 2), (2, 0), (0, 1)):
        slider = mbs.AddNode(NodeRigidBodyEP(referenceCoordinates=[*ARMS[g], 1.0, 0.0, 0.0, 0.0]))
        mbs.AddObject(ObjectRigidBody(nodeNumber=slider, mass=0.0, inertia=[0.0] * 6))
        marker = mbs.AddMarker(MarkerNodeRigid(nodeNumber=slider))
        mbs.AddObject(ObjectJointSpherical(markerNumbers=[marker, mesh_marker(mbs, body, 1 + g)]))
        axes = [0, 0, 0, 1, 1, 1]
        axes[f] = 1
        mbs.AddObject(ObjectJointGeneric(markerNumbers=[hub, marker], constrainedAxes=axes))


def _rigid_marker(mbs: Any, body: int, hub: int) -> None:
    """Exudyn's own way: a `MarkerSuperElementRigid` on the six +-ARM nodes (their
    linearised rotation) welded to the hub by a generic joint; converged, the tip lag
    differs from the weld's by 2.8e-3 of its range (measured 2026-11-29)."""
    from exudyn.utilities import MarkerSuperElementRigid, ObjectJointGeneric

    root = mbs.AddMarker(
        MarkerSuperElementRigid(
            bodyNumber=body,
            offset=[0.0, 0.0, 0.0],
            meshNodeNumbers=list(range(4, 10)),
            weightingFactors=[1.0 / 6.0] * 6,
            useAlternativeApproach=True,
            rotationsExponentialMap=0,
        )
    )
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[hub, root], constrainedAxes=[1] * 6))


@dataclass
class KaneSystem:
    """The assembled Exudyn system: container, system, the tip sensor, the hub angle's
    constraint, settings (fixed steps)."""

    container: Any
    mbs: Any
    sensor: int
    angle: int
    settings: Any


def build_kane_exudyn(
    step: float, end: float = 20.0, output_step: float = 0.1, joint: str = "weld"
) -> KaneSystem:
    """Kane's unstiffened spin-up beam in Exudyn, assembled, with generalized-alpha settings
    (spectral radius 0.9, index 3, sparse solver: the suite's) at the fixed `step` (s);
    `joint` "weld" (`loads`'s equations, `_weld`) or "marker" (`_rigid_marker`)."""
    from exudyn.utilities import SensorMarker

    from benchmarks.exudyn_models import import_exudyn
    from benchmarks.flexible import SpinUp

    exu = import_exudyn()
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    model = kane_beam_model()
    terms = ffrf_terms(model)
    body = add_reduced_body(exu, mbs, terms, mesh(model, terms))
    tip = mesh_marker(mbs, body, TIP)
    hub, angle = _add_hub(mbs)
    (_weld if joint == "weld" else _rigid_marker)(mbs, body, hub)
    spin = SpinUp()

    def pre_step(mbs_: Any, t: float) -> bool:
        # Exudyn passes the time of the step's end (measured: with t + step the hub led
        # by one step, a lag error proportional to the step)
        mbs_.SetObjectParameter(angle, "offset", spin.value(t))
        return True

    mbs.SetPreStepUserFunction(pre_step)
    sensor = mbs.AddSensor(
        SensorMarker(
            markerNumber=tip,
            outputVariableType=exu.OutputVariableType.Position,
            storeInternal=True,
            writeToFile=False,
        )
    )
    mbs.Assemble()
    settings = solver_settings(exu, step, end, output_step)
    return KaneSystem(sc, mbs, sensor, angle, settings)


def run_kane_exudyn(
    step: float, end: float = 20.0, output_step: float = 0.1, joint: str = "weld"
) -> FlexRun:
    """Solve `build_kane_exudyn`; the tip's lag (m) in the hub frame at the output times."""
    from benchmarks.flexible import SpinUp

    built = build_kane_exudyn(step, end, output_step, joint)
    cpu = time.process_time()
    ok = built.mbs.SolveDynamic(built.settings)
    cpu = time.process_time() - cpu
    if ok is False:
        raise RuntimeError(f"Exudyn failed on Kane's beam with step {step} s")
    data = np.asarray(built.mbs.GetSensorStoredData(built.sensor))
    spin = SpinUp()
    hub = np.array([spin.value(x) for x in data[:, 0]])
    lag = -np.sin(hub) * data[:, 1] + np.cos(hub) * data[:, 2]
    steps = int(built.settings.timeIntegration.numberOfSteps)
    return FlexRun(time=data[:, 0], signal=lag, cpu_seconds=cpu, steps=steps)
