"""The three benchmark mechanisms as plain data, shared by the Exudyn and the `loads` side.

Every model is one `ModelSpec`: rigid bodies (mass, centre of mass and inertia tensor in the
global frame at the design position), joints (`revolute`, `spherical`, `universal`,
`prismatic`, with the SPEC 1.2 meaning of `bodies`, `at`, `axis` and `axes`), named points,
gravity, the initial state and the requests that the benchmark compares. From one spec,
`benchmarks.exudyn_models` builds the Exudyn system and `benchmarks.cases` writes the `loads`
case file, so both codes integrate the same equations of motion.

All quantities are SI: m, kg, kg*m^2, s, rad, rad/s, m/s^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

__all__ = [
    "JOINT_EQUATIONS",
    "BodySpec",
    "ContactSpec",
    "JointSpec",
    "ModelSpec",
    "OutputSpec",
    "PointSpec",
    "all_models",
    "chain",
    "chain20",
    "chain100",
    "consistent_velocities",
    "constraint_velocity_jacobian",
    "degrees_of_freedom",
    "fourbar10",
    "model_by_name",
    "slider_crank",
]

JointType = Literal["revolute", "spherical", "universal", "prismatic"]

#: Number of constraint equations of each joint type in 3D.
JOINT_EQUATIONS: dict[str, int] = {"revolute": 5, "spherical": 3, "universal": 4, "prismatic": 5}

GRAVITY = 9.81  # m/s^2


@dataclass(frozen=True)
class BodySpec:
    """A rigid body at the design position.

    `cm` is the centre of mass (m, global); `inertia` the 3x3 inertia tensor about the centre
    of mass in global axes at the design position (kg*m^2); the body frame coincides with the
    global frame at the design position.
    """

    name: str
    mass: float
    cm: tuple[float, float, float]
    inertia: tuple[tuple[float, float, float], ...]

    @property
    def inertia_matrix(self) -> np.ndarray:
        """The inertia tensor as a (3, 3) array, kg*m^2."""
        return np.array(self.inertia, dtype=float)

    def inertia_list(self) -> list[float]:
        """`[Ixx, Iyy, Izz, Ixy, Ixz, Iyz]` tensor entries (kg*m^2), as SPEC 1.2 writes them."""
        i = self.inertia_matrix
        return [
            float(i[0, 0]),
            float(i[1, 1]),
            float(i[2, 2]),
            float(i[0, 1]),
            float(i[0, 2]),
            float(i[1, 2]),
        ]


@dataclass(frozen=True)
class JointSpec:
    """A joint between `bodies[0]` (body 1) and `bodies[1]` (body 2; may be `ground`).

    `at` is the joint point (m, global); `axis` the revolute / prismatic axis; `axes` the two
    universal-joint axes, the first fixed in body 1, the second in body 2 (unit vectors,
    global at the design position).
    """

    name: str
    type: JointType
    bodies: tuple[str, str]
    at: tuple[float, float, float]
    axis: tuple[float, float, float] | None = None
    axes: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None


@dataclass(frozen=True)
class PointSpec:
    """A named point fixed on a body, at global position `at` (m) at the design position."""

    name: str
    body: str
    at: tuple[float, float, float]


@dataclass(frozen=True)
class ContactSpec:
    """A sphere fixed on `body` against a plane fixed to the ground (`sphere_plane`).

    `center` and `radius` (m) place the sphere at the design position, `plane_point` and
    `normal` the plane (the unit normal points from the ground towards the body). Normal
    force: Hertz with Lankarani-Nikravesh damping, F = K x^n (1 + 3 (1 - e^2) / 4 x' / x'(-))
    (x penetration, m; x' its rate; x'(-) its rate when the contact began), `stiffness` K
    (N/m^n), `exponent` n, `restitution` e; no friction.
    """

    name: str
    body: str
    center: tuple[float, float, float]
    radius: float
    plane_point: tuple[float, float, float]
    normal: tuple[float, float, float]
    stiffness: float
    exponent: float
    restitution: float


@dataclass(frozen=True)
class OutputSpec:
    """A requested result channel.

    `request` and `component` form the `loads` column name `REQUEST.COMPONENT`; `kind` says
    what is measured: `point_position` (m, global; `component` x, y or z), `joint_force` (N,
    reaction on body 1 from body 2 in ground axes; fx, fy or fz) or `joint_angle` (rad).
    `target` names the point or the joint.
    """

    request: str
    component: str
    kind: Literal["point_position", "joint_force", "joint_angle"]
    target: str

    @property
    def column(self) -> str:
        """The `loads` result column name."""
        return f"{self.request}.{self.component}"


@dataclass(frozen=True)
class ModelSpec:
    """One benchmark model.

    `initial_rate` gives `(joint, rate)`: the rate (rad/s) of a revolute joint at t = 0; every
    other velocity follows from the constraints (None: the system starts at rest).
    `main` lists the columns whose error against the reference decides the accuracy;
    `secondary` the columns also compared, for information. `end` is the simulated time (s),
    `quick_end` the shorter one of `--quick`, `output_step` the output interval (s).
    `contacts` lists the sphere-plane contacts (none in the jointed models).
    `initial_velocity` gives `(body, cm velocity m/s)` pairs of a model without joints that
    does not start at rest. `extension` names a module of `benchmarks.kinds` that adds what
    the rigid spec cannot say (force elements, events, other contacts) to both codes.
    """

    name: str
    title: str
    bodies: tuple[BodySpec, ...]
    joints: tuple[JointSpec, ...]
    points: tuple[PointSpec, ...]
    gravity: tuple[float, float, float]
    end: float
    quick_end: float
    output_step: float
    outputs: tuple[OutputSpec, ...]
    main: tuple[str, ...]
    secondary: tuple[str, ...] = ()
    contacts: tuple[ContactSpec, ...] = ()
    initial_rate: tuple[str, float] | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)
    initial_velocity: tuple[tuple[str, tuple[float, float, float]], ...] = ()
    extension: str | None = None

    def body(self, name: str) -> BodySpec:
        """The body called `name`."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)

    def joint(self, name: str) -> JointSpec:
        """The joint called `name`."""
        for j in self.joints:
            if j.name == name:
                return j
        raise KeyError(name)

    def point(self, name: str) -> PointSpec:
        """The point called `name`."""
        for p in self.points:
            if p.name == name:
                return p
        raise KeyError(name)

    def output(self, column: str) -> OutputSpec:
        """The output whose `loads` column is `column`."""
        for o in self.outputs:
            if o.column == column:
                return o
        raise KeyError(column)


def _diag(a: float, b: float, c: float) -> tuple[tuple[float, float, float], ...]:
    return ((a, 0.0, 0.0), (0.0, b, 0.0), (0.0, 0.0, c))


def _vec(v: np.ndarray | list[float] | tuple[float, ...]) -> tuple[float, float, float]:
    x, y, z = (float(c) for c in v)
    return (x, y, z)


def _rotated_inertia(local: np.ndarray, rot: np.ndarray) -> tuple[tuple[float, float, float], ...]:
    """`rot @ local @ rot.T` with round-off below 1e-18 kg*m^2 set to zero, as nested tuples."""
    g = rot @ local @ rot.T
    g[np.abs(g) < 1e-18] = 0.0
    g = 0.5 * (g + g.T)
    return tuple(_vec(row) for row in g)


# --------------------------------------------------------------------------------------
# a. slider-crank of SPEC 1.2
# --------------------------------------------------------------------------------------
def slider_crank() -> ModelSpec:
    """The SPEC 1.2 slider-crank (crank 100 mm, rod 300 mm), free motion under gravity.

    Bodies (SI): crank 1.2 kg, cm (0.05, 0, 0), inertia diag(1e-4, 1e-3, 1e-3); rod 0.8 kg,
    cm (0.25, 0, 0), diag(1e-4, 6e-3, 6e-3); slider 2.0 kg, cm (0.4, 0, 0), diag(1e-3)*3.
    Joints: pivot revolute crank-ground at 0 about z; big spherical rod-crank at (0.1, 0, 0);
    small universal slider-rod at (0.4, 0, 0), axes z (slider), y (rod); guide prismatic
    slider-ground along x. Gravity -9.81 m/s^2 along y. The design position is the outer dead
    centre; at t = 0 the crank turns at 2*pi rad/s with no drive, 1 s simulated.
    """
    bodies = (
        BodySpec("crank", 1.2, (0.05, 0.0, 0.0), _diag(1e-4, 1e-3, 1e-3)),
        BodySpec("rod", 0.8, (0.25, 0.0, 0.0), _diag(1e-4, 6e-3, 6e-3)),
        BodySpec("slider", 2.0, (0.4, 0.0, 0.0), _diag(1e-3, 1e-3, 1e-3)),
    )
    joints = (
        JointSpec("pivot", "revolute", ("crank", "ground"), (0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)),
        JointSpec("big", "spherical", ("rod", "crank"), (0.1, 0.0, 0.0)),
        JointSpec(
            "small",
            "universal",
            ("slider", "rod"),
            (0.4, 0.0, 0.0),
            axes=((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
        ),
        JointSpec(
            "guide", "prismatic", ("slider", "ground"), (0.4, 0.0, 0.0), axis=(1.0, 0.0, 0.0)
        ),
    )
    points = (
        PointSpec("crank_pin", "crank", (0.1, 0.0, 0.0)),
        PointSpec("slider_c", "slider", (0.4, 0.0, 0.0)),
    )
    outputs = (
        OutputSpec("slider_pos", "x", "point_position", "slider_c"),
        OutputSpec("pivot_force", "fx", "joint_force", "pivot"),
        OutputSpec("pivot_force", "fy", "joint_force", "pivot"),
    )
    return ModelSpec(
        name="slider_crank",
        title="slider-crank (SPEC 1.2), free, 1 s",
        bodies=bodies,
        joints=joints,
        points=points,
        gravity=(0.0, -GRAVITY, 0.0),
        end=1.0,
        quick_end=0.25,
        output_step=1e-3,
        outputs=outputs,
        main=("slider_pos.x",),
        secondary=("pivot_force.fx", "pivot_force.fy"),
        initial_rate=("pivot", 2.0 * math.pi),
        notes=("3 bodies, 17 constraint equations, 1 DOF",),
    )


# --------------------------------------------------------------------------------------
# b. spatial chains of N links (chain20, chain100; the scaling study's chain<N>)
# --------------------------------------------------------------------------------------
CHAIN_LINKS = 20  # links of chain20
CHAIN_LENGTH = 0.1  # m, each link
CHAIN_MASS = 0.1  # kg, each link
CHAIN_I_AXIAL = 1.25e-6  # kg*m^2, about the link axis (rod of radius 5 mm)
CHAIN_I_TRANSVERSE = 8.4e-5  # kg*m^2, about a transverse axis through the cm (~ m L^2 / 12)
CHAIN_BEND = 0.02  # rad, heading change from one link to the next in the horizontal plane
CHAIN100_END = 2.0  # s, simulated time of chain100


def chain_joint_points(links: int = CHAIN_LINKS) -> np.ndarray:
    """The links + 1 joint points (m) of the chain: a horizontal arc in the x-z plane from the
    origin, each link 0.1 m long and turned 0.02 rad about y from the one before."""
    pts = np.zeros((links + 1, 3))
    for i in range(links):
        phi = CHAIN_BEND * i
        pts[i + 1] = pts[i] + CHAIN_LENGTH * np.array([math.cos(phi), 0.0, math.sin(phi)])
    return pts


def chain(links: int, end: float = 2.0, quick_end: float = 0.5) -> ModelSpec:
    """`links` slender links (0.1 m, 0.1 kg) joined by spherical joints, released at rest.

    The chain lies in the horizontal plane y = 0 along a gentle arc (each link turned by
    0.02 rad about y from the previous one, the first along +x), so it falls under gravity
    (-y) out of any single vertical plane: a spatial motion. Link inertia about its cm:
    1.25e-6 kg*m^2 about its own axis, 8.4e-5 kg*m^2 across. Spherical joint `s0` holds link
    0 to the ground at the origin, `s<i>` joins link i to link i-1; 3 * links DOF. Output:
    the free end `tip`. `end` and `quick_end` (s) are the simulated times of the suite.
    """
    pts = chain_joint_points(links)
    local = np.diag([CHAIN_I_AXIAL, CHAIN_I_TRANSVERSE, CHAIN_I_TRANSVERSE])
    bodies = []
    joints = []
    for i in range(links):
        phi = CHAIN_BEND * i
        c, s = math.cos(phi), math.sin(phi)
        # columns: link axis (cos, 0, sin), global y, and their cross product
        rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
        cm = 0.5 * (pts[i] + pts[i + 1])
        bodies.append(BodySpec(f"link{i}", CHAIN_MASS, _vec(cm), _rotated_inertia(local, rot)))
        other = "ground" if i == 0 else f"link{i - 1}"
        joints.append(JointSpec(f"s{i}", "spherical", (f"link{i}", other), _vec(pts[i])))
    points = (PointSpec("tip", f"link{links - 1}", _vec(pts[-1])),)
    outputs = tuple(OutputSpec("tip", c, "point_position", "tip") for c in ("x", "y", "z"))
    return ModelSpec(
        name=f"chain{links}",
        title=f"{links}-link spatial chain, spherical joints, {end:g} s",
        bodies=tuple(bodies),
        joints=tuple(joints),
        points=points,
        gravity=(0.0, -GRAVITY, 0.0),
        end=end,
        quick_end=quick_end,
        output_step=5e-3,
        outputs=outputs,
        main=("tip.x", "tip.y", "tip.z"),
        notes=(f"{links} bodies, {3 * links} constraint equations, {3 * links} DOF",),
    )


def chain20() -> ModelSpec:
    """chain(20), 2 s simulated: the chain swings down, its tip whips past the bottom at about
    0.65 s and again at about 1.95 s. Beyond about 3 s the whips amplify any difference
    (halving the step changes the tip path by 1e-2 of its range at 4 s): no step size gives
    a 1e-4 answer there, so the benchmark stops at 2 s, where Exudyn's solution converges at
    second order.
    """
    return chain(CHAIN_LINKS, end=2.0, quick_end=0.5)


def chain100() -> ModelSpec:
    """chain(100): 100 links, 10 m of chain along a 2 rad arc, 300 DOF, CHAIN100_END s: the
    tip falls freely for about 1 s, then the chain swings down (the tip reaches 9.5 m below
    the pivot); Exudyn's runs converge at 2 s (halving 5e-4 s changes the tip path by 8e-5
    of its range)."""
    return chain(100, end=CHAIN100_END, quick_end=0.5)


# --------------------------------------------------------------------------------------
# c. ten four-bar loops in series
# --------------------------------------------------------------------------------------
FOURBAR_LOOPS = 10
FOURBAR_PITCH = 0.2  # m, between ground pivots
FOURBAR_LINK = 0.15  # m, pivot to the lower (input) point of a link
FOURBAR_OFFSET = 0.03  # m, x offset of a link's output point from its input point
FOURBAR_LINK_MASS = 0.2  # kg
FOURBAR_COUPLER_MASS = 0.1  # kg
FOURBAR_RATE = 2.0  # rad/s, initial rate of the first link


def fourbar10() -> ModelSpec:
    """Ten R-S-U-R four-bar loops in series: each loop's rocker is the next loop's crank.

    Eleven links hang from ground pivots G_k = (0.2 k, 0, 0), k = 0..10 (revolute `r<k>`,
    axis z), each a bar 0.15 m long along -y: 0.2 kg, cm G_k + (0, -0.075, 0), inertia
    diag(3.75e-4, 1e-5, 3.75e-4). Coupler k (0.1 kg, 0.17 m along x, inertia diag(5e-6,
    2.4e-4, 2.4e-4)) runs from the output point S_k = G_k + (0.03, -0.15, 0) of link k
    (spherical `s<k>`) to the input point U_{k+1} = G_{k+1} + (0, -0.15, 0) of link k+1
    (universal `u<k>`, axes z in the link and y in the coupler, which blocks the coupler's
    spin about its own line). Each loop: ground 0.2 m, crank 0.153 m, coupler 0.17 m, rocker
    0.15 m, not a parallelogram; 21 bodies, 11*5 + 10*3 + 10*4 = 125 equations for 126
    coordinates: exactly 1 DOF and no redundant equation. Link 0 starts at 2 rad/s; the
    mechanism swings under gravity for 10 s; output: the angle of `r10` (the last rocker).
    """
    bodies = []
    joints = []
    link_local = np.diag([3.75e-4, 1e-5, 3.75e-4])
    coupler_local = np.diag([5e-6, 2.4e-4, 2.4e-4])
    eye = np.eye(3)
    for k in range(FOURBAR_LOOPS + 1):
        g = np.array([FOURBAR_PITCH * k, 0.0, 0.0])
        bodies.append(
            BodySpec(
                f"link{k}",
                FOURBAR_LINK_MASS,
                _vec(g + [0.0, -FOURBAR_LINK / 2, 0.0]),
                _rotated_inertia(link_local, eye),
            )
        )
        joints.append(
            JointSpec(f"r{k}", "revolute", (f"link{k}", "ground"), _vec(g), axis=(0.0, 0.0, 1.0))
        )
    for k in range(FOURBAR_LOOPS):
        s = np.array([FOURBAR_PITCH * k + FOURBAR_OFFSET, -FOURBAR_LINK, 0.0])
        u = np.array([FOURBAR_PITCH * (k + 1), -FOURBAR_LINK, 0.0])
        bodies.append(
            BodySpec(
                f"coupler{k}",
                FOURBAR_COUPLER_MASS,
                _vec(0.5 * (s + u)),
                _rotated_inertia(coupler_local, eye),
            )
        )
        joints.append(JointSpec(f"s{k}", "spherical", (f"coupler{k}", f"link{k}"), _vec(s)))
        joints.append(
            JointSpec(
                f"u{k}",
                "universal",
                (f"link{k + 1}", f"coupler{k}"),
                _vec(u),
                axes=((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
            )
        )
    outputs = (OutputSpec("rocker_angle", "value", "joint_angle", f"r{FOURBAR_LOOPS}"),)
    return ModelSpec(
        name="fourbar10",
        title="10 four-bar loops in series (R-S-U-R), 10 s",
        bodies=tuple(bodies),
        joints=tuple(joints),
        points=(),
        gravity=(0.0, -GRAVITY, 0.0),
        end=10.0,
        quick_end=2.0,
        output_step=1e-2,
        outputs=outputs,
        main=("rocker_angle.value",),
        initial_rate=("r0", FOURBAR_RATE),
        notes=("21 bodies, 125 constraint equations, 1 DOF, no redundant equation",),
    )


def all_models() -> list[ModelSpec]:
    """The benchmark models, in the order the suite runs them."""
    from benchmarks.ball import ball_bounce  # the ball's module builds on this one

    return [slider_crank(), chain20(), fourbar10(), ball_bounce(), chain100()]


def model_by_name(name: str) -> ModelSpec:
    """The model called `name`: one of `all_models` (`slider_crank`, `chain20`, `fourbar10`,
    `ball_bounce`, `chain100`) or of `benchmarks.kinds.kind_models` (`loads bench --kinds`)."""
    from benchmarks.kinds import kind_models  # the kinds build on this module

    known = all_models() + kind_models()
    for m in known:
        if m.name == name:
            return m
    raise KeyError(f"unknown model {name!r}; known: {[m.name for m in known]}")


# --------------------------------------------------------------------------------------
# velocity-level constraints at the design position
# --------------------------------------------------------------------------------------
def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _perpendicular_pair(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a = a / np.linalg.norm(a)
    trial = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(a, trial)
    u /= np.linalg.norm(u)
    return u, np.cross(a, u)


def constraint_velocity_jacobian(model: ModelSpec) -> tuple[np.ndarray, list[str]]:
    """The velocity constraint matrix at the design position and a label per row.

    The unknowns are, per body in `model.bodies` order, the cm velocity (m/s) and the angular
    velocity (rad/s), both global: 6 per body. Row counts per joint follow JOINT_EQUATIONS.
    """
    index = {b.name: i for i, b in enumerate(model.bodies)}
    n = 6 * len(model.bodies)
    rows: list[np.ndarray] = []
    labels: list[str] = []

    def point_rows(body: str, at: np.ndarray, sign: float) -> np.ndarray:
        """3 x n block of `sign * (v_cm + omega x (at - cm))` of `body` (zero for ground)."""
        block = np.zeros((3, n))
        if body == "ground":
            return block
        i = index[body]
        r = at - np.array(model.body(body).cm)
        block[:, 6 * i : 6 * i + 3] = sign * np.eye(3)
        block[:, 6 * i + 3 : 6 * i + 6] = -sign * _skew(r)
        return block

    def omega_rows(body: str, sign: float) -> np.ndarray:
        block = np.zeros((3, n))
        if body != "ground":
            i = index[body]
            block[:, 6 * i + 3 : 6 * i + 6] = sign * np.eye(3)
        return block

    for j in model.joints:
        b1, b2 = j.bodies
        at = np.array(j.at)
        dv = point_rows(b1, at, 1.0) + point_rows(b2, at, -1.0)
        dw = omega_rows(b1, 1.0) + omega_rows(b2, -1.0)
        if j.type in ("revolute", "spherical", "universal"):
            rows.extend(dv)
            labels.extend(f"{j.name}: translation {c}" for c in "xyz")
        if j.type == "revolute":
            u, w = _perpendicular_pair(np.array(j.axis))
            rows.extend([u @ dw, w @ dw])
            labels.extend([f"{j.name}: rotation 1", f"{j.name}: rotation 2"])
        elif j.type == "universal":
            a1, a2 = (np.array(a) for a in j.axes)
            rows.append(np.cross(a1, a2) @ dw)
            labels.append(f"{j.name}: rotation")
        elif j.type == "prismatic":
            u, w = _perpendicular_pair(np.array(j.axis))
            rows.extend([u @ dv, w @ dv])
            rows.extend(dw)
            labels.extend([f"{j.name}: translation 1", f"{j.name}: translation 2"])
            labels.extend(f"{j.name}: rotation {c}" for c in "xyz")
    return np.array(rows).reshape(len(rows), n), labels


def degrees_of_freedom(model: ModelSpec) -> tuple[int, int]:
    """`(dof, redundant)`: mobility from the rank of the velocity constraints at the design
    position, and the number of redundant constraint equations."""
    jac, _ = constraint_velocity_jacobian(model)
    rank = int(np.linalg.matrix_rank(jac, tol=1e-10))
    return jac.shape[1] - rank, jac.shape[0] - rank


def consistent_velocities(model: ModelSpec) -> tuple[np.ndarray, np.ndarray]:
    """Cm velocities (m/s) and angular velocities (rad/s), shape (nb, 3) each, global axes,
    that satisfy the constraints and give the joint named in `model.initial_rate` its rate.

    Requires a mechanism with exactly one DOF when `initial_rate` is set; a model without
    `initial_rate` starts at rest, but for the cm velocities of `initial_velocity`.
    """
    nb = len(model.bodies)
    if model.initial_rate is None:
        velocities = np.zeros((nb, 3))
        names = [b.name for b in model.bodies]
        for body, v in model.initial_velocity:
            velocities[names.index(body)] = v
        return velocities, np.zeros((nb, 3))
    jac, _ = constraint_velocity_jacobian(model)
    name, rate = model.initial_rate
    joint = model.joint(name)
    if joint.type != "revolute":
        raise ValueError(f"initial_rate needs a revolute joint, {name} is {joint.type}")
    index = {b.name: i for i, b in enumerate(model.bodies)}
    drive = np.zeros(jac.shape[1])
    axis = np.array(joint.axis) / np.linalg.norm(joint.axis)
    for body, sign in zip(joint.bodies, (1.0, -1.0)):
        if body != "ground":
            drive[6 * index[body] + 3 : 6 * index[body] + 6] = sign * axis
    a = np.vstack([jac, drive])
    rhs = np.zeros(a.shape[0])
    rhs[-1] = rate
    sol, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    if np.linalg.norm(a @ sol - rhs) > 1e-9 * max(1.0, abs(rate)):
        raise ValueError(f"{model.name}: the initial rate of {name} contradicts the constraints")
    sol = sol.reshape(nb, 6)
    return sol[:, :3].copy(), sol[:, 3:].copy()
