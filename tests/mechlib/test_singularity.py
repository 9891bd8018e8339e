"""Near-singular positions: warnings at toggles and dead points, and failures that name them.

References are closed forms of the slider-crank of `_models.slider_crank` (crank r = 0.1 m,
rod l = 0.3 m, slider on x): its dead centres are where crank and rod are collinear, crank
angle phi = 0 or 180 deg from +x (joint A's angle theta = phi - 90 deg), and the slider
cannot pass x = r + l.
"""

from __future__ import annotations

import math
import re

import numpy as np

import mechlib
from mechlib.solvers.assembly import InitialValue

from ._models import Ramp, slider_crank

R, L = 0.1, 0.3
STEP = 0.01  # s, output interval of the kinematic runs


class SliderOfTurningCrank:
    """Slider travel (m, from the design position) of a crank turning at `omega` (rad/s)
    from phi = 90 deg: x(phi) = r cos phi + sqrt(l^2 - r^2 sin^2 phi), exact rates."""

    def __init__(self, omega: float):
        self.omega = omega
        self.x0 = math.sqrt(L * L - R * R)

    def _phi(self, t: float) -> tuple[float, float, float]:
        phi = 0.5 * math.pi + self.omega * t
        return math.sin(phi), math.cos(phi), L * L - (R * math.sin(phi)) ** 2

    def value(self, t: float) -> float:
        _s, c, root2 = self._phi(t)
        return R * c + math.sqrt(root2) - self.x0

    def rate(self, t: float) -> float:
        s, c, root2 = self._phi(t)
        return (-R * s - R * R * s * c / math.sqrt(root2)) * self.omega

    def accel(self, t: float) -> float:
        s, c, root2 = self._phi(t)
        second = (
            -R * c - R * R * (c * c - s * s) / math.sqrt(root2) - R**4 * s * s * c * c / root2**1.5
        )
        return second * self.omega**2


def _toggle_times(warnings: list[str]) -> list[float]:
    return [
        float(re.search(r"at t = ([0-9.e+-]+) s", w).group(1))
        for w in warnings
        if "near-singular" in w
    ]


def test_kinematic_slider_drive_warns_at_the_dead_centre() -> None:
    """Driving the slider with the travel of a uniformly turning crank, the crank passes
    phi = 180 deg (crank and
    rod folded) at t* = (pi/2) / omega; the warning is within one output step of t* and
    names the slider's guide D with the loop joints A, B, C."""
    omega = 0.9 * 2.0 * math.pi  # t* = 0.2778 s, off the output grid
    mech, _ = slider_crank(R, L)
    mech.add_motion("push", joint="D", function=SliderOfTurningCrank(omega))
    sol = mechlib.solve(mech, mechlib.Kinematic(end=0.5, step=STEP), throw=False)
    assert sol.ok, sol.message
    times = _toggle_times(sol.warnings)
    assert len(times) == 1, sol.warnings
    assert abs(times[0] - 0.5 * math.pi / omega) <= STEP
    text = sol.warnings[0]
    assert all(name in text for name in ("A", "B", "C")) and "push" in text, text


def test_kinematic_crank_drive_has_no_warning() -> None:
    """The same mechanism driven at the crank passes the slider's dead centres without any
    singularity (the crank angle fixes every position): no warning over one turn."""
    mech, _ = slider_crank(R, L)
    mech.add_motion("turn", joint="A", function=Ramp(0.0, 2.0 * math.pi))
    sol = mechlib.solve(mech, mechlib.Kinematic(end=1.0, step=STEP))
    assert sol.ok and sol.warnings == []


def test_kinematic_failure_beyond_reach_names_the_dependent_equations() -> None:
    """Pushing the slider past x = r + l = 0.4 m (travel 0.4 - 0.2828 m, reached at
    t = 0.781 s of the ramp) fails there, and the message names the loop's equations at the
    stretched toggle instead of only the largest residuals."""
    mech, x0 = slider_crank(R, L)
    mech.add_motion("push", joint="D", function=Ramp(0.0, 0.15))
    sol = mechlib.solve(mech, mechlib.Kinematic(end=1.0, step=STEP), throw=False)
    assert not sol.ok
    reach = (R + L - x0) / 0.15
    failed_at = float(re.search(r"at t = ([0-9.e+-]+) s", sol.message).group(1))
    assert reach - STEP <= failed_at <= reach + STEP, sol.message
    assert "near-singular position" in sol.message, sol.message
    detail = sol.message.split("near-singular position")[1]
    assert sum(name in detail for name in ("A", "B", "C", "D", "push")) >= 3, sol.message


def _flywheel_slider_crank() -> mechlib.Mechanism:
    """The slider-crank with a crank of 10 kg m^2 and rod and slider of 10 g: the crank
    turns at constant speed within 1e-5 relative (their kinetic energy over the crank's)."""
    mech, xs = slider_crank(R, L)
    mech.add_body("crank", mass=1.0, cm=(0.0, R / 2, 0.0), inertia=[10.0] * 3)
    mech.add_body("rod", mass=0.01, cm=(xs / 2, R / 2, 0.0), inertia=[1e-5] * 3)
    mech.add_body("slider", mass=0.01, cm=(xs, 0.0, 0.0), inertia=[1e-6] * 3)
    return mech


def test_dynamic_flywheel_passes_its_dead_centres_without_warning() -> None:
    """A free slider-crank spinning at 2 pi rad/s from phi = 90 deg passes the slider's dead
    centres at phi = 180 deg (t = 0.25 s) and 360 deg (t = 0.75 s): the slider's travel
    merely reverses there, the constraint Jacobian keeps its full rank and the reactions
    stay bounded, so no warning (before: one per dead centre, "D: travel cannot change")."""
    omega = 2.0 * math.pi
    sol = mechlib.solve(
        _flywheel_slider_crank(),
        mechlib.Dynamic(end=0.9, step=0.01),
        initial=[InitialValue("A", rate=omega)],
        requests=[mechlib.JointCoordinate("x", "D", "travel")],
        throw=False,
    )
    assert sol.ok, sol.message
    x = sol.channels["x.value"]
    assert np.argmin(x) == 25 and np.argmax(x) == 75  # both dead centres passed
    assert sol.warnings == []


class OverCentreLeg:
    """A leg on a trunnion O = (0, 0) held by a two-piece brace from B = (1, 0) (upper
    U = 0.5 m to the knee K, lower W = 0.6 m to the leg's pin P at P_ARM = 0.8 m from O),
    driven by its leg angle along the law that takes the brace's upper link from
    psi* - OMEGA T_STAR through the straight position psi* (K on B-P) at t = T_STAR and
    over centre: theta(t) = angle of P(psi(t)), psi(t) = psi* + OMEGA (t - T_STAR). theta
    is stationary at T_STAR (the leg's limit); value, rate and accel relative to t = 0
    (central differences, step 1e-4 s)."""

    B, U, W, P_ARM, OMEGA, T_STAR = np.array([1.0, 0.0]), 0.5, 0.6, 0.8, 1.2, 0.2777

    def __init__(self) -> None:
        px = (self.P_ARM**2 + 1.0 - (self.U + self.W) ** 2) / 2.0  # |P - B| = U + W
        straight = np.array([px, -math.sqrt(self.P_ARM**2 - px * px)])
        knee = self.B + self.U / (self.U + self.W) * (straight - self.B)
        self.psi_star = math.atan2(*(knee - self.B)[::-1])
        self.side = math.copysign(1.0, knee[0] * straight[1] - knee[1] * straight[0])
        self.theta0 = self._theta(0.0)

    def knee(self, t: float) -> np.ndarray:
        psi = self.psi_star + self.OMEGA * (t - self.T_STAR)
        return self.B + self.U * np.array([math.cos(psi), math.sin(psi)])

    def pin(self, t: float) -> np.ndarray:
        """P: on the circles about O (P_ARM) and K (W), on the side of O-K it has at the
        straight position."""
        k = self.knee(t)
        d = float(np.linalg.norm(k))
        a = (self.P_ARM**2 - self.W**2 + d * d) / (2.0 * d)
        h = math.sqrt(self.P_ARM**2 - a * a)
        mid, normal = a * k / d, np.array([-k[1], k[0]]) / d
        return mid + self.side * h * normal

    def _theta(self, t: float) -> float:
        p = self.pin(t)
        return math.atan2(p[1], p[0])

    def value(self, t: float) -> float:
        return self._theta(t) - self.theta0

    def rate(self, t: float) -> float:
        return (self._theta(t + 1e-4) - self._theta(t - 1e-4)) / 2e-4

    def accel(self, t: float) -> float:
        return (self._theta(t + 1e-4) - 2.0 * self._theta(t) + self._theta(t - 1e-4)) / 1e-8


def _over_centre_lock(law: OverCentreLeg) -> mechlib.Mechanism:
    """The leg and brace of `OverCentreLeg` at t = 0, in the xy plane without redundant
    equations: trunnion and brace_top revolutes (z), knee universal (an in-plane normal of
    the lower link, z), brace_leg spherical."""
    o, b, k, p = np.zeros(2), law.B, law.knee(0.0), law.pin(0.0)

    def at(point: np.ndarray) -> tuple[float, float, float]:
        return (float(point[0]), float(point[1]), 0.0)

    mech = mechlib.Mechanism(name="over_centre_lock")
    for name, (first, second) in {"leg": (o, p), "upper": (b, k), "lower": (k, p)}.items():
        mech.add_body(name, mass=1.0, cm=at((first + second) / 2), inertia=[1e-2] * 3)
    z = (0, 0, 1)
    mech.add_joint("trunnion", "revolute", bodies=("leg", "ground"), at=at(o), axis=z)
    mech.add_joint("brace_top", "revolute", bodies=("upper", "ground"), at=at(b), axis=z)
    normal = np.array([-(p - k)[1], (p - k)[0]]) / law.W
    mech.add_joint("knee", "universal", bodies=("lower", "upper"), at=at(k), axes=(at(normal), z))
    mech.add_joint("brace_leg", "spherical", bodies=("lower", "leg"), at=at(p))
    return mech


def test_over_centre_lock_driven_at_its_leg_warns_once() -> None:
    """The leg driven through the position where its brace goes straight (the leg's limit,
    t* = 0.2777 s, off the output grid) with the brace continuing over centre: the
    Jacobian with the leg's motion row loses rank there, so exactly one warning, within one
    output step of t*, naming the motion and the brace's joints (at most five joints)."""
    law = OverCentreLeg()
    mech = _over_centre_lock(law)
    mech.add_motion("swing", joint="trunnion", function=law)
    sol = mechlib.solve(
        mech,
        mechlib.Kinematic(end=0.5, step=STEP),
        requests=[mechlib.JointCoordinate("psi", "brace_top")],
        throw=False,
    )
    assert sol.ok, sol.message
    psi = sol.channels["psi.value"]  # from its design value psi* - OMEGA T_STAR
    assert psi[0] < law.OMEGA * law.T_STAR < psi[-1]  # through the straight position
    times = _toggle_times(sol.warnings)
    assert len(times) == 1, sol.warnings
    assert abs(times[0] - law.T_STAR) <= STEP
    text = sol.warnings[0]
    assert "swing" in text and all(n in text for n in ("knee", "brace_top")), text


def test_over_centre_lock_driven_at_its_knee_has_no_warning() -> None:
    """The same brace driven at its upper link (the knee's side) through the straight
    position: the leg merely stops and turns back, the Jacobian with that motion row has
    full rank: no warning."""
    law = OverCentreLeg()
    mech = _over_centre_lock(law)
    mech.add_motion("fold", joint="brace_top", function=Ramp(0.0, law.OMEGA))
    sol = mechlib.solve(mech, mechlib.Kinematic(end=0.5, step=STEP), throw=False)
    assert sol.ok, sol.message
    assert sol.warnings == []


def test_pendulum_has_no_warning() -> None:
    """A single hinge is never near-singular: its coordinate is the motion."""
    mech = mechlib.Mechanism(name="pendulum", gravity=(0.0, -9.81, 0.0))
    mech.add_body("bar", mass=1.0, cm=(0.5, 0.0, 0.0), inertia=[1e-3, 0.08, 0.08])
    mech.add_joint("hinge", "revolute", bodies=("bar", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    sol = mechlib.solve(mech, mechlib.Dynamic(end=1.0, step=0.01))
    assert sol.ok and sol.warnings == []


def _capture_toggle_checks(monkeypatch) -> list:
    """The (system, trajectory) of each run's toggle check from now on, in order."""
    import importlib

    from mechlib.checks import singularity

    captured: list = []

    def capture(system, trajectory, threshold=singularity.TOGGLE_THRESHOLD):
        captured.append((system, trajectory))
        return singularity.toggle_warnings(system, trajectory, threshold)

    monkeypatch.setattr(
        importlib.import_module("mechlib.solvers.solve"), "toggle_warnings", capture
    )
    return captured


def _flywheel_rows_by_svd(monkeypatch) -> tuple:
    """The flywheel slider-crank's 0.3 s run, its toggle check's (system, trajectory), and
    per recorded row the singular values of its scaled Jacobian from an independent SVD."""
    from mechlib.checks import singularity

    captured = _capture_toggle_checks(monkeypatch)
    mechlib.solve(
        _flywheel_slider_crank(),
        mechlib.Dynamic(end=0.3, step=0.01),
        initial=[InitialValue("A", rate=2.0 * math.pi)],
    )
    system, trajectory = captured[0]
    scale = singularity._column_scale(system)
    assert len(trajectory) == 31
    rows = []
    for i, t in enumerate(trajectory.time):
        k = system.kin(trajectory.q[i], None, t)
        jac = singularity._unit_rows(system.phi_q(k) * scale)
        rows.append(np.linalg.svd(jac, compute_uv=False))
    return system, trajectory, rows


def test_toggle_series_matches_the_svd_of_each_row(monkeypatch) -> None:
    """The batched measures of a run's rows (mechlib.checks.singularity._series: eigenvalues of
    J J^T) against an independent SVD of each row's scaled Jacobian: the smallest
    singular value. Tolerance 1e-9: it is exact to round-off (the inverse
    iteration used before stopped at 1e-6 and was up to 11 % high on the bench
    slider-crank)."""
    from mechlib.checks import singularity

    system, trajectory, rows = _flywheel_rows_by_svd(monkeypatch)
    ranks = singularity._series(system, trajectory)
    for i, sigma in enumerate(rows):
        assert abs(ranks[i] - sigma[-1]) <= 1e-9 * sigma[0]


def test_bounded_walk_matches_the_svd_of_each_row(monkeypatch) -> None:
    """The rows measured with bounds in one compiled call per run of rows
    (`_compiled_measures`: hand-written Cholesky, L^-1 and solves) against an independent
    SVD of each row's scaled Jacobian: lower bound <= smallest singular value <= upper
    bound (to round-off, 1e-12), each within a factor of it (lower above 0.45, upper below
    1.2 times; measured 0.494 and 1.170)."""
    from mechlib.checks import singularity

    system, trajectory, rows = _flywheel_rows_by_svd(monkeypatch)
    lows, highs = singularity._walk(system, trajectory, bounds=True)
    for i, sigma in enumerate(rows):
        assert lows[i] - 1e-12 <= sigma[-1] <= highs[i] + 1e-12
        assert lows[i] > 0.45 * sigma[-1] and highs[i] < 1.2 * sigma[-1]


def test_lower_inverse_is_the_inverse_cholesky_factor() -> None:
    """`_lower_inverse` (the bounds' hand-written Cholesky and L^-1, by rows) against
    numpy's Cholesky factor and its inverse (1e-12 relative, Gram matrices of 1 to 40
    random rows); False for a matrix that is not positive definite, or not finite."""
    from mechlib.checks import singularity

    rng = np.random.default_rng(7)
    for m in (1, 2, 7, 20, 40):
        rows = rng.normal(size=(m, m + 3))
        gram = rows @ rows.T
        low = np.linalg.cholesky(gram)
        work, inverse = gram.copy(), np.full((m, m), 5.0)
        assert singularity._lower_inverse(work, inverse)
        assert np.allclose(np.tril(work), low, rtol=0.0, atol=1e-12 * np.abs(low).max())
        expected = np.linalg.inv(low)
        assert np.allclose(
            np.tril(inverse), expected, rtol=0.0, atol=1e-12 * np.abs(expected).max()
        )
    indefinite = np.array([[1.0, 2.0], [2.0, 1.0]])
    assert not singularity._lower_inverse(indefinite, np.empty((2, 2)))
    assert not singularity._lower_inverse(
        np.array([[4.0, np.nan], [np.nan, 4.0]]), np.empty((2, 2))
    )


def test_assembly_to_two_consistent_given_values_in_stages() -> None:
    """Crank angle and slider travel given together, consistent at the end (the closed form
    x(phi) of SliderOfTurningCrank at crank angle 90 deg + 1.5 rad) but not along the
    assembly's three stages of at most 30 deg: each inconsistent stage stops at its
    least-squares point (before: 50 Newton iterations per stage), and the assembled
    position meets both values within 1e-9."""
    from mechlib.solvers.assembly import assemble
    from mechlib.system.system import System

    mech, _ = slider_crank(R, L)
    turn = 1.5
    travel = SliderOfTurningCrank(1.0).value(turn)  # omega 1 rad/s: t = turn
    system = System(mech)
    done = assemble(system, 0.0, [InitialValue("A", value=turn), InitialValue("D", value=travel)])
    k = system.kin(done.q, None, 0.0)
    assert abs(system.measure("A", "angle").value(k) - turn) <= 1e-9
    assert abs(system.measure("D", "travel").value(k) - travel) <= 1e-9
    assert done.notes == [] and done.newton_iterations <= 30


def _checked_run(monkeypatch, mech, analysis, **kwargs) -> tuple[list, list, tuple]:
    """The warnings of a run (the rank measure's bounds first, `_toggle_measures`), the
    warnings of the exact measures on the same rows, and the bounds and exact measures."""
    from mechlib.checks import singularity

    captured = _capture_toggle_checks(monkeypatch)
    sol = mechlib.solve(mech, analysis, throw=False, **kwargs)
    assert sol.ok, sol.message
    system, trajectory = captured[0]
    lows, highs = singularity._walk(system, trajectory, bounds=True)
    ranks = singularity._series(system, trajectory)
    with monkeypatch.context() as patch:
        exact = lambda system, trajectory, threshold: singularity._relative(  # noqa: E731
            singularity._series(system, trajectory)
        )
        patch.setattr(singularity, "_toggle_measures", exact)
        exact_warnings = singularity.toggle_warnings(system, trajectory)
    return sol.warnings, exact_warnings, (lows, highs, ranks)


def test_rank_bounds_hold_and_the_warnings_are_the_exact_ones(monkeypatch) -> None:
    """The bounds of the rank measure (`_rank_bounds`: 1 / trace((J J^T)^-1) below, a
    Rayleigh quotient of one inverse-iteration step above) hold at every row of the
    flywheel slider-crank (against the eigenvalues, to round-off: 1e-12; measured: the upper
    bound within 1.17 and the lower within 0.47 of the measure), and are close enough there
    (every row's lower bound above 0.1 of the largest upper bound; measured 0.42, guarded at
    0.4) that no row needs the eigenvalues: no warning, as from the exact measures (the
    slider's dead centres are no rank loss)."""
    warnings, exact, (lows, highs, ranks) = _checked_run(
        monkeypatch,
        _flywheel_slider_crank(),
        mechlib.Dynamic(end=0.9, step=0.01),
        initial=[InitialValue("A", rate=2.0 * math.pi)],
    )
    assert np.all(lows <= ranks + 1e-12) and np.all(ranks <= highs + 1e-12)
    assert (lows / highs.max()).min() > 0.4
    assert warnings == exact == []


def test_a_rank_toggle_is_measured_exactly(monkeypatch) -> None:
    """The slider driven through the crank's dead centre: there the rank measure itself
    falls (its lower bound below 0.1 of the largest), so the run's rows are measured
    exactly: the toggle warnings are the exact measures' word for word. Driven through the
    dead centre, the crank passes onto the other branch of the slider's position: the
    constraints' orientation flips there, which the run also reports (mechlib.solvers.branches)."""
    omega = 0.9 * 2.0 * math.pi
    mech, _ = slider_crank(R, L)
    mech.add_motion("push", joint="D", function=SliderOfTurningCrank(omega))
    warnings, exact, (lows, highs, ranks) = _checked_run(
        monkeypatch, mech, mechlib.Kinematic(end=0.5, step=STEP)
    )
    assert np.all(lows <= ranks + 1e-12) and np.all(ranks <= highs + 1e-12)
    assert (lows / highs.max()).min() < 0.1
    toggles = [w for w in warnings if not w.startswith("assembly branch changed")]
    assert len(_toggle_times(toggles)) == 1 and toggles == exact
    (branch,) = [w for w in warnings if w.startswith("assembly branch changed")]
    assert branch.startswith(f"assembly branch changed at t = {_toggle_times(toggles)[0]:g} s")


def test_a_dynamic_run_driven_onto_a_dead_centre_names_it() -> None:
    """The slider driven exactly onto the crank's dead centre (t* = 0.25 s, on the output
    grid) in a dynamic run: the constraints, the motion included, lose rank there. The
    run used to stall there (exit 1, naming the travel and the loop joints; still so with
    the carry rule at shrinks); since the ceiling after a Newton failure
    (rules.step_size) it goes through on the branch the crank's own motion takes (traced
    with numba off: the same run with the ceiling lifted stalls at 0.25 s, the step
    size falling to its 1e-12 s floor there), the crank's angle
    omega t within 1e-6 rad after the dead centre (measured 2.5e-7 at t*, 1e-14 after),
    and the near-singular warning names the position, the travel and the loop joints."""
    omega = 2.0 * math.pi
    mech, _ = slider_crank(R, L)
    mech.add_motion("push", joint="D", function=SliderOfTurningCrank(omega))
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=0.5, step=STEP),
        throw=False,
        requests=[mechlib.JointCoordinate("a", "A")],
    )
    assert sol.ok, sol.message
    after = np.asarray(sol.time) > 0.25 + STEP / 2
    angle = np.asarray(sol.channels["a.value"])[after]
    assert np.abs(angle - omega * np.asarray(sol.time)[after]).max() < 1e-6
    warning = next(w for w in sol.warnings if "near-singular position" in w)
    assert "t = 0.25 s" in warning and "push" in warning, warning
    assert all(name in warning for name in ("A", "B", "C")), warning
    assert "no mass or stiffness" not in warning, warning


def test_chained_bounds_hold_at_every_row(monkeypatch) -> None:
    """The toggle check's bounds taken at the rows `_chained` measures only, the rows
    after a measured row bounded from it by Weyl's inequality (the Frobenius distance of
    their scaled Jacobians): at every row of the flywheel slider-crank lower bound <=
    smallest singular value (an independent SVD) <= upper bound, to round-off (1e-12);
    the measured rows' bounds are those of the walk measuring every row, bit for bit. Its
    rows 0.063 rad of crank apart move the scaled Jacobian by up to 0.11 in a few rows, so
    a row is measured once its bound from the last measured one would fall below _REACH
    times the threshold (0.2 of the largest upper bound): the check stays conclusive
    (every row's lower bound at least 0.2 of the largest upper bound, no eigenvalues
    needed; measured 0.235) with fewer rows measured than the run has (measured 16 of
    31)."""
    from mechlib.checks import singularity

    system, trajectory, rows = _flywheel_rows_by_svd(monkeypatch)
    every = singularity._walk(system, trajectory, bounds=True)
    level = singularity.TOGGLE_THRESHOLD
    lows, highs = singularity._walk(system, trajectory, True, level)
    for i, sigma in enumerate(rows):
        assert lows[i] - 1e-12 <= sigma[-1] <= highs[i] + 1e-12
    measured = (lows == every[0]) & (highs == every[1])
    assert measured[0] and np.count_nonzero(measured) < len(trajectory)
    assert (lows / highs.max()).min() >= singularity._REACH * level


def test_the_campaign_rows_are_chained_far_from_the_threshold(monkeypatch) -> None:
    """The campaign's bench slider-crank (benchmarks/models/slider_crank.case.yaml: free,
    crank at 1 rev/s; 0.2 s of its 1001 rows of 1 ms, 0.0063 rad of crank apart): the
    scaled Jacobian moves 0.007-0.010 a row (at most 0.0103 over the 1001), the rank
    measure's lower bound at the first row is 0.14 (0.45 of the largest upper bound), so a
    measured row bounds the rows after it until they have moved about 0.07: at most an
    eighth of the rows are measured (measured 15 of 201; every 4th before, 51), every
    row's bounds hold against an independent SVD (1e-12) and the check stays conclusive
    (no warning, no eigenvalue)."""
    from mechlib.checks import singularity

    captured = _capture_toggle_checks(monkeypatch)
    mech = mechlib.Mechanism(name="slider_crank", gravity=(0.0, -9.81, 0.0))
    mech.add_body("crank", mass=1.2, cm=(0.05, 0, 0), inertia=(1e-4, 1e-3, 1e-3))
    mech.add_body("rod", mass=0.8, cm=(0.25, 0, 0), inertia=(1e-4, 6e-3, 6e-3))
    mech.add_body("slider", mass=2.0, cm=(0.4, 0, 0), inertia=(1e-3, 1e-3, 1e-3))
    mech.add_joint("pivot", "revolute", bodies=("crank", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_joint("big", "spherical", bodies=("rod", "crank"), at=(0.1, 0, 0))
    mech.add_joint(
        "small", "universal", bodies=("slider", "rod"), at=(0.4, 0, 0),
        axes=((0, 0, 1), (0, 1, 0)),
    )  # fmt: skip
    mech.add_joint(
        "guide", "prismatic", bodies=("slider", "ground"), at=(0.4, 0, 0), axis=(1, 0, 0)
    )
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=0.2, step=0.001),
        initial=[InitialValue("pivot", rate=2.0 * math.pi)],
    )
    assert sol.ok and sol.warnings == []
    system, trajectory = captured[0]
    scale = singularity._column_scale(system)
    every = singularity._walk(system, trajectory, bounds=True)
    lows, highs = singularity._walk(system, trajectory, True, singularity.TOGGLE_THRESHOLD)
    for i, t in enumerate(trajectory.time):
        jac = singularity._unit_rows(system.phi_q(system.kin(trajectory.q[i], None, t)) * scale)
        sigma = np.linalg.svd(jac, compute_uv=False)[-1]
        assert lows[i] - 1e-12 <= sigma <= highs[i] + 1e-12
    measured = np.count_nonzero((lows == every[0]) & (highs == every[1]))
    assert len(trajectory) == 201 and measured <= len(trajectory) // 8
    assert (lows / highs.max()).min() >= singularity._REACH * singularity.TOGGLE_THRESHOLD


def test_a_crossing_between_sampled_rows_still_warns(monkeypatch) -> None:
    """The slider driven through the crank's dead centre at t* = 0.2778 s, on row 6 of rows
    t* / 6 apart (0.26 rad of crank): midway between rows 4 and 8, which the strided
    bounds measure. Those rows' own bounds alone would pass the check (lower bounds 0.34
    of the largest upper bound, above the threshold 0.1: sampling them would miss the
    dead centre), but the Weyl bounds of the rows between them (`_between`) fall below
    it, so the rows are measured exactly: one warning, the exact measures' word for word,
    at t* (exact measure 0 there; closed form: crank and rod folded)."""
    from mechlib.checks import singularity

    omega = 0.9 * 2.0 * math.pi
    t_star = 0.5 * math.pi / omega
    mech, _ = slider_crank(R, L)
    mech.add_motion("push", joint="D", function=SliderOfTurningCrank(omega))
    captured = _capture_toggle_checks(monkeypatch)
    sol = mechlib.solve(mech, mechlib.Kinematic(end=2 * t_star, step=t_star / 6), throw=False)
    assert sol.ok, sol.message
    system, trajectory = captured[0]
    ranks = singularity._series(system, trajectory)
    assert len(trajectory) == 13 and ranks[6] / ranks.max() < 1e-6
    every_lows, every_highs = singularity._walk(system, trajectory, bounds=True)
    sampled = np.arange(0, len(trajectory), 4)
    assert (every_lows[sampled] / every_highs.max()).min() > 0.3
    lows, highs = singularity._walk(system, trajectory, True, singularity.TOGGLE_THRESHOLD)
    assert (lows / highs.max()).min() < singularity.TOGGLE_THRESHOLD
    with monkeypatch.context() as patch:
        exact_measures = lambda system, trajectory, threshold: singularity._relative(  # noqa: E731
            singularity._series(system, trajectory)
        )
        patch.setattr(singularity, "_toggle_measures", exact_measures)
        exact = singularity.toggle_warnings(system, trajectory)
    toggles = [w for w in sol.warnings if w.startswith(singularity.NEAR_SINGULAR)]
    assert toggles == exact
    (time,) = _toggle_times(toggles)
    assert abs(time - t_star) <= 1e-6  # printed to 6 digits
