"""Exudyn's side of the flexible bench (issue 40): Kane's spin-up beam as an
`ObjectFFRFreducedOrder` carrying the same Craig-Bampton modes and the same inertia as the
`loads` model of `benchmarks.flexible` (without geometric stiffening: Exudyn's reduced FFRF
object has none, so the unstiffened beam is the like-for-like comparison).

The body's constant matrices come from the beam's own mass matrix and modes
(`benchmarks.ffrf_exudyn`): both codes integrate one kinetic energy, one modal stiffness,
one frame.

The hub holds the beam's root node. `loads` welds a massless node body to it (position
r_n = x + A (s + Phi zeta), orientation rows (A_n f).(A (g + theta x g)) = 0 with
theta = Phi* zeta) and drives that by its revolute. The same equations here: massless mesh
nodes at `ARM` from the root along x, y, z move as the root's section (Phi + Phi* x arm), so
their offsets from the root are ARM A (g + theta x g); the root sits at the hub's origin and
each arm node g in the hub's plane normal to f (`_weld`). The hub is a rigid body whose six
coordinates are held, the angle about z set before each step to the spin-up law. Exudyn's
own way, a `MarkerSuperElementRigid` welded to the hub (`joint="marker"`), takes the root's
rotation otherwise: converged (h = 1.25 ms), its tip lag is 2.8e-3 of the range from the
weld's and 2.4e-3 from `loads`'s, against 1.3e-3 between the weld and `loads`. All SI.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from benchmarks.ffrf_exudyn import (
    ARM,
    FFRFTerms,
    FlexRun,
    add_held_body,
    add_reduced_body,
    assembled,
    ffrf_terms,
    mesh_marker,
    node_modes,
)
from benchmarks.flexible import KANE_MODES, kane_beam
from mechlib.flexible.fe_model import FEModel

__all__ = ["ARMS", "build_kane_exudyn", "mesh", "run_kane_exudyn"]

#: the arm nodes' offsets from the root (m): +x, +y, +z (the weld's), then +-x, +-y, +-z
ARMS = ARM * np.vstack(
    [np.eye(3), np.repeat(np.eye(3), 2, axis=0) * np.tile([1.0, -1.0], 3)[:, None]]
)
TIP = 1 + len(ARMS)  # mesh node of the tip


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
    model = kane_beam()
    terms = ffrf_terms(model, KANE_MODES)
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

    sensor, settings = assembled(
        exu,
        mbs,
        SensorMarker(
            markerNumber=tip,
            outputVariableType=exu.OutputVariableType.Position,
            storeInternal=True,
            writeToFile=False,
        ),
        pre_step,
        step,
        end,
        output_step,
    )
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
