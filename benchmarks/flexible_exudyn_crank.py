"""Exudyn's side of the flexible slider-crank (issue 40): the rod of `benchmarks.flexible`
(34 Craig-Bampton modes held at both ends, 460 Hz to 40 kHz, no damping) as an
`ObjectFFRFreducedOrder` with `loads`'s modes and inertia (`benchmarks.flexible_exudyn`).

Joints as `loads` writes them. A: the crank, a rigid body whose six coordinates are held,
its angle about z set before each step to 150 t. B: the rod's node 0 at the crank pin
(spherical). C: the rod's node 20 at the slider (spherical) and the universal's row
(A_n z).(A_s y) = 0 on the node's orientation A_n; `loads` welds a massless node body to the
rod there (orientation rows (A_n f).(A (g + theta x g)) = 0), so here a massless rigid body
does the same through three massless sliders at the arm nodes (as the Kane beam's weld),
and a fourth slider at ARM along its z axis keeps that point in the slider's plane normal
to y. D: the slider, its coordinates but x held. The run starts at the design position with
the crank at 150 rad/s, the rod and the slider translating at -22.5 m/s along x and the
modes at rest (the rigid motion meets every joint). Output: the slider's x (m). All SI.
"""

from __future__ import annotations

import time
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
from benchmarks.flexible import CRANK_PIN, CRANK_SPEED, ROD_MODES, SLIDER_PIN, slider_crank_rod

__all__ = ["rod_mesh", "run_crank_exudyn"]

#: the rod and the slider's velocity at t = 0 (m/s): the crank pin's, omega x CRANK_PIN
START_VELOCITY = (-CRANK_SPEED * CRANK_PIN[1], 0.0, 0.0)


def rod_mesh(terms: FFRFTerms) -> tuple[np.ndarray, np.ndarray]:
    """(reference positions (5, 3) m from the frame origin, mode basis (15, n)) of the mesh
    nodes: the rod's node 0, its node 20, then node 20's arm nodes (+ARM along x, y, z)."""
    model = slider_crank_rod()
    last = len(model.coordinates) - 1
    u_0 = node_modes(model, terms.psi, 0)[0]
    u_c, rot_c = node_modes(model, terms.psi, last)
    arms = ARM * np.eye(3)
    positions = [CRANK_PIN - terms.origin, SLIDER_PIN - terms.origin]
    positions += [SLIDER_PIN - terms.origin + arm for arm in arms]
    basis = [u_0, u_c] + [u_c + np.cross(rot_c.T, arm).T for arm in arms]
    return np.array(positions), np.vstack(basis)


def _massless(mbs: Any, at: Any) -> tuple[int, int]:
    """A massless rigid body at `at` (m) moving at START_VELOCITY: (body, rigid marker)."""
    from exudyn.utilities import MarkerNodeRigid, NodeRigidBodyEP, ObjectRigidBody

    node = mbs.AddNode(
        NodeRigidBodyEP(
            referenceCoordinates=[*at, 1.0, 0.0, 0.0, 0.0],
            initialVelocities=[*START_VELOCITY, 0.0, 0.0, 0.0, 0.0],
        )
    )
    body = mbs.AddObject(ObjectRigidBody(nodeNumber=node, mass=0.0, inertia=[0.0] * 6))
    return int(body), int(mbs.AddMarker(MarkerNodeRigid(nodeNumber=node)))


def _slide(mbs: Any, frame: int, point: int, at: Any, axis: int) -> None:
    """Keep position marker `point` (starting at `at`) in the plane through rigid marker
    `frame` normal to its axis `axis`: a massless slider turning with `frame`."""
    from exudyn.utilities import ObjectJointGeneric, ObjectJointSpherical

    _, slider = _massless(mbs, at)
    mbs.AddObject(ObjectJointSpherical(markerNumbers=[slider, point]))
    axes = [0, 0, 0, 1, 1, 1]
    axes[axis] = 1
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[frame, slider], constrainedAxes=axes))


def _universal(mbs: Any, rod: int, slider: int) -> None:
    """Joint C: the rod's node 20 at the slider, its node body's z normal to the slider's y."""
    from exudyn.utilities import MarkerBodyPosition, ObjectJointSpherical

    mbs.AddObject(ObjectJointSpherical(markerNumbers=[slider, mesh_marker(mbs, rod, 1)]))
    node_body, node = _massless(mbs, SLIDER_PIN)
    mbs.AddObject(ObjectJointSpherical(markerNumbers=[node, mesh_marker(mbs, rod, 1)]))
    for f, g in ((1, 2), (2, 0), (0, 1)):  # the weld's rows
        _slide(mbs, node, mesh_marker(mbs, rod, 2 + g), SLIDER_PIN + ARM * np.eye(3)[g], f)
    z_point = mbs.AddMarker(MarkerBodyPosition(bodyNumber=node_body, localPosition=[0, 0, ARM]))
    _slide(mbs, slider, z_point, SLIDER_PIN + ARM * np.eye(3)[2], 1)


def run_crank_exudyn(step: float, end: float = 0.1, output_step: float = 1e-3) -> FlexRun:
    """The flexible slider-crank in Exudyn at the fixed `step` (s): output times (s), the
    slider's x (m), CPU s of SolveDynamic, steps."""
    from exudyn.utilities import (
        MarkerBodyPosition,
        MarkerNodeRigid,
        ObjectJointSpherical,
        SensorNode,
    )

    from benchmarks.exudyn_models import import_exudyn

    exu = import_exudyn()
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    terms = ffrf_terms(slider_crank_rod(), ROD_MODES)
    rod = add_reduced_body(exu, mbs, terms, rod_mesh(terms), START_VELOCITY)
    # the crank's mass is moot: its motion is prescribed
    _, crank, held = add_held_body(
        mbs, (0.0, 0.0, 0.0), tuple(range(6)), (0, 0, 0, 0, 0, CRANK_SPEED), 0.38, (7.1e-4,) * 3
    )
    pin = mbs.AddMarker(MarkerBodyPosition(bodyNumber=crank, localPosition=list(CRANK_PIN)))
    mbs.AddObject(ObjectJointSpherical(markerNumbers=[pin, mesh_marker(mbs, rod, 0)]))
    slider_node, _, _ = add_held_body(
        mbs, SLIDER_PIN, (1, 2, 3, 4, 5), (*START_VELOCITY, 0, 0, 0), 0.76, (1e-4,) * 3
    )
    _universal(mbs, rod, mbs.AddMarker(MarkerNodeRigid(nodeNumber=slider_node)))

    def pre_step(mbs_: Any, t: float) -> bool:
        mbs_.SetObjectParameter(held[5], "offset", CRANK_SPEED * t)  # t: the step's end
        return True

    sensor, settings = assembled(
        exu,
        mbs,
        SensorNode(
            nodeNumber=slider_node,
            outputVariableType=exu.OutputVariableType.Position,
            storeInternal=True,
            writeToFile=False,
        ),
        pre_step,
        step,
        end,
        output_step,
    )
    cpu = time.process_time()
    ok = mbs.SolveDynamic(settings)
    cpu = time.process_time() - cpu
    if ok is False:
        raise RuntimeError(f"Exudyn failed on the flexible slider-crank with step {step} s")
    data = np.asarray(mbs.GetSensorStoredData(sensor))
    steps = int(settings.timeIntegration.numberOfSteps)
    return FlexRun(time=data[:, 0], signal=data[:, 1], cpu_seconds=cpu, steps=steps)
