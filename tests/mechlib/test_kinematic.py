"""Kinematic analysis: reactions from the equations of motion against hand Newton-Euler,
the degrees-of-freedom check, and the failure at a toggle position.

Model: uniform bar (m = 2 kg, L = 1 m) hinged at its end at the origin, axis +z, gravity
(0, -g, 0), driven by a motion theta(t) on the hinge. Newton-Euler about the fixed hinge O
(I_O = m L^2 / 3, cm at d = L/2):
    force on the bar from ground:   F = m (a_cm - g_vec),
    a_cm = d (-theta'^2 (cos, sin) + theta'' (-sin, cos)),
    drive torque about +z:          tau = I_O theta'' + m g d cos(theta).
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import mechlib

from ._models import Bar, G, Ramp, Sine, hinged_bar, slider_crank

BAR = Bar()


def _hand_reactions(
    theta: np.ndarray, omega: np.ndarray, alpha: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(fx, fy, tau) on the bar from ground and drive, by Newton-Euler (see module)."""
    d = BAR.length / 2.0
    ax = d * (-(omega**2) * np.cos(theta) - alpha * np.sin(theta))
    ay = d * (-(omega**2) * np.sin(theta) + alpha * np.cos(theta))
    tau = BAR.i_end * alpha + BAR.mass * G * d * np.cos(theta)
    return BAR.mass * ax, BAR.mass * (ay + G), tau


def _driven(function) -> mechlib.Solution:
    mech = hinged_bar(BAR)
    mech.add_motion("drive", joint="hinge", function=function)
    return mechlib.solve(
        mech,
        mechlib.Kinematic(1.0, 0.05),
        requests=[
            mechlib.JointReaction("R", "hinge"),
            mechlib.MotionEffort("E", "drive"),
            mechlib.JointCoordinate("angle", "hinge"),
            mechlib.JointCoordinate("w", "hinge", "omega"),
            mechlib.JointCoordinate("al", "hinge", "alpha"),
        ],
    )


def test_constant_speed_reactions_match_newton_euler() -> None:
    """theta = 0.2 + 3 t: hinge force = m (a_cm - g) with centripetal a_cm, drive torque
    = m g (L/2) cos(theta). Kinematic analysis is exact up to Newton's 1e-10: tolerance
    1e-9 of the peak force (m (g + omega^2 L/2) = 28.6 N)."""
    sol = _driven(Ramp(0.2, 3.0))
    theta = 0.2 + 3.0 * sol.time
    fx, fy, tau = _hand_reactions(theta, np.full_like(theta, 3.0), np.zeros_like(theta))
    peak = BAR.mass * (G + 9.0 * BAR.length / 2)
    ch = sol.channels
    assert np.abs(ch["angle.value"] - theta).max() < 1e-10
    assert np.abs(ch["R.fx"] - fx).max() < 1e-9 * peak
    assert np.abs(ch["R.fy"] - fy).max() < 1e-9 * peak
    assert np.abs(ch["R.fz"]).max() < 1e-9 * peak
    assert np.abs(ch["E.value"] - tau).max() < 1e-9 * peak
    # the reaction of the driven joint includes the drive torque (requests.py convention)
    assert np.abs(ch["R.tz"] - tau).max() < 1e-9 * peak
    assert np.abs(ch["R.tx"]).max() < 1e-9 * peak and np.abs(ch["R.ty"]).max() < 1e-9 * peak


def test_oscillating_drive_includes_inertia_torque() -> None:
    """theta = 0.5 sin(4 t): the drive torque carries I_O theta'' besides the weight
    moment; omega and alpha channels equal the exact rates. Tolerance 1e-9 of the peak."""
    motion = Sine(0.0, 0.5, 4.0)
    sol = _driven(motion)
    t = sol.time
    theta = np.array([motion.value(x) for x in t])
    omega = np.array([motion.rate(x) for x in t])
    alpha = np.array([motion.accel(x) for x in t])
    fx, fy, tau = _hand_reactions(theta, omega, alpha)
    peak = float(np.abs(tau).max())
    ch = sol.channels
    assert np.abs(ch["w.value"] - omega).max() < 1e-9 * np.abs(omega).max()
    assert np.abs(ch["al.value"] - alpha).max() < 1e-9 * np.abs(alpha).max()
    assert np.abs(ch["E.value"] - tau).max() < 1e-9 * peak
    assert np.abs(ch["R.fx"] - fx).max() < 1e-9 * peak
    assert np.abs(ch["R.fy"] - fy).max() < 1e-9 * peak


def test_free_degree_of_freedom_is_refused_by_name() -> None:
    """A hinged bar without motion has one degree of freedom: kinematic analysis raises
    ModelError saying so, naming the (absent) motions."""
    with pytest.raises(mechlib.ModelError) as info:
        mechlib.solve(hinged_bar(BAR), mechlib.Kinematic(1.0, 0.1))
    message = str(info.value)
    assert "degrees of freedom" in message
    assert "has 1" in message and "(none)" in message


def test_overconstrained_by_motions_is_refused() -> None:
    """Two motions on one hinge: the second is a redundant equation, named as such."""
    mech = hinged_bar(BAR)
    mech.add_motion("m1", joint="hinge", function=Ramp(0.0, 1.0))
    mech.add_motion("m2", joint="hinge", function=Ramp(0.0, 1.0))
    with pytest.raises(mechlib.ModelError, match="redundant constraint: m2: angle of hinge"):
        mechlib.solve(mech, mechlib.Kinematic(1.0, 0.1))


SLIDER_SPEED = 0.15  # m/s pushed on the slider


def _pushed_slider_crank() -> tuple[mechlib.Mechanism, float]:
    """Slider-crank (crank 0.1 m, rod 0.3 m) whose slider is driven outwards at 0.15 m/s:
    the reach x = 0.4 m (crank and rod aligned, dead point) is met at t* (returned)."""
    mech, xs = slider_crank(0.1, 0.3)
    mech.add_motion("push", joint="D", function=Ramp(0.0, SLIDER_SPEED))
    return mech, (0.4 - xs) / SLIDER_SPEED


def test_driving_past_the_dead_point_fails_by_time() -> None:
    """Pushing the slider past the reach: the solution fails (status 'failed') between t* =
    0.781 s and the next output time (steps Newton cannot take are halved, which locates
    the failure), with a message saying it did not converge (or is singular) and when; the
    outputs up to then are kept."""
    mech, t_star = _pushed_slider_crank()
    step = 0.01
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(1.0, step),
        throw=False,
        requests=[mechlib.JointCoordinate("x", "D", "travel")],
    )
    assert sol.status == "failed"
    assert "did not converge" in sol.message or "singular" in sol.message
    t_fail = math.ceil(t_star / step) * step
    times = [float(m) for m in re.findall(r"t = ([0-9.]+) s", sol.message)]
    assert times and t_star <= times[0] <= t_fail, sol.message
    assert sol.time[-1] == pytest.approx(t_fail - step, abs=1e-12)
    assert sol.channels["x.value"][-1] == pytest.approx(SLIDER_SPEED * sol.time[-1], abs=1e-10)


def test_dead_point_failure_raises_with_time_when_throwing() -> None:
    """With throw=True the same failure raises SolverFailure carrying the time."""
    mech, t_star = _pushed_slider_crank()
    with pytest.raises(mechlib.SolverFailure) as info:
        mechlib.solve(mech, mechlib.Kinematic(1.0, 0.01))
    assert t_star < info.value.time < t_star + 0.01  # located within the output step
    assert f"t = {info.value.time:.6g} s" in str(info.value)


def test_coarse_output_step_on_a_fast_crank() -> None:
    """A crank at 2 rev/s for 1.2 s sampled every 0.3 s (3.8 rad per output) is a valid
    kinematic run: the final angle is 4.8 pi (1e-9 rad)."""
    mech = hinged_bar(BAR)
    mech.add_motion("spin", joint="hinge", function=Ramp(0.0, 4.0 * math.pi))
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(1.2, 0.3),
        throw=False,
        requests=[mechlib.JointCoordinate("angle", "hinge")],
    )
    assert sol.ok, sol.message
    assert sol.channels["angle.value"][-1] == pytest.approx(4.8 * math.pi, abs=1e-9)


def _matches_newton_euler(sol: mechlib.Solution, motion, tolerance: float) -> None:
    """Angle (rad, unwrapped), hinge force and drive torque of `sol` against Newton-Euler
    (module docstring) of `motion`'s exact rates, `tolerance` of the peak load."""
    t = sol.time
    theta = np.array([motion.value(x) for x in t])
    omega = np.array([motion.rate(x) for x in t])
    alpha = np.array([motion.accel(x) for x in t])
    fx, fy, tau = _hand_reactions(theta, omega, alpha)
    peak = max(np.abs(fx).max(), np.abs(fy).max(), np.abs(tau).max())
    ch = sol.channels
    assert np.abs(ch["angle.value"] - theta).max() <= 1e-9 * np.abs(theta).max()
    for got, hand in ((ch["R.fx"], fx), (ch["R.fy"], fy), (ch["E.value"], tau)):
        assert np.abs(got - hand).max() < tolerance * peak


@pytest.mark.parametrize(
    ("motion", "per_step"),
    [(Ramp(0.2, -25000.0), 3), (Sine(0.0, 1000.0, 400.0), 8)],
    ids=["ramp-25000rad/s", "sine-1000rad-400rad/s"],
)
def test_drive_turning_hundreds_of_turns_per_output_step(motion, per_step: int) -> None:
    """Issue 39 (`--set 'speed=-025 kN'`): a drive turning 1250 rad (199 turns) between two
    output times was solved only by halving the step about 1000 times per output time (the
    angle unwraps within pi of the state before; 13 s CPU for 11 steps). The drive now sets
    its angle's turn and the guess turns the body by its rates: no step halved, at most
    `per_step` Newton iterations per output time (measured 2.4 and 6.2), the angle
    continuous and the loads as Newton-Euler to 1e-10 of the peak (measured 3e-12 of
    6.25e8 N and 4e-14: the angle's own round-off, 25000 rad x 1.1e-16)."""
    sol = _driven(motion)
    assert sol.status == "ok", sol.message
    assert sol.stats.rejected_steps == 0
    assert sol.stats.newton_iterations <= per_step * len(sol.time)
    _matches_newton_euler(sol, motion, 1e-10)


def test_drive_angle_beyond_double_resolution_fails_by_name_without_noise(capfd) -> None:
    """Issue 39 (`--set speed=1e150`): a drive asking for 1e148 rad reached LAPACK with
    overflowing positions (NumPy's overflow warning, 'DLASCL parameter number 4 had an
    illegal value' on stderr). Beyond ANGLE_LIMIT (4.5e8 rad: 2.2e-16 x angle above 1e3 x
    the position tolerance) the run fails naming the motion, the angle and the time, with
    nothing printed and no warning."""
    mech = hinged_bar(BAR)
    mech.add_motion("drive", joint="hinge", function=Ramp(0.0, 1e150))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = mechlib.solve(mech, mechlib.Kinematic(1.0, 0.05), throw=False)
    assert sol.status == "failed"
    assert "drive: angle of hinge is set to " in sol.message
    assert "rad, beyond +-4.5e+08 rad" in sol.message and " at t = " in sol.message
    assert sol.time.tolist() == [0.0]
    printed = capfd.readouterr()
    assert printed.out == "" and printed.err == ""


def test_drive_angle_limit_keeps_every_angle_newton_meets() -> None:
    """Just below ANGLE_LIMIT (4e8 rad at t = 0.5 s, 8e8 rad/s) the drive is still solved:
    no halved step, the loads as Newton-Euler to 1e-6 of the peak (1.6e17 N; the angle's
    round-off, 4e8 rad x 1.1e-16 = 4.4e-8 rad, is what is left)."""
    mech = hinged_bar(BAR)
    motion = Ramp(0.0, 8e8)
    mech.add_motion("drive", joint="hinge", function=motion)
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(0.5, 0.05),
        requests=[
            mechlib.JointReaction("R", "hinge"),
            mechlib.MotionEffort("E", "drive"),
            mechlib.JointCoordinate("angle", "hinge"),
        ],
    )
    assert sol.stats.rejected_steps == 0
    _matches_newton_euler(sol, motion, 1e-6)
