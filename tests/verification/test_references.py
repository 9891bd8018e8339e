"""Self-checks of the independent references (no engine involved).

Each reference is checked against a second, independent route to the same physics: a limit
case, a conservation law, or a different formulation. Tolerances are stated per test.
"""

from __future__ import annotations

import numpy as np
import pytest
from references import (
    DoublePendulum,
    FourBar,
    HeavyTop,
    HeavyTopSolution,
    Pendulum,
    SliderCrank,
    SpringBar,
    angular_velocity_from_points,
    double_pendulum_energy,
    double_pendulum_solve,
    fourbar_drive_torque,
    fourbar_pose,
    fourbar_potential,
    fourbar_static_loads,
    fourbar_velocity_ratios,
    heavy_top_energy,
    heavy_top_solve,
    heavy_top_vertical_momentum,
    pendulum_bottom_reaction,
    pendulum_hinge_reaction,
    pendulum_period,
    pendulum_rhs,
    pendulum_small_angle_period,
    slider_crank_energy,
    slider_crank_kinematics,
    slider_crank_loads,
    spring_bar_equilibrium,
    spring_bar_moment,
)
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

G = 9.81


# ---------------------------------------------------------------- pendulum


def test_elliptic_period_tends_to_small_angle_limit() -> None:
    """T(theta0) -> 2 pi sqrt(L_eq / g) as theta0 -> 0; the first correction is
    (1 + theta0^2 / 16), so at 1e-3 rad the relative difference is 6e-8 (tolerance 1e-7)."""
    p = Pendulum()
    t_small = pendulum_small_angle_period(p)
    l_eq = p.izz_hinge / (p.mass * p.cm_distance)
    assert t_small == pytest.approx(2 * np.pi * np.sqrt(l_eq / G), rel=1e-14)
    assert pendulum_period(1e-3, p) == pytest.approx(t_small, rel=1e-7)


def test_elliptic_period_matches_tabulated_ratio() -> None:
    """T / T0 = 2 K(sin^2 30 deg) / pi = 1.073182 at 60 deg (tabulated, e.g. Nelson & Olsson,
    Am. J. Phys. 54 (1986) 112); tolerance 1e-6 on the six tabulated digits."""
    ratio = pendulum_period(np.radians(60.0)) / pendulum_small_angle_period()
    assert ratio == pytest.approx(1.073182, abs=1e-6)


def test_elliptic_period_matches_integration() -> None:
    """Period from integrating theta'' = -w0^2 sin theta (rtol 1e-12) and locating the
    zero crossings: agrees with the elliptic-integral period to 1e-9 relative."""
    theta0 = np.radians(60.0)

    def through_bottom(t: float, y: np.ndarray) -> float:
        return float(y[0])

    sol = solve_ivp(
        pendulum_rhs,
        (0.0, 4.0),
        [theta0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        events=through_bottom,
    )
    crossings = sol.t_events[0]
    assert len(crossings) >= 4
    period = crossings[2] - crossings[0]
    assert period == pytest.approx(pendulum_period(theta0), rel=1e-9)


def test_hinge_reaction_from_energy_matches_integration() -> None:
    """R(theta) from energy equals m a_G - m g computed from an integrated motion
    (rtol 1e-12): agreement to 1e-7 of the peak; at the bottom it is the closed form."""
    p, theta0 = Pendulum(), np.radians(60.0)
    sol = solve_ivp(
        pendulum_rhs,
        (0.0, 2.0),
        [theta0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        dense_output=True,
    )
    t = np.linspace(0.0, 2.0, 401)
    th, w = sol.sol(t)
    a = -p.omega0_squared * np.sin(th)
    d = p.cm_distance
    ax = d * (a * np.cos(th) - w**2 * np.sin(th))
    ay = d * (a * np.sin(th) + w**2 * np.cos(th))
    fx, fy = pendulum_hinge_reaction(th, theta0, p)
    peak = np.max(np.hypot(fx, fy))
    assert np.max(np.abs(fx - p.mass * ax)) < 1e-7 * peak
    assert np.max(np.abs(fy - p.mass * (ay + G))) < 1e-7 * peak
    bottom = pendulum_hinge_reaction(np.array([0.0]), theta0, p)
    assert bottom[0][0] == pytest.approx(0.0, abs=1e-12)
    assert bottom[1][0] == pytest.approx(pendulum_bottom_reaction(theta0, p), rel=1e-14)
    # m g (1 + 2 m d^2 (1 - cos theta0) / I_hinge) = 3 g (1 + 0.75) at 60 deg
    assert pendulum_bottom_reaction(theta0, p) == pytest.approx(3 * G * 1.75, rel=1e-14)


# ---------------------------------------------------------------- slider-crank


def _crank_motion(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A non-uniform crank motion th = 2 pi t + 0.3 sin(5 t), so alpha != 0 (rad, s)."""
    return (
        2 * np.pi * t + 0.3 * np.sin(5 * t),
        2 * np.pi + 1.5 * np.cos(5 * t),
        -7.5 * np.sin(5 * t),
    )


def test_slider_crank_power_balance() -> None:
    """Drive power T w = d(kinetic + potential)/dt (no friction, rigid joints): the
    Newton-Euler loads and the energy are independent formulas. Central differences on a
    1e-5 s grid are accurate to ~1e-9 of the peak power; tolerance 1e-6 of the peak."""
    t = np.linspace(0.0, 1.0, 100_001)
    th, w, a = _crank_motion(t)
    loads = slider_crank_loads(th, w, a)
    kinetic, potential = slider_crank_energy(th, w)
    d_energy = np.gradient(kinetic + potential, t, edge_order=2)
    power = loads.drive_torque * w
    assert np.max(np.abs(power - d_energy)) < 1e-6 * np.max(np.abs(power))


def test_slider_crank_kinematics_by_differences() -> None:
    """Closed-form x', x'', b', b'' equal central differences of x(t), b(t) (1e-6 rel)."""
    t = np.linspace(0.0, 1.0, 20_001)
    th, w, a = _crank_motion(t)
    k = slider_crank_kinematics(th, w, a)
    for value, rate, label in (
        (k.x, k.x_d, "x'"),
        (k.x_d, k.x_dd, "x''"),
        (k.beta, k.beta_d, "b'"),
        (k.beta_d, k.beta_dd, "b''"),
    ):
        fd = np.gradient(value, t, edge_order=2)
        assert np.max(np.abs(fd - rate)[1:-1]) < 1e-6 * np.max(np.abs(rate)), label
    # loop closure: |B - A| = l with B = (x, 0)
    span = np.stack([k.x, np.zeros_like(k.x)], -1) - k.pin
    assert np.allclose(np.linalg.norm(span, axis=-1), SliderCrank().rod_length, atol=1e-15)


def test_slider_crank_whole_system_balance() -> None:
    """External forces on the whole mechanism (pivot, guide, weights) equal the rate of its
    momentum, sum m_i a_i, to round-off (1e-10 of the peak force)."""
    p = SliderCrank()
    t = np.linspace(0.0, 1.0, 501)
    th, w, a = _crank_motion(t)
    k = slider_crank_kinematics(th, w, a)
    f = slider_crank_loads(th, w, a, p)
    total_mass = p.crank_mass + p.rod_mass + p.slider_mass
    mx = (
        p.crank_mass * k.crank_cm_acc[:, 0]
        + p.rod_mass * k.rod_cm_acc[:, 0]
        + p.slider_mass * k.x_dd
    )
    my = p.crank_mass * k.crank_cm_acc[:, 1] + p.rod_mass * k.rod_cm_acc[:, 1]
    peak = np.max(np.abs(f.pivot_fy))
    assert np.max(np.abs(f.pivot_fx - mx)) < 1e-10 * peak
    assert np.max(np.abs(f.pivot_fy + f.guide_fy - total_mass * G - my)) < 1e-10 * peak


def test_slider_crank_static_dead_centre() -> None:
    """At rest with the crank on +x, the drive holds the crank weight (arm 50 mm) and half
    the rod weight (at the pin, arm 100 mm): T = 1.2 g 0.05 + 0.4 g 0.1 = 0.981 N*m;
    the guide carries the slider and half the rod: 2.4 g."""
    f = slider_crank_loads(np.zeros(1), np.zeros(1), np.zeros(1))
    assert f.drive_torque[0] == pytest.approx(1.2 * G * 0.05 + 0.4 * G * 0.1, rel=1e-12)
    assert f.guide_fy[0] == pytest.approx(2.4 * G, rel=1e-12)
    assert f.pivot_fy[0] == pytest.approx(1.6 * G, rel=1e-12)


# ---------------------------------------------------------------- four-bar


def test_fourbar_loop_closes_and_starts_at_design() -> None:
    """Link lengths are preserved over a full crank turn (1e-14 m) and theta = 0 is the
    design position (phi3 = phi4 = 0)."""
    p = FourBar()
    th = np.linspace(0.0, 2 * np.pi, 721)
    pose = fourbar_pose(th, p)
    assert np.allclose(np.linalg.norm(pose.c - pose.b, axis=-1), 0.3, atol=1e-14)
    assert np.allclose(np.linalg.norm(pose.c - np.array(p.o4), axis=-1), 0.35, atol=1e-14)
    assert np.allclose(np.linalg.norm(pose.b, axis=-1), 0.1, atol=1e-15)
    assert abs(pose.phi3[0]) < 1e-14 and abs(pose.phi4[0]) < 1e-14
    assert np.allclose(pose.coupler_cm[0], p.coupler_cm0, atol=1e-15)


def test_fourbar_velocity_ratios_by_differences() -> None:
    """Loop-closure velocity ratios equal central differences of the closed-form angles
    (step 1e-6 rad: truncation ~1e-12, round-off ~1e-10; tolerance 1e-8)."""
    th = np.linspace(0.0, 2 * np.pi, 73)
    h = 1e-6
    r3, r4 = fourbar_velocity_ratios(th)
    hi, lo = fourbar_pose(th + h), fourbar_pose(th - h)
    assert np.max(np.abs((hi.phi3 - lo.phi3) / (2 * h) - r3)) < 1e-8
    assert np.max(np.abs((hi.phi4 - lo.phi4) / (2 * h) - r4)) < 1e-8


def test_fourbar_virtual_work_is_potential_slope() -> None:
    """Virtual work torque = dV/dtheta, V from positions only (central difference, step
    1e-6 rad; tolerance 1e-7 of the peak torque)."""
    th = np.linspace(0.0, 2 * np.pi, 181)
    h = 1e-6
    torque = fourbar_drive_torque(th)
    slope = (fourbar_potential(th + h) - fourbar_potential(th - h)) / (2 * h)
    assert np.max(np.abs(torque - slope)) < 1e-7 * np.max(np.abs(torque))


def test_fourbar_statics_agrees_with_virtual_work() -> None:
    """Link-by-link statics and virtual work give the same drive torque (round-off), and
    the ground reactions carry the total weight (vertical) with no net horizontal force."""
    p = FourBar()
    th = np.linspace(0.0, 2 * np.pi, 181)
    loads = fourbar_static_loads(th, p)
    torque = fourbar_drive_torque(th, p)
    assert np.max(np.abs(loads["drive_torque"] - torque)) < 1e-10 * np.max(np.abs(torque))
    weight = (p.crank_mass + p.coupler_mass + p.rocker_mass) * p.g
    assert np.allclose(loads["crank_pivot_fy"] + loads["rocker_pivot_fy"], weight, rtol=1e-12)
    assert np.allclose(loads["crank_pivot_fx"] + loads["rocker_pivot_fx"], 0.0, atol=1e-12 * weight)


# ---------------------------------------------------------------- spring bar


def test_spring_bar_equilibrium_minimises_potential() -> None:
    """The moment-balance root is the minimum of V = k (s - s0)^2 / 2 + m g y_G, found by a
    separate bounded minimiser (xatol 1e-10 rad); stable (dM/dtheta < 0)."""
    p = SpringBar()
    eq = spring_bar_equilibrium(p)

    def potential(theta: float) -> float:
        tip = np.array([np.cos(theta), np.sin(theta)]) * p.tip0[0]
        s = np.linalg.norm(np.asarray(p.anchor) - tip)
        return 0.5 * p.stiffness * (s - p.free_length) ** 2 + p.mass * p.g * p.cm0[0] * np.sin(
            theta
        )

    found = minimize_scalar(
        potential, bounds=(-1.5, 1.5), method="bounded", options={"xatol": 1e-10}
    )
    assert eq["angle"] == pytest.approx(found.x, abs=1e-8)
    assert abs(spring_bar_moment(eq["angle"], p)) < 1e-10
    assert eq["stiffness"] < 0.0
    assert eq["angle"] == pytest.approx(0.465945, abs=1e-6)


def test_spring_bar_hinge_balances_forces() -> None:
    """Hinge + spring + weight = 0 on the bar (round-off); tension = k (length - free)."""
    p = SpringBar()
    eq = spring_bar_equilibrium(p)
    tip = np.array([np.cos(eq["angle"]), np.sin(eq["angle"])]) * p.tip0[0]
    span = np.asarray(p.anchor) - tip
    spring = eq["tension"] * span / np.linalg.norm(span)
    assert eq["hinge_fx"] + spring[0] == pytest.approx(0.0, abs=1e-12)
    assert eq["hinge_fy"] + spring[1] - p.mass * p.g == pytest.approx(0.0, abs=1e-12)
    assert eq["tension"] == pytest.approx(p.stiffness * (eq["length"] - p.free_length))


# ---------------------------------------------------------------- heavy top


@pytest.fixture(scope="module")
def top_solution() -> HeavyTopSolution:
    """Reference heavy-top motion, 2 s at 1 ms."""
    return heavy_top_solve(np.linspace(0.0, 2.0, 2001))


def test_heavy_top_conserves_energy_and_vertical_momentum(top_solution: HeavyTopSolution) -> None:
    """Gravity does no work about the fixed point and has no torque about the vertical:
    energy and L_z stay constant to 1e-8 relative with rtol 1e-10 (and |q| = 1)."""
    e = heavy_top_energy(top_solution)
    lz = heavy_top_vertical_momentum(top_solution)
    assert np.max(np.abs(e - e[0])) < 1e-8 * abs(e[0])
    assert np.max(np.abs(lz - lz[0])) < 1e-8 * abs(lz[0])
    assert np.allclose(np.linalg.norm(top_solution.quaternion, axis=1), 1.0, atol=1e-8)


def test_heavy_top_spin_is_constant(top_solution: HeavyTopSolution) -> None:
    """For a symmetric top the spin about the symmetry axis (body axis e) is constant
    (Euler's third equation, no torque about e): 1e-8 relative."""
    spin = top_solution.omega_body @ np.array([0.6, 0.0, 0.8])
    assert np.max(np.abs(spin - 100.0)) < 1e-8 * 100.0


def test_heavy_top_precession_rate(top_solution: HeavyTopSolution) -> None:
    """Mean precession of the axis equals the slow steady-precession root of
    I_t' cos(th) W^2 - I_a w3 W + m g h = 0 [GO 5.7] within 0.2% (released without a
    precession rate, the top nods about that mean; the fitted mean differs by 5e-4)."""
    top = HeavyTop()
    tip = top_solution.position([0.06, 0.0, 0.08])
    azimuth = np.unwrap(np.arctan2(tip[:, 1], tip[:, 0]))
    rate = np.polyfit(top_solution.t, azimuth, 1)[0]
    i_t = 0.0025 + top.mass * 0.05**2  # transverse, about the pivot
    i_a, w3, cos_th, mgh = 0.004, 100.0, 0.8, top.mass * top.g * 0.05
    slow = (i_a * w3 - np.sqrt((i_a * w3) ** 2 - 4 * i_t * cos_th * mgh)) / (2 * i_t * cos_th)
    assert rate == pytest.approx(slow, rel=2e-3)


def test_angular_velocity_from_points_recovers_omega(top_solution: HeavyTopSolution) -> None:
    """omega rebuilt from two points' velocities v = w x p equals the reference (round-off)."""
    w = top_solution.omega_global
    pos = [top_solution.position(p) for p in ([0.06, 0, 0.08], [0.03, 0.05, 0.04])]
    vel = [np.cross(w, p) for p in pos]
    rebuilt = angular_velocity_from_points(pos, vel)
    assert np.max(np.abs(rebuilt - w)) < 1e-10 * np.max(np.abs(w))


# ---------------------------------------------------------------- double pendulum


def test_double_pendulum_energy_is_conserved() -> None:
    """The energy function is constant along the Lagrange-equation motion (rtol 1e-10):
    drift below 1e-8 of the potential-well depth g (m1 c1 + m2 (L1 + c2))."""
    p = DoublePendulum()
    t = np.linspace(0.0, 10.0, 2001)
    phi0 = (np.radians(90.0), np.radians(135.0))
    y = double_pendulum_solve(t, phi0, p)
    e = double_pendulum_energy(y[:, 0], y[:, 1], y[:, 2], y[:, 3], p)
    scale = p.g * (p.mass1 * p.cm1 + p.mass2 * (p.length1 + p.cm2))
    assert np.max(np.abs(e - e[0])) < 1e-8 * scale


def test_double_pendulum_energy_from_finite_differences() -> None:
    """Kinetic energy from central differences of the centre-of-mass positions (no
    velocity formula involved) agrees with the energy function (1e-6 of the well depth)."""
    p = DoublePendulum()
    t = np.linspace(0.0, 1.0, 100_001)
    y = double_pendulum_solve(t, (np.radians(90.0), np.radians(135.0)), p)
    phi1, phi2 = y[:, 0], y[:, 1]
    u1 = np.stack([np.sin(phi1), -np.cos(phi1)], -1)
    u2 = np.stack([np.sin(phi2), -np.cos(phi2)], -1)
    g1, g2 = p.cm1 * u1, p.length1 * u1 + p.cm2 * u2
    v1, v2 = (np.gradient(g, t, axis=0, edge_order=2) for g in (g1, g2))
    w1, w2 = (np.gradient(phi, t, edge_order=2) for phi in (phi1, phi2))
    e_fd = 0.5 * (
        p.mass1 * np.sum(v1**2, -1) + p.izz1 * w1**2 + p.mass2 * np.sum(v2**2, -1) + p.izz2 * w2**2
    ) + p.g * (p.mass1 * g1[:, 1] + p.mass2 * g2[:, 1])
    e = double_pendulum_energy(phi1, phi2, y[:, 2], y[:, 3], p)
    scale = p.g * (p.mass1 * p.cm1 + p.mass2 * (p.length1 + p.cm2))
    assert np.max(np.abs(e_fd - e)) < 1e-6 * scale
