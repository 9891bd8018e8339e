"""Hand model of the library's landing gear (loadcases/library/gear, plane x-z, mm in the
file, SI here): the closed-loop geometry by rotations about -y (loop closure solved with
fsolve from the design), the generalized force on the trunnion angle by virtual work, and
the free-body statics of the five bodies (15 linear equations). Independent of the engine:
no multipliers, no constraint equations of mechlib."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import fsolve

G = 9.81
KNOT = 1852.0 / 3600.0  # m/s
RHO, CDA = 1.225, 0.45  # kg/m^3, m^2
DOWNLOCK_K, DOWNLOCK_FREE = 2.0e4, 0.444065  # N/m, free length m (tension only)
PIN_RADIUS = 0.06  # m, trunnion friction
STOP_K, STOP_E = 2.0e6, 1.5  # knee stop: N*m/rad^1.5, exponent

TRUNNION, BRACE_TOP = np.array([0.0, 0.0]), np.array([0.9, -0.1])
KNEE, BRACE_LEG = np.array([0.412686, -0.344030]), np.array([0.0, -0.7])
ACT_TOP, ACT_PIN = np.array([-0.7, 0.0]), np.array([-0.15, -0.25])
AXIS = np.array([0.91036648, -0.41380294])  # act_slide, from act_top towards the pin
AXLE, LOCK_UP, LOCK_LOW = np.array([0.0, -1.8]), np.array([0.65, -0.12]), np.array([0.25, -0.41])
MASSES = {"leg": 180.0, "upper": 8.0, "lower": 7.0, "cylinder": 6.0, "rod": 3.0}  # kg
CMS = {
    "leg": np.array([0.0, -1.3]),
    "upper": np.array([0.656, -0.222]),
    "lower": np.array([0.206, -0.522]),
    "cylinder": np.array([-0.52, -0.082]),
    "rod": np.array([-0.3, -0.182]),
}


def turn(p: np.ndarray, centre: np.ndarray, angle: float) -> np.ndarray:
    """(x, z) point p turned by `angle` (rad) about -y around centre (+: x towards z)."""
    c, s = math.cos(angle), math.sin(angle)
    d = p - centre
    return centre + np.array([d[0] * c - d[1] * s, d[0] * s + d[1] * c])


@dataclass(frozen=True)
class Pose:
    """Angles (rad) about -y from design: leg `theta`, upper brace `alpha`, knee `knee`
    (lower brace relative to upper: the joint coordinate)."""

    theta: float
    alpha: float
    knee: float

    def lower(self, p: np.ndarray) -> np.ndarray:
        """A point of the lower brace: turned by alpha + knee about the knee, which moves."""
        return turn(p, KNEE, self.alpha + self.knee) + turn(KNEE, BRACE_TOP, self.alpha) - KNEE

    def actuator(self) -> tuple[float, float]:
        """(psi, stroke): the actuator line's turn about act_top (rad), its extension (m)."""
        pin, d0 = turn(ACT_PIN, TRUNNION, self.theta) - ACT_TOP, ACT_PIN - ACT_TOP
        psi = math.atan2(pin[1], pin[0]) - math.atan2(d0[1], d0[0])
        return psi, float(np.linalg.norm(pin) - np.linalg.norm(d0))

    def cm(self, body: str) -> np.ndarray:
        psi, stroke = self.actuator()
        p = CMS[body]
        if body == "leg":
            return turn(p, TRUNNION, self.theta)
        if body == "upper":
            return turn(p, BRACE_TOP, self.alpha)
        if body == "lower":
            return self.lower(p)
        if body == "cylinder":
            return turn(p, ACT_TOP, psi)
        return turn(p, ACT_TOP, psi) + stroke * turn(AXIS, np.zeros(2), psi)


def pose(theta: float | None = None, knee: float | None = None, guess=(0.0, 0.0)) -> Pose:
    """The assembled pose with the leg angle or the knee angle given (rad)."""

    def closure(u):
        p = Pose(theta if theta is not None else u[0], u[1], knee if knee is not None else u[0])
        return p.lower(BRACE_LEG) - turn(BRACE_LEG, TRUNNION, p.theta)

    u = fsolve(closure, guess, xtol=1e-12, full_output=True)[0]
    assert np.linalg.norm(closure(u)) < 1e-12, "the loop does not close"
    return Pose(theta if theta is not None else u[0], u[1], knee if knee is not None else u[0])


def retracted(theta: float, steps: int = 20) -> Pose:
    """The pose at leg angle theta (rad) on the branch of the design (continued from it in
    `steps` steps: fsolve from the design alone may find the mirrored brace)."""
    p = pose(0.0)
    for t in np.linspace(0.0, theta, steps + 1)[1:]:
        p = pose(float(t), guess=(p.knee, p.alpha))
    return p


def _lock_span(p: Pose) -> np.ndarray:
    """From the downlock spring's bracket on the upper brace to the lower one's, m."""
    return p.lower(LOCK_LOW) - turn(LOCK_UP, BRACE_TOP, p.alpha)


def spring(p: Pose) -> tuple[float, np.ndarray]:
    """(tension N, unit vector from lock_up towards lock_low) of the downlock spring."""
    d = _lock_span(p)
    length = float(np.linalg.norm(d))
    return max(DOWNLOCK_K * (length - DOWNLOCK_FREE), 0.0), d / length


def drag(airspeed: float, theta: float) -> float:
    """Drag at the axle, N (along -x, times cos theta as the file's expression)."""
    return 0.5 * RHO * airspeed**2 * CDA * math.cos(theta)


def _energy(p: Pose) -> float:
    """Gravitational potential (J) of the five bodies."""
    return sum(m * G * p.cm(b)[1] for b, m in MASSES.items())


def _moment(point: np.ndarray, force: np.ndarray) -> float:
    """Moment about -y of a force at a point (about the origin), N*m."""
    return float(point[0] * force[1] - point[1] * force[0])


def actuator_force(theta: float, airspeed: float, friction: float, h: float = 1e-4) -> float:
    """The actuator's force (N, along its travel, + extends) holding the gear at `theta`
    against gravity, drag, the downlock spring and a trunnion friction moment `friction`
    (N*m, resisting retraction), by virtual work: E ds + sum Q dtheta = 0 (central
    differences of the closed-form geometry, h rad)."""
    now = retracted(theta)
    plus, minus = (pose(theta + d, guess=(now.knee, now.alpha)) for d in (h, -h))
    ds = (plus.actuator()[1] - minus.actuator()[1]) / (2 * h)
    q = -(_energy(plus) - _energy(minus)) / (2 * h)
    axle = (turn(AXLE, TRUNNION, theta + h) - turn(AXLE, TRUNNION, theta - h)) / (2 * h)
    q -= drag(airspeed, theta) * axle[0]
    tension, _ = spring(now)
    length = [float(np.linalg.norm(_lock_span(p))) for p in (plus, minus)]
    q -= tension * (length[0] - length[1]) / (2 * h)
    return -(q - friction) / ds


_BODIES = ("leg", "upper", "lower", "cylinder", "rod")


def statics(p: Pose, airspeed: float, trunnion_moment: float = 0.0) -> dict[str, float]:
    """Free-body statics of the five bodies at pose p (actuator force 0; a moment on the
    leg about -y at the trunnion, N*m, such as a stuck bearing's friction):
    the knee stop's moment `stop` (N*m, on the lower brace, + opens the knee) and the
    magnitudes of the joint forces (N)."""
    rows = {b: 3 * i for i, b in enumerate(_BODIES)}
    a, rhs = np.zeros((15, 15)), np.zeros(15)

    def force(body: str, col: int, f: np.ndarray, at: np.ndarray) -> None:
        a[rows[body] : rows[body] + 2, col] += f
        a[rows[body] + 2, col] += _moment(at, f)

    def load(body: str, f: np.ndarray, at: np.ndarray) -> None:
        rhs[rows[body] : rows[body] + 2] -= f
        rhs[rows[body] + 2] -= _moment(at, f)

    psi, _ = p.actuator()
    pin = turn(ACT_PIN, TRUNNION, p.theta)
    pairs = {
        "trunnion": ("leg", None, TRUNNION),
        "brace_top": ("upper", None, BRACE_TOP),
        "knee": ("lower", "upper", turn(KNEE, BRACE_TOP, p.alpha)),
        "brace_leg": ("lower", "leg", turn(BRACE_LEG, TRUNNION, p.theta)),
        "act_base": ("cylinder", None, ACT_TOP),
        "act_pin": ("rod", "leg", pin),
    }
    for j, (b1, b2, at) in enumerate(pairs.values()):
        for k, unit in enumerate(np.eye(2)):
            force(b1, 2 * j + k, unit, at)
            if b2 is not None:
                force(b2, 2 * j + k, -unit, at)
    axis = turn(AXIS, np.zeros(2), psi)
    normal = np.array([-axis[1], axis[0]])
    force("rod", 12, normal, pin)  # act_slide: force normal to its axis, and a moment
    force("cylinder", 12, -normal, pin)
    a[rows["rod"] + 2, 13], a[rows["cylinder"] + 2, 13] = 1.0, -1.0
    a[rows["lower"] + 2, 14], a[rows["upper"] + 2, 14] = 1.0, -1.0  # knee stop
    for body, m in MASSES.items():
        load(body, np.array([0.0, -m * G]), p.cm(body))
    load("leg", np.array([-drag(airspeed, p.theta), 0.0]), turn(AXLE, TRUNNION, p.theta))
    tension, unit = spring(p)
    load("upper", tension * unit, turn(LOCK_UP, BRACE_TOP, p.alpha))
    load("lower", -tension * unit, p.lower(LOCK_LOW))
    rhs[rows["leg"] + 2] -= trunnion_moment
    x = np.linalg.solve(a, rhs)
    out = {name: float(np.hypot(x[2 * j], x[2 * j + 1])) for j, name in enumerate(pairs)}
    return out | {"stop": float(x[14])}


def locked(airspeed: float, trunnion_moment: float = 0.0) -> tuple[Pose, dict[str, float]]:
    """The gear resting on its knee stop: statics at the pose where the stop's moment
    k x^e holds the knee x rad past its stop (fixed point from the design)."""
    p = pose(knee=0.0)
    for _ in range(30):
        loads = statics(p, airspeed, trunnion_moment)
        x = (max(loads["stop"], 0.0) / STOP_K) ** (1.0 / STOP_E)
        p = pose(knee=-x, guess=(p.theta, p.alpha))
    return p, statics(p, airspeed, trunnion_moment)
