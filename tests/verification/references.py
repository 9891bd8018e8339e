"""Independent reference solutions for the verification cases (plain NumPy/SciPy).

Nothing here imports the engine (`mechlib`, `loadcases`): every number is computed from a
textbook formula or from a separate, small integration, so that the verification tests compare
two independent computations. All inputs and outputs are SI (m, kg, s, N, rad, N*m).

Sources:
- [SM] J.L. Meriam, L.G. Kraige, *Engineering Mechanics: Dynamics*, ch. 5-6 (planar rigid-body
  kinematics and Newton-Euler equations; slider-crank and four-bar examples).
- [RS] R.L. Norton, *Design of Machinery*, ch. 4 & 11 (four-bar position analysis by loop
  closure, velocity ratios, dynamic/static force analysis, virtual work).
- [AS] M. Abramowitz, I. Stegun, *Handbook of Mathematical Functions*, 17.3 (complete elliptic
  integral K(m), m = k^2) and the large-amplitude pendulum period T = 4 sqrt(L/g) K(k^2).
- [GO] H. Goldstein, *Classical Mechanics*, 3rd ed., ch. 4-5 (Euler's equations of a rigid body
  about a fixed point; heavy symmetric top; quaternion kinematics qdot = q (x) (0, w)/2).
- Double pendulum of two rigid bars: Lagrange's equations, e.g. [SM] or any dynamics text.

Planar conventions used throughout: the plane is x-y, angles are about +z (right-hand rule),
`cross2(a, b) = a_x b_y - a_y b_x` is the z-component of a 3D cross product.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import ellipj, ellipk

__all__ = [
    "STANDARD_GRAVITY",
    "DoublePendulum",
    "FourBar",
    "FourBarPose",
    "HeavyTop",
    "HeavyTopSolution",
    "Pendulum",
    "SliderCrank",
    "SliderCrankKinematics",
    "SliderCrankLoads",
    "SpringBar",
    "all_warnings",
    "angular_velocity_from_points",
    "assert_within_peak",
    "channel",
    "cross2",
    "double_pendulum_energy",
    "double_pendulum_rhs",
    "double_pendulum_solve",
    "fourbar_drive_torque",
    "fourbar_pose",
    "fourbar_potential",
    "fourbar_static_loads",
    "fourbar_velocity_ratios",
    "heavy_top_energy",
    "heavy_top_solve",
    "heavy_top_vertical_momentum",
    "pendulum_bottom_reaction",
    "pendulum_hinge_reaction",
    "pendulum_period",
    "pendulum_rhs",
    "pendulum_small_angle_period",
    "slider_crank_energy",
    "slider_crank_kinematics",
    "slider_crank_loads",
    "spring_bar_equilibrium",
    "spring_bar_moment",
    "vector",
    "wrap_angle",
]

STANDARD_GRAVITY = 9.81
"""Gravity used by every verification case file (m/s^2)."""

FloatArray = NDArray[np.float64]


def cross2(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """z-component of a x b for planar vectors of shape (..., 2)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _perp(v: FloatArray) -> FloatArray:
    """e_z x v for planar vectors (..., 2): v rotated by +90 deg."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


# --------------------------------------------------------------------------------------------
# Slider-crank (SPEC 1.2): crank on a revolute at the origin about +z, rod from the crank pin to
# the slider, slider on a prismatic along x; gravity -y. [SM] 5/6 and 6/6 (general plane motion).
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SliderCrank:
    """Slider-crank data (SI). Defaults are those of slider_crank.mech.yaml.

    The crank angle theta is zero with the crank pin on +x; the rod centre of mass lies on the
    line from crank pin to slider, `rod_cm_fraction` of the way from the pin; the slider centre
    of mass is at the slider joint point on the x axis.
    """

    crank_length: float = 0.100  # m, pivot to crank pin
    rod_length: float = 0.300  # m, crank pin to slider joint
    crank_mass: float = 1.2  # kg
    crank_cm_radius: float = 0.050  # m, pivot to crank centre of mass (on the crank line)
    crank_izz: float = 0.001  # kg*m^2, about the crank centre of mass
    rod_mass: float = 0.8  # kg
    rod_cm_fraction: float = 0.5  # -, along the rod from the crank pin
    rod_izz: float = 0.006  # kg*m^2, about the rod centre of mass
    slider_mass: float = 2.0  # kg
    g: float = STANDARD_GRAVITY  # m/s^2, acting along -y


@dataclass(frozen=True)
class SliderCrankKinematics:
    """Closed-form kinematics, arrays of shape (n,) or (n, 2) (m, rad, s)."""

    beta: FloatArray  # rod angle from +x, rad (negative while theta in (0, pi))
    beta_d: FloatArray  # rad/s
    beta_dd: FloatArray  # rad/s^2
    x: FloatArray  # slider position along x, m
    x_d: FloatArray  # m/s
    x_dd: FloatArray  # m/s^2
    pin: FloatArray  # crank pin position (n, 2), m
    crank_cm: FloatArray  # (n, 2), m
    crank_cm_acc: FloatArray  # (n, 2), m/s^2
    rod_cm: FloatArray  # (n, 2), m
    rod_cm_vel: FloatArray  # (n, 2), m/s
    rod_cm_acc: FloatArray  # (n, 2), m/s^2


def slider_crank_kinematics(
    theta: ArrayLike, omega: ArrayLike, alpha: ArrayLike, p: SliderCrank = SliderCrank()
) -> SliderCrankKinematics:
    """Slider-crank positions, velocities and accelerations in closed form.

    Loop closure [SM 5/6]: pin A = r (cos th, sin th); slider B = A + L (cos b, sin b) with
    B_y = 0, so sin b = -r sin th / L. Differentiating L sin b = -r sin th twice gives b', b''.
    `theta` (rad), `omega` (rad/s), `alpha` (rad/s^2) are the crank angle and its derivatives.
    """
    th, w, a = (np.asarray(v, float) for v in (theta, omega, alpha))
    r, L = p.crank_length, p.rod_length
    sb = -r * np.sin(th) / L
    cb = np.sqrt(1.0 - sb**2)
    beta = np.arctan2(sb, cb)
    bd = -r * np.cos(th) * w / (L * cb)
    bdd = (r * np.sin(th) * w**2 - r * np.cos(th) * a + L * sb * bd**2) / (L * cb)
    x = r * np.cos(th) + L * cb
    xd = -r * np.sin(th) * w - L * sb * bd
    xdd = -r * np.cos(th) * w**2 - r * np.sin(th) * a - L * cb * bd**2 - L * sb * bdd
    u_th = np.stack([np.cos(th), np.sin(th)], axis=-1)
    u_b = np.stack([cb, sb], axis=-1)
    pin = r * u_th
    pin_vel = r * w[..., None] * _perp(u_th)
    pin_acc = r * (a[..., None] * _perp(u_th) - (w**2)[..., None] * u_th)
    s = p.rod_cm_fraction * L
    rod_cm = pin + s * u_b
    rod_vel = pin_vel + s * bd[..., None] * _perp(u_b)
    rod_acc = pin_acc + s * (bdd[..., None] * _perp(u_b) - (bd**2)[..., None] * u_b)
    rc = p.crank_cm_radius
    crank_cm = rc * u_th
    crank_acc = rc * (a[..., None] * _perp(u_th) - (w**2)[..., None] * u_th)
    return SliderCrankKinematics(
        beta, bd, bdd, x, xd, xdd, pin, crank_cm, crank_acc, rod_cm, rod_vel, rod_acc
    )


@dataclass(frozen=True)
class SliderCrankLoads:
    """Joint reactions and drive torque, arrays of shape (n,) (N, N*m), global axes.

    Sign conventions are those of SPEC 1.3 for the joints of slider_crank.mech.yaml:
    `pivot` = force on the crank from ground; `big` = force on the rod from the crank (at the
    crank pin); `small` = force on the slider from the rod; `guide_fy` = force on the slider
    from ground normal to the guide; `drive_torque` = torque on the crank about +z.
    """

    pivot_fx: FloatArray
    pivot_fy: FloatArray
    big_fx: FloatArray
    big_fy: FloatArray
    small_fx: FloatArray
    small_fy: FloatArray
    guide_fy: FloatArray
    drive_torque: FloatArray


def slider_crank_loads(
    theta: ArrayLike, omega: ArrayLike, alpha: ArrayLike, p: SliderCrank = SliderCrank()
) -> SliderCrankLoads:
    """Planar Newton-Euler solution of the slider-crank [SM 6/6], inertia and gravity included.

    Unknowns u = [Px, Py, Ax, Ay, Bx, By, N, T]: P on the crank from ground at the pivot, A on
    the rod from the crank at the pin, B on the slider from the rod, N on the slider from the
    guide (y), T drive torque on the crank. Equations: crank m a = P - A + m g and
    I alpha = T + (O - G) x P + (A - G) x (-A); rod m a = A - B + m g and
    I b'' = (A - G) x A + (B - G) x (-B); slider m x'' = Bx, 0 = By + N - m g.
    The frictionless guide takes no x force. Inputs as in `slider_crank_kinematics`.
    """
    k = slider_crank_kinematics(theta, omega, alpha, p)
    alpha_arr = np.broadcast_to(np.asarray(alpha, float), k.x.shape)
    n = k.x.shape[0]
    gvec = np.array([0.0, -p.g])
    slider = np.stack([k.x, np.zeros(n)], axis=-1)
    rO = -k.crank_cm  # pivot relative to crank cm
    rA = k.pin - k.crank_cm  # pin relative to crank cm
    sA = k.pin - k.rod_cm  # pin relative to rod cm
    sB = slider - k.rod_cm  # slider joint relative to rod cm
    mat = np.zeros((n, 8, 8))
    rhs = np.zeros((n, 8))
    # crank translation: P - A = m a - m g
    mat[:, 0, 0], mat[:, 0, 2] = 1.0, -1.0
    mat[:, 1, 1], mat[:, 1, 3] = 1.0, -1.0
    rhs[:, 0:2] = p.crank_mass * (k.crank_cm_acc - gvec)
    # crank rotation about its cm: T + rO x P - rA x A = I alpha
    mat[:, 2, 7] = 1.0
    mat[:, 2, 0], mat[:, 2, 1] = -rO[:, 1], rO[:, 0]
    mat[:, 2, 2], mat[:, 2, 3] = rA[:, 1], -rA[:, 0]
    rhs[:, 2] = p.crank_izz * alpha_arr
    # rod translation: A - B = m a - m g
    mat[:, 3, 2], mat[:, 3, 4] = 1.0, -1.0
    mat[:, 4, 3], mat[:, 4, 5] = 1.0, -1.0
    rhs[:, 3:5] = p.rod_mass * (k.rod_cm_acc - gvec)
    # rod rotation about its cm: sA x A - sB x B = I b''
    mat[:, 5, 2], mat[:, 5, 3] = -sA[:, 1], sA[:, 0]
    mat[:, 5, 4], mat[:, 5, 5] = sB[:, 1], -sB[:, 0]
    rhs[:, 5] = p.rod_izz * k.beta_dd
    # slider: Bx = m x'', By + N = -m g_y
    mat[:, 6, 4] = 1.0
    rhs[:, 6] = p.slider_mass * k.x_dd
    mat[:, 7, 5], mat[:, 7, 6] = 1.0, 1.0
    rhs[:, 7] = -p.slider_mass * gvec[1]
    u = np.linalg.solve(mat, rhs[..., None])[..., 0]
    return SliderCrankLoads(u[:, 0], u[:, 1], u[:, 2], u[:, 3], u[:, 4], u[:, 5], u[:, 6], u[:, 7])


def slider_crank_energy(
    theta: ArrayLike, omega: ArrayLike, p: SliderCrank = SliderCrank()
) -> tuple[FloatArray, FloatArray]:
    """Kinetic and potential energy of the slider-crank (J), potential zero at y = 0.

    T = 1/2 (I_c + m_c r_c^2) w^2 + 1/2 m_r |v_G|^2 + 1/2 I_r b'^2 + 1/2 m_s x'^2;
    V = g (m_c y_Gc + m_r y_Gr) (the slider stays at y = 0).
    """
    w = np.asarray(omega, float)
    k = slider_crank_kinematics(theta, w, np.zeros_like(w), p)
    i_pivot = p.crank_izz + p.crank_mass * p.crank_cm_radius**2
    kinetic = (
        0.5 * i_pivot * w**2
        + 0.5 * p.rod_mass * np.sum(k.rod_cm_vel**2, axis=-1)
        + 0.5 * p.rod_izz * k.beta_d**2
        + 0.5 * p.slider_mass * k.x_d**2
    )
    potential = p.g * (p.crank_mass * k.crank_cm[:, 1] + p.rod_mass * k.rod_cm[:, 1])
    return kinetic, potential


# --------------------------------------------------------------------------------------------
# Physical pendulum: a rigid body on a revolute about +z, centre of mass a distance d below the
# hinge at the design position (theta = 0), gravity -y.
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Pendulum:
    """Physical pendulum data (SI); defaults are those of pendulum.case.yaml (uniform 1 m bar)."""

    mass: float = 3.0  # kg
    cm_distance: float = 0.5  # m, hinge to centre of mass
    izz_cm: float = 0.25  # kg*m^2, about the centre of mass (m L^2 / 12)
    g: float = STANDARD_GRAVITY  # m/s^2

    @property
    def izz_hinge(self) -> float:
        """Moment of inertia about the hinge axis, I_cm + m d^2 (kg*m^2)."""
        return self.izz_cm + self.mass * self.cm_distance**2

    @property
    def omega0_squared(self) -> float:
        """Small-oscillation angular frequency squared, m g d / I_hinge (1/s^2)."""
        return self.mass * self.g * self.cm_distance / self.izz_hinge


def pendulum_period(theta0: float, p: Pendulum = Pendulum()) -> float:
    """Exact period (s) of a pendulum released at rest from `theta0` (rad, |theta0| < pi).

    [AS 17.3] T = 4 / w0 * K(m) with m = k^2 = sin^2(theta0 / 2) and w0^2 = m g d / I_hinge
    (scipy's `ellipk` takes the parameter m = k^2).
    """
    return 4.0 / np.sqrt(p.omega0_squared) * float(ellipk(np.sin(0.5 * theta0) ** 2))


def pendulum_angle(t: ArrayLike, theta0: float, p: Pendulum = Pendulum()) -> FloatArray:
    """Exact angle (rad) at times t (s) of a pendulum released at rest from `theta0`.

    [AS 16.1, 17.3] theta(t) = 2 asin(k sn(K(m) - w0 t | m)), k = sin(theta0 / 2), m = k^2.
    """
    k = np.sin(0.5 * theta0)
    m = float(k * k)
    w0 = np.sqrt(p.omega0_squared)
    return 2.0 * np.arcsin(k * ellipj(float(ellipk(m)) - w0 * np.asarray(t, float), m)[0])


def pendulum_small_angle_period(p: Pendulum = Pendulum()) -> float:
    """Small-amplitude period 2 pi sqrt(I_hinge / (m g d)) (s), = 2 pi sqrt(L_eq / g)."""
    return 2.0 * np.pi / np.sqrt(p.omega0_squared)


def pendulum_hinge_reaction(
    theta: ArrayLike, theta0: float, p: Pendulum = Pendulum()
) -> tuple[FloatArray, FloatArray]:
    """Force on the pendulum from the hinge (N, global x and y) at angle `theta` (rad).

    Energy [SM 6/6]: theta'^2 = 2 m g d (cos theta - cos theta0) / I_hinge and moment balance
    theta'' = -w0^2 sin theta. The centre of mass is at d (sin th, -cos th), so its
    acceleration is d theta'' (cos th, sin th) + d theta'^2 (-sin th, cos th), and the
    reaction is R = m a - m g_vec with g_vec = (0, -g).
    """
    th = np.asarray(theta, float)
    d, w02 = p.cm_distance, p.omega0_squared
    rate2 = 2.0 * w02 * (np.cos(th) - np.cos(theta0))
    acc_t = -w02 * np.sin(th)
    ax = d * (acc_t * np.cos(th) - rate2 * np.sin(th))
    ay = d * (acc_t * np.sin(th) + rate2 * np.cos(th))
    return p.mass * ax, p.mass * (ay + p.g)


def pendulum_bottom_reaction(theta0: float, p: Pendulum = Pendulum()) -> float:
    """Vertical hinge force on the pendulum at the bottom of the swing (N).

    Energy: I_hinge w^2 / 2 = m g d (1 - cos theta0); then R_y = m g + m d w^2.
    """
    w2 = 2.0 * p.mass * p.g * p.cm_distance * (1.0 - np.cos(theta0)) / p.izz_hinge
    return p.mass * p.g + p.mass * p.cm_distance * w2


def pendulum_rhs(t: float, y: FloatArray, p: Pendulum = Pendulum()) -> FloatArray:
    """State derivative of [theta (rad), theta' (rad/s)]: theta'' = -w0^2 sin theta."""
    return np.array([y[1], -p.omega0_squared * np.sin(y[0])])


# --------------------------------------------------------------------------------------------
# Four-bar (planar): crank O2-B, coupler B-C, rocker O4-C; design position of fourbar*.yaml.
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FourBar:
    """Four-bar geometry and masses at the design position (SI, global x-y).

    Defaults are those of fourbar_quasistatic.case.yaml and fourbar_revolutes.mech.yaml:
    crank 0.1 m, coupler 0.3 m, rocker 0.35 m, ground 0.45 m (Grashof crank-rocker).
    """

    o2: tuple[float, float] = (0.0, 0.0)  # crank pivot, m
    o4: tuple[float, float] = (0.45, 0.0)  # rocker pivot, m
    b0: tuple[float, float] = (0.0, 0.1)  # crank pin at design, m
    c0: tuple[float, float] = (0.24, 0.28)  # coupler-rocker pin at design, m
    crank_mass: float = 0.5  # kg
    crank_cm0: tuple[float, float] = (0.0, 0.05)
    coupler_mass: float = 5.0
    coupler_cm0: tuple[float, float] = (0.09, 0.23)  # off the line B-C on purpose
    rocker_mass: float = 1.5
    rocker_cm0: tuple[float, float] = (0.345, 0.14)
    g: float = STANDARD_GRAVITY  # m/s^2, along -y


@dataclass(frozen=True)
class FourBarPose:
    """Positions at crank rotations `theta` (from design), arrays (n, 2) in m and (n,) in rad."""

    b: FloatArray
    c: FloatArray
    phi3: FloatArray  # coupler rotation from design, rad
    phi4: FloatArray  # rocker rotation from design, rad
    crank_cm: FloatArray
    coupler_cm: FloatArray
    rocker_cm: FloatArray


def _rotate(v: FloatArray, angle: FloatArray) -> FloatArray:
    """Planar vectors v (2,) or (n, 2) rotated by `angle` (n,) rad about +z."""
    c, s = np.cos(angle), np.sin(angle)
    v = np.broadcast_to(v, (*np.shape(angle), 2))
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _angle_of(v: FloatArray) -> FloatArray:
    return np.arctan2(v[..., 1], v[..., 0])


def fourbar_pose(theta: ArrayLike, p: FourBar = FourBar()) -> FourBarPose:
    """Closed-form position analysis [RS 4.5] by circle intersection.

    B = O2 + R(theta)(B0 - O2); C is the intersection of the circles |C - B| = b and
    |C - O4| = c on the same side of the line B-O4 as at design (the assembly branch that is
    continuous for a Grashof crank-rocker). `theta` is the crank rotation from design (rad).
    """
    th = np.asarray(theta, float)
    o2, o4, b0, c0 = (np.asarray(v, float) for v in (p.o2, p.o4, p.b0, p.c0))
    len_b, len_c = np.linalg.norm(c0 - b0), np.linalg.norm(c0 - o4)
    branch = np.sign(cross2(o4 - b0, c0 - b0))
    b = o2 + _rotate(b0 - o2, th)
    e = o4 - b
    dist = np.linalg.norm(e, axis=-1)
    along = (dist**2 + len_b**2 - len_c**2) / (2.0 * dist)
    across = np.sqrt(len_b**2 - along**2)
    u = e / dist[..., None]
    c = b + along[..., None] * u + branch * across[..., None] * _perp(u)
    phi3 = _angle_of(c - b) - _angle_of(c0 - b0)
    phi4 = _angle_of(c - o4) - _angle_of(c0 - o4)
    crank_cm = o2 + _rotate(np.asarray(p.crank_cm0) - o2, th)
    coupler_cm = b + _rotate(np.asarray(p.coupler_cm0) - b0, phi3)
    rocker_cm = o4 + _rotate(np.asarray(p.rocker_cm0) - o4, phi4)
    return FourBarPose(b, c, phi3, phi4, crank_cm, coupler_cm, rocker_cm)


def fourbar_velocity_ratios(
    theta: ArrayLike, p: FourBar = FourBar()
) -> tuple[FloatArray, FloatArray]:
    """Velocity ratios d(phi3)/d(theta), d(phi4)/d(theta) (-) from the loop closure.

    Differentiating B(theta) + (C - B) = O4 + (C - O4) [RS 6.7]:
    dB/dth + phi3' e_z x (C - B) = phi4' e_z x (C - O4), a 2x2 linear system per angle.
    """
    pose = fourbar_pose(theta, p)
    o2, o4 = np.asarray(p.o2, float), np.asarray(p.o4, float)
    db = _perp(pose.b - o2)
    mat = np.stack([_perp(pose.c - pose.b), -_perp(pose.c - o4)], axis=-1)  # (n, 2, 2)
    sol = np.linalg.solve(mat, -db[..., None])[..., 0]
    return sol[:, 0], sol[:, 1]


def fourbar_potential(theta: ArrayLike, p: FourBar = FourBar()) -> FloatArray:
    """Gravitational potential energy V = g sum(m_i y_Gi) (J) at crank rotations `theta`."""
    pose = fourbar_pose(theta, p)
    return p.g * (
        p.crank_mass * pose.crank_cm[:, 1]
        + p.coupler_mass * pose.coupler_cm[:, 1]
        + p.rocker_mass * pose.rocker_cm[:, 1]
    )


def fourbar_drive_torque(theta: ArrayLike, p: FourBar = FourBar()) -> FloatArray:
    """Quasi-static crank torque (N*m, on the crank about +z) by virtual work [RS 11.9].

    T dtheta + sum(m_i g_vec . dG_i) = 0, with dG_i/dtheta from the velocity ratios:
    crank e_z x (G - O2), coupler dB/dth + phi3' e_z x (G - B), rocker phi4' e_z x (G - O4).
    So T = g sum(m_i dy_Gi/dtheta).
    """
    pose = fourbar_pose(theta, p)
    r3, r4 = fourbar_velocity_ratios(theta, p)
    o2, o4 = np.asarray(p.o2, float), np.asarray(p.o4, float)
    dy_crank = _perp(pose.crank_cm - o2)[:, 1]
    dy_coupler = _perp(pose.b - o2)[:, 1] + r3 * _perp(pose.coupler_cm - pose.b)[:, 1]
    dy_rocker = r4 * _perp(pose.rocker_cm - o4)[:, 1]
    return p.g * (p.crank_mass * dy_crank + p.coupler_mass * dy_coupler + p.rocker_mass * dy_rocker)


def fourbar_static_loads(theta: ArrayLike, p: FourBar = FourBar()) -> dict[str, FloatArray]:
    """Planar static equilibrium of the three links [RS 11.5], gravity only (N, N*m).

    Unknowns [P2x, P2y, FBx, FBy, FCx, FCy, P4x, P4y, T]: P2 on the crank from ground, FB on
    the coupler from the crank (at B), FC on the coupler from the rocker (at C), P4 on the
    rocker from ground, T on the crank about +z. Equations: crank P2 - FB + m g = 0 and
    moments about O2; coupler FB + FC + m g = 0 and moments about B; rocker P4 - FC + m g = 0
    and moments about O4. Keys: crank_pivot_fx/fy, pin_b_fx/fy, pin_c_fx/fy,
    rocker_pivot_fx/fy, drive_torque.
    """
    pose = fourbar_pose(theta, p)
    n = pose.b.shape[0]
    o2, o4 = np.asarray(p.o2, float), np.asarray(p.o4, float)
    w2, w3, w4 = (np.array([0.0, -m * p.g]) for m in (p.crank_mass, p.coupler_mass, p.rocker_mass))
    rb, cb, c4 = pose.b - o2, pose.c - pose.b, pose.c - o4
    mat = np.zeros((n, 9, 9))
    rhs = np.zeros((n, 9))
    mat[:, 0, 0], mat[:, 0, 2], rhs[:, 0] = 1.0, -1.0, -w2[0]
    mat[:, 1, 1], mat[:, 1, 3], rhs[:, 1] = 1.0, -1.0, -w2[1]
    mat[:, 2, 8], mat[:, 2, 2], mat[:, 2, 3] = 1.0, rb[:, 1], -rb[:, 0]  # T - rb x FB
    rhs[:, 2] = -cross2(pose.crank_cm - o2, w2)
    mat[:, 3, 2], mat[:, 3, 4], rhs[:, 3] = 1.0, 1.0, -w3[0]
    mat[:, 4, 3], mat[:, 4, 5], rhs[:, 4] = 1.0, 1.0, -w3[1]
    mat[:, 5, 4], mat[:, 5, 5] = -cb[:, 1], cb[:, 0]  # cb x FC
    rhs[:, 5] = -cross2(pose.coupler_cm - pose.b, w3)
    mat[:, 6, 6], mat[:, 6, 4], rhs[:, 6] = 1.0, -1.0, -w4[0]
    mat[:, 7, 7], mat[:, 7, 5], rhs[:, 7] = 1.0, -1.0, -w4[1]
    mat[:, 8, 4], mat[:, 8, 5] = c4[:, 1], -c4[:, 0]  # -c4 x FC
    rhs[:, 8] = -cross2(pose.rocker_cm - o4, w4)
    u = np.linalg.solve(mat, rhs[..., None])[..., 0]
    names = (
        "crank_pivot_fx",
        "crank_pivot_fy",
        "pin_b_fx",
        "pin_b_fy",
        "pin_c_fx",
        "pin_c_fy",
        "rocker_pivot_fx",
        "rocker_pivot_fy",
        "drive_torque",
    )
    return {name: u[:, i] for i, name in enumerate(names)}


# --------------------------------------------------------------------------------------------
# Bar on a hinge held up by a linear spring (static_spring_bar.case.yaml).
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SpringBar:
    """Bar hinged at the origin about +z, horizontal along +x at design, gravity -y (SI).

    A linear spring joins the bar point `tip` (on the bar, at design) to the ground point
    `anchor`; tension = stiffness * (length - free_length).
    """

    mass: float = 4.0  # kg
    cm0: tuple[float, float] = (0.5, 0.0)  # m, centre of mass at design
    tip0: tuple[float, float] = (0.8, 0.0)  # m, spring point on the bar at design
    anchor: tuple[float, float] = (0.0, 0.6)  # m, spring point on ground (1 m from tip0)
    stiffness: float = 200.0  # N/m
    free_length: float = 0.6  # m
    g: float = STANDARD_GRAVITY  # m/s^2


def _spring_bar_state(theta: float, p: SpringBar) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tip position, spring force on the bar (N, global) and centre of mass at angle theta."""
    tip = _rotate(np.asarray(p.tip0, float), np.asarray(theta, float))
    cm = _rotate(np.asarray(p.cm0, float), np.asarray(theta, float))
    span = np.asarray(p.anchor, float) - tip
    length = float(np.linalg.norm(span))
    tension = p.stiffness * (length - p.free_length)
    return tip, tension * span / length, cm


def spring_bar_moment(theta: float, p: SpringBar = SpringBar()) -> float:
    """Net moment about the hinge (N*m, +z) of spring and weight at bar angle `theta` (rad)."""
    tip, force, cm = _spring_bar_state(theta, p)
    return float(cross2(tip, force) + cross2(cm, np.array([0.0, -p.mass * p.g])))


def spring_bar_equilibrium(
    p: SpringBar = SpringBar(), bracket: tuple[float, float] = (-1.5, 1.5)
) -> dict[str, float]:
    """Static equilibrium of the spring bar by moment balance, solved with `brentq`.

    Returns `angle` (rad), `tension` (N), `length` (m) of the spring, `hinge_fx`, `hinge_fy`
    (N, force on the bar from ground: R = -F_spring - m g_vec) and `stiffness` (the slope
    dM/dtheta, N*m/rad; negative means a stable equilibrium).
    """
    angle = brentq(spring_bar_moment, *bracket, args=(p,), xtol=1e-14, rtol=1e-14)
    tip, force, _ = _spring_bar_state(angle, p)
    length = float(np.linalg.norm(np.asarray(p.anchor) - tip))
    h = 1e-6
    slope = (spring_bar_moment(angle + h, p) - spring_bar_moment(angle - h, p)) / (2 * h)
    return {
        "angle": angle,
        "tension": p.stiffness * (length - p.free_length),
        "length": length,
        "hinge_fx": -float(force[0]),
        "hinge_fy": -float(force[1]) + p.mass * p.g,
        "stiffness": slope,
    }


# --------------------------------------------------------------------------------------------
# Heavy top on a spherical joint at the origin (heavy_top.case.yaml), gravity -z.
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class HeavyTop:
    """Top data (SI). The body frame is the global frame at the design position.

    `inertia_cm` is the 3x3 inertia tensor about the centre of mass in design axes (flat list
    [Ixx, Iyy, Izz, Ixy, Ixz, Iyz], tensor entries). Defaults: symmetric top, axis
    e = (0.6, 0, 0.8), axial 0.004 and transverse 0.0025 kg*m^2 about the cm, so that
    I = 0.0025 * 1 + 0.0015 * e e^T.
    """

    mass: float = 1.0
    cm0: tuple[float, float, float] = (0.03, 0.0, 0.04)  # m, 0.05 m along e
    inertia_cm: tuple[float, ...] = (0.00304, 0.0025, 0.00346, 0.0, 0.00072, 0.0)
    omega0: tuple[float, float, float] = (60.0, 0.0, 80.0)  # rad/s, global, = 100 e
    g: float = STANDARD_GRAVITY  # m/s^2, along -z

    def inertia_pivot(self) -> FloatArray:
        """Inertia tensor about the pivot (origin), design axes (kg*m^2), parallel axes."""
        ixx, iyy, izz, ixy, ixz, iyz = self.inertia_cm
        i_cm = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        r = np.asarray(self.cm0, float)
        return i_cm + self.mass * (r @ r * np.eye(3) - np.outer(r, r))


@dataclass(frozen=True)
class HeavyTopSolution:
    """Reference motion at times `t` (n,): body-frame rates, quaternions, global rates."""

    t: FloatArray
    omega_body: FloatArray  # (n, 3) rad/s, body (design) axes
    quaternion: FloatArray  # (n, 4) scalar first, body -> global
    omega_global: FloatArray  # (n, 3) rad/s
    alpha_global: FloatArray  # (n, 3) rad/s^2

    def rotation(self) -> FloatArray:
        """Rotation matrices (n, 3, 3), body -> global."""
        return _quat_to_matrix(self.quaternion)

    def position(self, point_design: ArrayLike) -> FloatArray:
        """Global positions (n, 3) m of a body point given at the design position."""
        return self.rotation() @ np.asarray(point_design, float)

    def pivot_reaction(self, top: HeavyTop) -> FloatArray:
        """Force on the top from the spherical joint (n, 3) N: R = m a_G - m g_vec."""
        r = self.position(top.cm0)
        w, a = self.omega_global, self.alpha_global
        acc = np.cross(a, r) + np.cross(w, np.cross(w, r))
        return top.mass * (acc - np.array([0.0, 0.0, -top.g]))


def _quat_to_matrix(q: FloatArray) -> FloatArray:
    """Rotation matrices (n, 3, 3) of unit quaternions (n, 4), scalar first."""
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def _top_rhs(
    top: HeavyTop, i_pivot: FloatArray, i_inv: FloatArray
) -> Callable[[float, FloatArray], FloatArray]:
    """Euler's equations about the fixed point + quaternion kinematics [GO 4.9, 5.5]."""
    r_body = np.asarray(top.cm0, float)
    g_global = np.array([0.0, 0.0, -top.g])

    def rhs(t: float, y: FloatArray) -> FloatArray:
        w, q = y[:3], y[3:]
        rot = _quat_to_matrix(q[None])[0]
        torque = np.cross(r_body, top.mass * rot.T @ g_global)  # gravity, body axes
        wd = i_inv @ (torque - np.cross(w, i_pivot @ w))
        qw, qv = q[0], q[1:]
        qd = 0.5 * np.concatenate([[-qv @ w], qw * w + np.cross(qv, w)])
        return np.concatenate([wd, qd])

    return rhs


def heavy_top_solve(
    t_eval: ArrayLike, top: HeavyTop = HeavyTop(), rtol: float = 1e-10, atol: float = 1e-12
) -> HeavyTopSolution:
    """Integrate the heavy top with `solve_ivp` (DOP853) from the design position (s).

    State: body-frame angular velocity w (rad/s) and quaternion q (body -> global, starts at
    identity). I_O w' = r x (m R^T g) - w x I_O w; q' = q (x) (0, w) / 2 [GO].
    """
    t_eval = np.asarray(t_eval, float)
    i_pivot = top.inertia_pivot()
    i_inv = np.linalg.inv(i_pivot)
    rhs = _top_rhs(top, i_pivot, i_inv)
    y0 = np.concatenate([np.asarray(top.omega0, float), [1.0, 0.0, 0.0, 0.0]])
    sol = solve_ivp(
        rhs, (t_eval[0], t_eval[-1]), y0, method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol
    )
    if not sol.success:
        raise RuntimeError(f"heavy top reference integration failed: {sol.message}")
    w_body, quat = sol.y[:3].T, sol.y[3:].T
    wd_body = np.array([rhs(t, y)[:3] for t, y in zip(sol.t, sol.y.T)])
    rot = _quat_to_matrix(quat)
    return HeavyTopSolution(
        sol.t,
        w_body,
        quat,
        np.einsum("nij,nj->ni", rot, w_body),
        np.einsum("nij,nj->ni", rot, wd_body),
    )


def heavy_top_energy(solution: HeavyTopSolution, top: HeavyTop = HeavyTop()) -> FloatArray:
    """Total energy (J): w.I_O.w/2 (body axes) + m g z_G."""
    i_pivot = top.inertia_pivot()
    w = solution.omega_body
    kinetic = 0.5 * np.einsum("ni,ij,nj->n", w, i_pivot, w)
    return kinetic + top.mass * top.g * solution.position(top.cm0)[:, 2]


def heavy_top_vertical_momentum(
    solution: HeavyTopSolution, top: HeavyTop = HeavyTop()
) -> FloatArray:
    """Angular momentum about the vertical (global z) through the pivot (kg*m^2/s)."""
    h_body = solution.omega_body @ top.inertia_pivot().T
    return np.einsum("nij,nj->ni", solution.rotation(), h_body)[:, 2]


def angular_velocity_from_points(
    positions: list[FloatArray], velocities: list[FloatArray]
) -> FloatArray:
    """Angular velocity (n, 3) rad/s of a body turning about a fixed origin.

    Each point satisfies v = w x p, i.e. [-p]x w = v; two points not in line with the origin
    determine w, solved in the least-squares sense from all given points.
    """

    def skew(p: FloatArray) -> FloatArray:
        z = np.zeros(p.shape[0])
        return np.stack(
            [
                np.stack([z, -p[:, 2], p[:, 1]], -1),
                np.stack([p[:, 2], z, -p[:, 0]], -1),
                np.stack([-p[:, 1], p[:, 0], z], -1),
            ],
            axis=-2,
        )

    mat = np.concatenate([-skew(np.asarray(p, float)) for p in positions], axis=1)
    rhs = np.concatenate([np.asarray(v, float) for v in velocities], axis=1)
    return np.stack([np.linalg.lstsq(m, b, rcond=None)[0] for m, b in zip(mat, rhs)])


# --------------------------------------------------------------------------------------------
# Double pendulum of two bars on revolutes about +z, hanging along -y at design, gravity -y.
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class DoublePendulum:
    """Two-bar pendulum (SI); defaults are those of double_pendulum.case.yaml.

    Bar 1 hinges at the origin, bar 2 at the lower end of bar 1 (a distance `length1` below);
    centres of mass `cm1`, `cm2` below their hinges; phi1, phi2 absolute angles from the
    vertical about +z (phi2 = joint1 + joint2 angles).
    """

    mass1: float = 3.0
    length1: float = 1.0
    cm1: float = 0.5
    izz1: float = 0.25
    mass2: float = 1.2
    cm2: float = 0.5
    izz2: float = 0.1
    g: float = STANDARD_GRAVITY


def _double_pendulum_points(
    phi1: FloatArray, phi2: FloatArray, p: DoublePendulum
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Unit vectors from hinge to centre of mass (hanging = (0, -1)) and joint-2 position."""
    u1 = np.stack([np.sin(phi1), -np.cos(phi1)], axis=-1)
    u2 = np.stack([np.sin(phi2), -np.cos(phi2)], axis=-1)
    return u1, u2, p.length1 * u1


def double_pendulum_energy(
    phi1: ArrayLike,
    phi2: ArrayLike,
    w1: ArrayLike,
    w2: ArrayLike,
    p: DoublePendulum = DoublePendulum(),
) -> FloatArray:
    """Total energy (J) from absolute angles (rad) and rates (rad/s); V = 0 at the hinge level.

    G1 = c1 u1, G2 = L1 u1 + c2 u2 with u = (sin phi, -cos phi); the velocities are
    c1 w1 u1', L1 w1 u1' + c2 w2 u2' with u' = (cos phi, sin phi).
    """
    phi1, phi2, w1, w2 = (np.asarray(v, float) for v in (phi1, phi2, w1, w2))
    u1, u2, j2 = _double_pendulum_points(phi1, phi2, p)
    t1, t2 = _perp(u1), _perp(u2)
    v1 = p.cm1 * w1[..., None] * t1
    v2 = p.length1 * w1[..., None] * t1 + p.cm2 * w2[..., None] * t2
    kinetic = 0.5 * (
        p.mass1 * np.sum(v1**2, -1) + p.izz1 * w1**2 + p.mass2 * np.sum(v2**2, -1) + p.izz2 * w2**2
    )
    potential = p.g * (p.mass1 * p.cm1 * u1[..., 1] + p.mass2 * (j2 + p.cm2 * u2)[..., 1])
    return kinetic + potential


def double_pendulum_rhs(
    t: float, y: FloatArray, p: DoublePendulum = DoublePendulum()
) -> FloatArray:
    """Lagrange's equations, state [phi1, phi2, w1, w2] (rad, rad/s).

    M = [[I1 + m1 c1^2 + m2 L1^2, m2 L1 c2 cos(d)], [m2 L1 c2 cos(d), I2 + m2 c2^2]],
    d = phi1 - phi2; forcing -m2 L1 c2 sin(d) w2^2 - (m1 c1 + m2 L1) g sin phi1 and
    m2 L1 c2 sin(d) w1^2 - m2 c2 g sin phi2.
    """
    phi1, phi2, w1, w2 = y
    d = phi1 - phi2
    k = p.mass2 * p.length1 * p.cm2
    mass = np.array(
        [
            [p.izz1 + p.mass1 * p.cm1**2 + p.mass2 * p.length1**2, k * np.cos(d)],
            [k * np.cos(d), p.izz2 + p.mass2 * p.cm2**2],
        ]
    )
    force = np.array(
        [
            -k * np.sin(d) * w2**2 - (p.mass1 * p.cm1 + p.mass2 * p.length1) * p.g * np.sin(phi1),
            k * np.sin(d) * w1**2 - p.mass2 * p.cm2 * p.g * np.sin(phi2),
        ]
    )
    return np.concatenate([[w1, w2], np.linalg.solve(mass, force)])


def double_pendulum_solve(
    t_eval: ArrayLike,
    phi0: tuple[float, float],
    p: DoublePendulum = DoublePendulum(),
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> FloatArray:
    """Reference motion from rest at absolute angles `phi0` (rad): array (n, 4) of
    [phi1, phi2, w1, w2] at `t_eval` (s), integrated with DOP853."""
    t_eval = np.asarray(t_eval, float)
    sol = solve_ivp(
        double_pendulum_rhs,
        (t_eval[0], t_eval[-1]),
        [phi0[0], phi0[1], 0.0, 0.0],
        method="DOP853",
        t_eval=t_eval,
        rtol=rtol,
        atol=atol,
        args=(p,),
    )
    if not sol.success:
        raise RuntimeError(f"double pendulum reference integration failed: {sol.message}")
    return sol.y.T


# --------------------------------------------------------------------------------------------
# Comparing engine results with the references (any object with `.solution`).
# --------------------------------------------------------------------------------------------


def channel(outcome: Any, column: str) -> FloatArray:
    """Result column `REQUEST.COMPONENT` as a float array, with a helpful error if absent."""
    channels = outcome.solution.channels
    if column not in channels:
        raise AssertionError(f"missing column {column!r}; have {sorted(channels)}")
    return np.asarray(channels[column], dtype=float)


def vector(outcome: Any, request: str, components: str = "xyz") -> FloatArray:
    """Columns `request.c` for each character c of `components`, stacked as (n, len)."""
    names = components.split() if " " in components else list(components)
    return np.stack([channel(outcome, f"{request}.{c}") for c in names], axis=-1)


def all_warnings(outcome: Any) -> list[str]:
    """Warnings of the run and of its solution (the summary shows both)."""
    return [
        *(d.keyed_message() for d in getattr(outcome, "warnings", [])),
        *getattr(outcome.solution, "warnings", []),
    ]


def wrap_angle(angle: np.ndarray) -> FloatArray:
    """Angles mapped to (-pi, pi] (rad), to compare joint angles that may or may not wrap."""
    return np.angle(np.exp(1j * np.asarray(angle, dtype=float)))


def assert_within_peak(
    actual: np.ndarray, expected: np.ndarray, fraction: float, label: str, peak: float | None = None
) -> None:
    """Assert max |actual - expected| <= fraction * peak, peak = max |expected| by default."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    scale = float(np.max(np.abs(expected))) if peak is None else peak
    error = float(np.max(np.abs(actual - expected)))
    assert error <= fraction * scale, (
        f"{label}: max error {error:.6g} exceeds {fraction:g} x peak {scale:.6g}"
    )
