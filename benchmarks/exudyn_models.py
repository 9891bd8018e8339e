"""The benchmark models in Exudyn, built from the shared `benchmarks.models` specs.

Each body is an Exudyn `ObjectRigidBody` on a `NodeRigidBodyEP` node (Euler parameters, like
`loads`), its reference point at the centre of mass and its frame equal to the global frame at
the design position, so the inertia tensor of the spec is used as given. Joints:

| spec        | Exudyn                                                                |
|-------------|-----------------------------------------------------------------------|
| revolute    | `CreateRevoluteJoint` (ObjectJointRevoluteZ, 5 equations)             |
| spherical   | `CreateSphericalJoint` (ObjectJointSpherical, 3 equations)            |
| universal   | `CreateGenericJoint`, constrainedAxes [1,1,1,1,0,0] (4 equations:     |
|             | the joint-0 y axis stays perpendicular to the joint-1 z axis)         |
| prismatic   | `CreatePrismaticJoint` (ObjectJointPrismaticX, 5 equations)           |

The joint's marker 0 is on body 2 of the spec (the ground for ground joints) and marker 1 on
body 1, so joint outputs are in body-2 axes and joint rotations are those of body 1 relative to
body 2, as in SPEC 1.3.

A model with an `extension` (benchmarks.kinds) gets its force elements, events and other
contacts from that module's `extend_exudyn`, which may return a pre-step function (Exudyn's
`PreStepUserFunction`: called once before each step, for switching).

A sphere-plane contact (`ContactSpec`, the `hertz` law of `loads`) is Exudyn's native
`ObjectContactSphereSphere` between the ball and a ground sphere of radius GROUND_SPHERE_RADIUS
whose surface touches the plane at the plane point: for a ball that moves along the normal
through that point (the bouncing ball) its gap is exactly the plane's. Its Hunt-Crossley model
(`impactModel=1`), F = K x^n (1 + 3 (1 - e_HC) / 2 x' / x'(-)), is the Lankarani-Nikravesh law
F = K x^n (1 + 3 (1 - e^2) / 4 x' / x'(-)) of `loads` with e_HC = (1 + e^2) / 2
(`hunt_crossley_restitution`); the smallest remembered approach speed is 1 mm/s in both
codes. Exudyn remembers x'(-) at the end of the first step in contact, `loads` interpolates it
to the instant of touching: the difference vanishes with the step.

Time integration: Exudyn's implicit generalized-alpha (index 3, Euler-parameter nodes),
fixed steps `numberOfSteps = round(end / h)`, spectral radius 0.9 (Exudyn's default), modified
Newton with Exudyn's default tolerances, no solution file, sensors stored in memory.

`exudyn` is imported on first use only; `ExudynMissing` says how to install it.
"""

from __future__ import annotations

import importlib
import sys
import time
from dataclasses import dataclass, field
from types import ModuleType
from typing import Any, Literal

import numpy as np

from benchmarks.models import ModelSpec, consistent_velocities

__all__ = [
    "GROUND_SPHERE_RADIUS",
    "REACTION_SIGN",
    "ExudynMissing",
    "ExudynOptions",
    "ExudynRun",
    "build_system",
    "exudyn_version",
    "hunt_crossley_restitution",
    "import_exudyn",
    "run_exudyn",
]

LinearSolver = Literal["dense", "sparse"]

#: Exudyn's revolute-joint `ForceLocal` output (marker 0 on body 2, turned to ground axes with
#: the marker-0 rotation) is the force on body 2 from body 1 (checked against a hanging
#: pendulum in tests/benchmarks/test_models.py); SPEC 1.3
#: reports the reaction on body 1 from body 2, hence the sign.
REACTION_SIGN = -1.0

#: Radius (m) of the ground sphere that stands for a contact plane.
GROUND_SPHERE_RADIUS = 1.0

#: Smallest remembered approach speed (m/s), mechlib.elements.contact.laws.MIN_APPROACH_SPEED of
#: `loads`.
MIN_IMPACT_SPEED = 1.0e-3


def hunt_crossley_restitution(restitution: float) -> float:
    """Exudyn's Hunt-Crossley coefficient e_HC giving the Lankarani-Nikravesh damping of
    coefficient `restitution` e: 3 (1 - e_HC) / 2 = 3 (1 - e^2) / 4."""
    return 0.5 * (1.0 + restitution * restitution)


class ExudynMissing(ImportError):
    """Exudyn is not installed in this Python environment."""


_EXUDYN: ModuleType | None = None


def import_exudyn(fast: bool = True) -> ModuleType:
    """Import `exudyn` once and return it.

    `fast=True` asks for Exudyn's `exudynCPPfast` module (no range checks, AVX2; Exudyn falls
    back to the regular module where the CPU lacks AVX2). Only the first call decides.
    Raises ExudynMissing with the install command when the package is absent.
    """
    global _EXUDYN
    if _EXUDYN is not None:
        return _EXUDYN
    if fast and not hasattr(sys, "exudynFast"):
        sys.exudynFast = True  # type: ignore[attr-defined]
    try:
        import io
        from contextlib import redirect_stdout

        with redirect_stdout(io.StringIO()):  # Exudyn prints a note when it loads the fast module
            module = importlib.import_module("exudyn")
            importlib.import_module("exudyn.utilities")
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ExudynMissing(
            "the benchmark needs Exudyn, which is not installed: run "
            "`.venv/bin/pip install -e '.[bench]'` (or `.venv/bin/pip install exudyn`)"
        ) from exc
    _EXUDYN = module
    return module


def exudyn_version() -> str | None:
    """The installed Exudyn version, or None when Exudyn is missing (does not import it)."""
    try:
        from importlib.metadata import PackageNotFoundError, version

        return version("exudyn")
    except PackageNotFoundError:
        return None


def exudyn_module_name() -> str:
    """Which compiled Exudyn module was loaded (`exudynCPPfast` or `exudynCPP`)."""
    exu = import_exudyn()
    return str(getattr(exu, "_compiledModuleName", "exudynCPP"))


@dataclass(frozen=True)
class ExudynOptions:
    """Solver settings of one Exudyn run.

    `step` (s) is the fixed time step; `end` (s) the end time; `output_step` (s) the interval
    at which sensors are stored (None: every step); `spectral_radius` the generalized-alpha
    rho_infinity; `linear_solver` Exudyn's dense (EXUdense) or sparse (EigenSparse) solver;
    `check` adds sensors for energy and joint-point gaps (verification runs only, slower).
    """

    step: float
    end: float
    output_step: float | None = None
    spectral_radius: float = 0.9
    linear_solver: LinearSolver = "dense"
    check: bool = False


@dataclass
class ExudynRun:
    """What one Exudyn run produced.

    `time` (s) and `channels` (`REQUEST.COMPONENT` -> array, SI, `loads` conventions);
    `build_seconds` (wall, s) for creating the system and `Assemble`; `solve_seconds` (wall, s)
    for `SolveDynamic`; `steps` the number of time steps; `energy` (J, total mechanical energy
    at the stored times) and `joint_gap` (m, largest distance between the two bodies' copies
    of any joint point at the stored times) when `check` was set.
    """

    model: str
    options: ExudynOptions
    time: np.ndarray
    channels: dict[str, np.ndarray]
    build_seconds: float
    solve_seconds: float
    steps: int
    energy: np.ndarray | None = None
    joint_gap: np.ndarray | None = None
    info: dict[str, Any] = field(default_factory=dict)


@dataclass
class _Built:
    sc: Any
    mbs: Any
    settings: Any
    channel_sensors: dict[str, tuple[int, int, float, np.ndarray | None]]
    body_sensors: dict[str, tuple[int, int, int, int]]
    joint_point_sensors: list[tuple[str, int | None, int | None, np.ndarray, np.ndarray | None]]


def _add_contacts(mbs: Any, model: ModelSpec, bodies: dict[str, Any]) -> None:
    """Each sphere-plane contact as an ObjectContactSphereSphere against a ground sphere."""
    from exudyn.utilities import (  # type: ignore[import-not-found]
        MarkerBodyRigid,
        NodeGenericData,
        ObjectContactSphereSphere,
    )

    for c in model.contacts:
        normal = np.array(c.normal, dtype=float) / np.linalg.norm(c.normal)
        centre = np.array(c.plane_point, dtype=float) - GROUND_SPHERE_RADIUS * normal
        ball = np.array(c.center, dtype=float)
        gap = float((ball - np.array(c.plane_point)) @ normal) - c.radius
        m_ground = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies["ground"], localPosition=centre))
        local = ball - np.array(model.body(c.body).cm)
        m_ball = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[c.body], localPosition=local))
        data = mbs.AddNode(
            NodeGenericData(numberOfDataCoordinates=4, initialCoordinates=[gap, 0, 0, 0])
        )
        mbs.AddObject(
            ObjectContactSphereSphere(
                name=c.name,
                markerNumbers=[m_ground, m_ball],
                nodeNumber=data,
                spheresRadii=[GROUND_SPHERE_RADIUS, c.radius],
                contactStiffness=c.stiffness,
                contactStiffnessExponent=c.exponent,
                restitutionCoefficient=hunt_crossley_restitution(c.restitution),
                minimumImpactVelocity=MIN_IMPACT_SPEED,
                impactModel=1,
            )
        )


def _add_bodies(exu: ModuleType, mbs: Any, model: ModelSpec) -> dict[str, Any]:
    """The ground and each body (at its centre of mass, with the spec's consistent initial
    velocities); {name: body number}."""
    from exudyn.utilities import ObjectGround, RigidBodyInertia  # type: ignore[import-not-found]

    ground = mbs.AddObject(ObjectGround())
    velocities, omegas = consistent_velocities(model)
    bodies: dict[str, Any] = {"ground": ground}
    for i, b in enumerate(model.bodies):
        inertia = RigidBodyInertia(
            mass=b.mass, inertiaTensor=b.inertia_matrix, com=np.zeros(3), inertiaTensorAtCOM=True
        )
        bodies[b.name] = mbs.CreateRigidBody(
            name=b.name,
            referencePosition=list(b.cm),
            inertia=inertia,
            initialVelocity=[float(c) for c in velocities[i]],
            initialAngularVelocity=[float(c) for c in omegas[i]],
            gravity=list(model.gravity),
            nodeType=exu.NodeType.RotationEulerParameters,
            graphicsDataList=[],
            show=False,
        )
    return bodies


def _add_joint(mbs: Any, j: Any, bodies: dict[str, Any]) -> Any:
    """One joint of the spec (module notes: marker 0 on body 2, marker 1 on body 1)."""
    items = [bodies[j.bodies[1]], bodies[j.bodies[0]]]  # marker 0: body 2, marker 1: body 1
    at = [float(c) for c in j.at]
    if j.type == "revolute":
        return mbs.CreateRevoluteJoint(
            name=j.name, itemNumbers=items, position=at, axis=list(j.axis), show=False
        )
    if j.type == "spherical":
        return mbs.CreateSphericalJoint(name=j.name, itemNumbers=items, position=at, show=False)
    if j.type == "prismatic":
        return mbs.CreatePrismaticJoint(
            name=j.name, itemNumbers=items, position=at, axis=list(j.axis), show=False
        )
    if j.type == "universal":
        a1 = np.array(j.axes[0], dtype=float)  # fixed in body 1 = marker 1 (joint-1 z axis)
        a2 = np.array(j.axes[1], dtype=float)  # fixed in body 2 = marker 0 (joint-0 y axis)
        a1 /= np.linalg.norm(a1)
        a2 /= np.linalg.norm(a2)
        rot = np.column_stack([np.cross(a2, a1), a2, a1])
        return mbs.CreateGenericJoint(
            name=j.name,
            itemNumbers=items,
            position=at,
            rotationMatrixAxes=rot,
            constrainedAxes=[1, 1, 1, 1, 0, 0],
            show=False,
        )
    raise ValueError(f"unsupported joint type {j.type}")  # pragma: no cover - a Literal


_AXIS_INDEX = {"x": 0, "y": 1, "z": 2, "fx": 0, "fy": 1, "fz": 2}


def _add_output_sensors(
    exu: ModuleType, mbs: Any, model: ModelSpec, bodies: dict[str, Any], joints: dict[str, Any]
) -> dict[str, tuple[int, int, float, np.ndarray | None]]:
    """A sensor per output of the spec: {column: (sensor, component, sign, rotation)}."""
    from exudyn.utilities import SensorBody, SensorObject  # type: ignore[import-not-found]

    ovt = exu.OutputVariableType
    channel_sensors: dict[str, tuple[int, int, float, np.ndarray | None]] = {}
    for out in model.outputs:
        if out.kind == "point_position":
            p = model.point(out.target)
            local = (np.array(p.at) - np.array(model.body(p.body).cm)).tolist()
            s = mbs.AddSensor(
                SensorBody(
                    bodyNumber=bodies[p.body],
                    localPosition=local,
                    outputVariableType=ovt.Position,
                    storeInternal=True,
                    writeToFile=False,
                )
            )
            channel_sensors[out.column] = (int(s), _AXIS_INDEX[out.component], 1.0, None)
        elif out.kind == "joint_force":
            s, rot = _joint_force_sensor(exu, mbs, model, out.target, joints)
            channel_sensors[out.column] = (s, _AXIS_INDEX[out.component], REACTION_SIGN, rot)
        elif out.kind == "joint_angle":
            s = mbs.AddSensor(
                SensorObject(
                    objectNumber=joints[out.target],
                    outputVariableType=ovt.Rotation,
                    storeInternal=True,
                    writeToFile=False,
                )
            )
            channel_sensors[out.column] = (int(s), 2, 1.0, None)
    return channel_sensors


def _joint_force_sensor(
    exu: ModuleType, mbs: Any, model: ModelSpec, name: str, joints: dict[str, Any]
) -> tuple[int, np.ndarray]:
    """The `ForceLocal` sensor of a ground joint and its marker-0 rotation to ground axes."""
    from exudyn.utilities import SensorObject  # type: ignore[import-not-found]

    joint = model.joint(name)
    if joint.bodies[1] != "ground":
        raise ValueError(
            f"{model.name}: a joint_force output needs a ground joint "
            f"(its marker 0 frame is then fixed), {joint.name} is not one"
        )
    marker0 = mbs.GetObject(joints[name])["markerNumbers"][0]
    rot = np.array(mbs.GetMarker(marker0)["localHT"], dtype=float)[:3, :3]
    s = mbs.AddSensor(
        SensorObject(
            objectNumber=joints[name],
            outputVariableType=exu.OutputVariableType.ForceLocal,
            storeInternal=True,
            writeToFile=False,
        )
    )
    return int(s), rot


def _add_body_check_sensors(
    exu: ModuleType, mbs: Any, model: ModelSpec, bodies: dict[str, Any]
) -> dict[str, tuple[int, int, int, int]]:
    """Position, velocity, angular velocity and rotation sensors of each body (energy)."""
    from exudyn.utilities import SensorBody  # type: ignore[import-not-found]

    ovt = exu.OutputVariableType
    body_sensors: dict[str, tuple[int, int, int, int]] = {}
    for b in model.bodies:
        ids = tuple(
            int(
                mbs.AddSensor(
                    SensorBody(
                        bodyNumber=bodies[b.name],
                        outputVariableType=v,
                        storeInternal=True,
                        writeToFile=False,
                    )
                )
            )
            for v in (ovt.Position, ovt.Velocity, ovt.AngularVelocity, ovt.RotationMatrix)
        )
        body_sensors[b.name] = ids  # type: ignore[assignment]
    return body_sensors


def _add_joint_check_sensors(
    exu: ModuleType, mbs: Any, model: ModelSpec, bodies: dict[str, Any]
) -> list[tuple[str, int | None, int | None, np.ndarray, np.ndarray | None]]:
    """Each joint's point on both of its bodies (None: the ground) and, for a prismatic
    joint, its sliding axis: (joint, sensor 1, sensor 2, point, axis), for the gap check."""
    from exudyn.utilities import SensorBody  # type: ignore[import-not-found]

    joint_point_sensors: list[
        tuple[str, int | None, int | None, np.ndarray, np.ndarray | None]
    ] = []
    for j in model.joints:
        ids: list[int | None] = []
        for name in j.bodies:
            if name == "ground":
                ids.append(None)
                continue
            local = (np.array(j.at) - np.array(model.body(name).cm)).tolist()
            sensor = SensorBody(
                bodyNumber=bodies[name],
                localPosition=local,
                outputVariableType=exu.OutputVariableType.Position,
                storeInternal=True,
                writeToFile=False,
            )
            ids.append(int(mbs.AddSensor(sensor)))
        slide = None
        if j.type == "prismatic":
            if j.bodies[1] != "ground":
                raise ValueError(f"{model.name}: the gap check of {j.name} needs body 2 = ground")
            slide = np.array(j.axis, dtype=float) / np.linalg.norm(j.axis)
        joint_point_sensors.append((j.name, ids[0], ids[1], np.array(j.at, dtype=float), slide))
    return joint_point_sensors


def _settings(exu: ModuleType, model: ModelSpec, options: ExudynOptions) -> Any:
    """Exudyn's simulation settings for `options` (fixed steps of generalized-alpha)."""
    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    ti.numberOfSteps = round(options.end / options.step)
    ti.endTime = options.end
    ti.verboseMode = 0
    ti.generalizedAlpha.spectralRadius = options.spectral_radius
    ti.generalizedAlpha.computeInitialAccelerations = True
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = (
        options.step if options.output_step is None else options.output_step
    )
    if model.contacts or model.extension is not None:
        # Exudyn's step recommended at a contact switch drives the step to its 1e-8 s minimum
        # and aborts on this stiff contact (1.13.6): fixed steps, as for the jointed models
        ti.discontinuous.useRecommendedStepSize = False
    settings.show.statistics = False
    settings.show.computationTime = False
    settings.linearSolver.solverType = (
        exu.LinearSolverType.EXUdense
        if options.linear_solver == "dense"
        else exu.LinearSolverType.EigenSparse
    )
    return settings


def build_system(model: ModelSpec, options: ExudynOptions) -> _Built:
    """Create the Exudyn system of `model` with the sensors its outputs need, and assemble it."""
    exu = import_exudyn()
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    bodies = _add_bodies(exu, mbs, model)
    _add_contacts(mbs, model, bodies)
    joints = {j.name: _add_joint(mbs, j, bodies) for j in model.joints}
    if model.extension is not None:  # the kinds' force elements, events, other contacts
        extend = importlib.import_module(model.extension).extend_exudyn
        pre_step = extend(exu, mbs, bodies, joints, options.step)
        if pre_step is not None:
            mbs.SetPreStepUserFunction(pre_step)
    channel_sensors = _add_output_sensors(exu, mbs, model, bodies, joints)
    body_sensors: dict[str, tuple[int, int, int, int]] = {}
    joint_point_sensors: list[
        tuple[str, int | None, int | None, np.ndarray, np.ndarray | None]
    ] = []
    if options.check:
        body_sensors = _add_body_check_sensors(exu, mbs, model, bodies)
        joint_point_sensors = _add_joint_check_sensors(exu, mbs, model, bodies)
    mbs.Assemble()
    settings = _settings(exu, model, options)
    return _Built(sc, mbs, settings, channel_sensors, body_sensors, joint_point_sensors)


def _energy(model: ModelSpec, built: _Built) -> np.ndarray:
    """Total mechanical energy (J) at the stored sensor times."""
    total = None
    g = np.array(model.gravity)
    for b in model.bodies:
        sp, sv, sw, sr = built.body_sensors[b.name]
        pos = built.mbs.GetSensorStoredData(sp)[:, 1:4]
        vel = built.mbs.GetSensorStoredData(sv)[:, 1:4]
        omg = built.mbs.GetSensorStoredData(sw)[:, 1:4]
        rot = built.mbs.GetSensorStoredData(sr)[:, 1:10].reshape(-1, 3, 3)
        inertia = np.einsum("nij,jk,nlk->nil", rot, b.inertia_matrix, rot)
        kinetic = 0.5 * b.mass * np.sum(vel * vel, axis=1) + 0.5 * np.einsum(
            "ni,nij,nj->n", omg, inertia, omg
        )
        potential = -b.mass * pos @ g
        e = kinetic + potential
        total = e if total is None else total + e
    assert total is not None
    return total


def _joint_gap(built: _Built) -> np.ndarray:
    """Largest joint-point gap (m) over all joints, at the stored sensor times.

    For a prismatic joint (body 2 = ground) only the gap across the sliding axis counts; a
    model without joints (the bouncing ball) has none: zeros.
    """
    if not built.joint_point_sensors:
        first = next(iter(built.body_sensors.values()))[0]
        return np.zeros(len(built.mbs.GetSensorStoredData(first)))
    gap = None
    for _name, s1, s2, at, slide in built.joint_point_sensors:
        p1 = built.mbs.GetSensorStoredData(s1)[:, 1:4] if s1 is not None else at[None, :]
        p2 = built.mbs.GetSensorStoredData(s2)[:, 1:4] if s2 is not None else at[None, :]
        diff = p1 - p2
        if slide is not None:
            diff = diff - np.outer(diff @ slide, slide)
        d = np.linalg.norm(diff, axis=1)
        gap = d if gap is None else np.maximum(gap, d)
    assert gap is not None
    return gap


def run_exudyn(model: ModelSpec, options: ExudynOptions) -> ExudynRun:
    """Build and solve `model` with `options`; wall times measured with time.perf_counter.

    `build_seconds` covers creating the items and `Assemble`; `solve_seconds` covers
    `SolveDynamic` alone (initial accelerations included), `info["solve_cpu_seconds"]` its
    process CPU time. Channels follow `loads`
    conventions (joint reactions on body 1 from body 2, ground axes).
    """
    exu = import_exudyn()
    t0 = time.perf_counter()
    built = build_system(model, options)
    t1, cpu = time.perf_counter(), time.process_time()
    try:
        ok = built.mbs.SolveDynamic(built.settings)
    except RuntimeError as exc:  # Exudyn's SolverError (aborted run) is one
        raise RuntimeError(
            f"Exudyn failed to solve {model.name} with step {options.step} s"
        ) from exc
    t2, cpu = time.perf_counter(), time.process_time() - cpu
    if ok is False:
        raise RuntimeError(f"Exudyn failed to solve {model.name} with step {options.step} s")
    channels: dict[str, np.ndarray] = {}
    times: np.ndarray | None = None
    for column, (sensor, component, sign, rot) in built.channel_sensors.items():
        data = np.asarray(built.mbs.GetSensorStoredData(sensor))
        if times is None:
            times = data[:, 0].copy()
        values = data[:, 1:4] @ rot.T if rot is not None else data[:, 1:]
        channels[column] = sign * values[:, component]
    assert times is not None
    run = ExudynRun(
        model=model.name,
        options=options,
        time=times,
        channels=channels,
        build_seconds=t1 - t0,
        solve_seconds=t2 - t1,
        steps=int(built.settings.timeIntegration.numberOfSteps),
    )
    stats = built.mbs.sys.get("dynamicSolver") if hasattr(built.mbs, "sys") else None
    if stats is not None and hasattr(stats, "it"):
        run.info["newton_iterations"] = int(stats.it.newtonStepsCount)
    if options.check:
        run.energy = _energy(model, built)
        run.joint_gap = _joint_gap(built)
    run.info["solve_cpu_seconds"] = cpu  # process CPU time of SolveDynamic
    run.info["exudyn_module"] = str(getattr(exu, "_compiledModuleName", "exudynCPP"))
    return run
