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


def test_dynamic_flywheel_warns_at_each_dead_centre_of_the_slider() -> None:
    """A free slider-crank spinning at 2 pi rad/s from phi = 90 deg: the slider's travel
    cannot change at phi = 180 deg (t = 0.25 s) and 360 deg (t = 0.75 s); one warning per
    dead centre, within one output step (0.01 s), naming the guide D."""
    omega = 2.0 * math.pi
    sol = mechlib.solve(
        _flywheel_slider_crank(),
        mechlib.Dynamic(end=0.9, step=0.01),
        initial=[InitialValue("A", rate=omega)],
        throw=False,
    )
    assert sol.ok, sol.message
    times = _toggle_times(sol.warnings)
    assert np.allclose(times, [0.25, 0.75], atol=0.01), sol.warnings
    assert all("D: travel cannot change" in w for w in sol.warnings), sol.warnings


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
    per recorded row from an independent SVD of its scaled Jacobian: the singular values
    and each free coordinate's share of its gradient outside the span of the rows (1 -
    projection onto the right singular vectors), by (joint, kind)."""
    from mechlib.checks import singularity

    captured = _capture_toggle_checks(monkeypatch)
    mechlib.solve(
        _flywheel_slider_crank(),
        mechlib.Dynamic(end=0.3, step=0.01),
        initial=[InitialValue("A", rate=2.0 * math.pi)],
    )
    system, trajectory = captured[0]
    scale = singularity._column_scale(system)
    free = singularity._free_measures(system)
    assert len(free) == 2 and len(trajectory) == 31  # A angle, D travel
    rows = []
    for i, t in enumerate(trajectory.time):
        k = system.kin(trajectory.q[i], None, t)
        jac = singularity._unit_rows(system.phi_q(k) * scale)
        _, sigma, vt = np.linalg.svd(jac, full_matrices=False)  # vt: (m, nq), the rows
        shares = {}
        for joint, measure in free:
            g = system.coordinate_gradient(measure, k) * scale
            shares[(joint, measure.kind)] = np.linalg.norm(g - vt.T @ (vt @ g)) / np.linalg.norm(g)
        rows.append((sigma, shares))
    return system, trajectory, rows


def test_toggle_series_matches_the_svd_of_each_row(monkeypatch) -> None:
    """The batched measures of a run's rows (mechlib.checks.singularity._series: eigenvalues of
    J J^T and one batched solve) against an independent SVD of each row's scaled Jacobian:
    the smallest singular value, and per free coordinate the share of its gradient outside
    the span of the rows. Tolerance 1e-9: both are exact to round-off (the inverse
    iteration used before stopped at 1e-6 and was up to 11 % high on the bench
    slider-crank)."""
    from mechlib.checks import singularity

    system, trajectory, rows = _flywheel_rows_by_svd(monkeypatch)
    ranks, sines = singularity._series(system, trajectory)
    for i, (sigma, shares) in enumerate(rows):
        assert abs(ranks[i] - sigma[-1]) <= 1e-9 * sigma[0]
        for key, share in shares.items():
            assert abs(sines[i][key] - share) <= 1e-9


def test_bounded_walk_matches_the_svd_of_each_row(monkeypatch) -> None:
    """The rows measured with bounds in one compiled call per run of rows
    (`_compiled_measures`: hand-written Cholesky, L^-1 and solves) against an independent
    SVD of each row's scaled Jacobian: lower bound <= smallest singular value <= upper
    bound (to round-off, 1e-12), each within a factor of it (lower above 0.45, upper below
    1.2 times; measured 0.494 and 1.170), and the free coordinates' shares outside the span
    of the rows to 1e-12 (measured 3.3e-16)."""
    from mechlib.checks import singularity

    system, trajectory, rows = _flywheel_rows_by_svd(monkeypatch)
    lows, highs, sines = singularity._walk(system, trajectory, bounds=True)
    for i, (sigma, shares) in enumerate(rows):
        assert lows[i] - 1e-12 <= sigma[-1] <= highs[i] + 1e-12
        assert lows[i] > 0.45 * sigma[-1] and highs[i] < 1.2 * sigma[-1]
        for key, share in shares.items():
            assert abs(sines[i][key] - share) <= 1e-12


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
    """The warnings of a run (the rank measure's bounds first, `_bounded_measures`), the
    warnings of the exact measures on the same rows, and the bounds and exact measures."""
    from mechlib.checks import singularity

    captured = _capture_toggle_checks(monkeypatch)
    sol = mechlib.solve(mech, analysis, throw=False, **kwargs)
    assert sol.ok, sol.message
    system, trajectory = captured[0]
    lows, highs, _ = singularity._walk(system, trajectory, bounds=True)
    ranks, _ = singularity._series(system, trajectory)
    with monkeypatch.context() as patch:
        exact = lambda system, trajectory, threshold: singularity._measures(  # noqa: E731
            *singularity._series(system, trajectory)
        )
        patch.setattr(singularity, "_bounded_measures", exact)
        exact_warnings = singularity.toggle_warnings(system, trajectory)
    return sol.warnings, exact_warnings, (lows, highs, ranks)


def test_rank_bounds_hold_and_the_warnings_are_the_exact_ones(monkeypatch) -> None:
    """The bounds of the rank measure (`_rank_bounds`: 1 / trace((J J^T)^-1) below, a
    Rayleigh quotient of one inverse-iteration step above) hold at every row of the
    flywheel slider-crank (against the eigenvalues, to round-off: 1e-12; measured: the upper
    bound within 1.17 and the lower within 0.47 of the measure), and are close enough there
    (every row's lower bound above 0.1 of the largest upper bound; measured 0.42, guarded at
    0.4) that no row needs the eigenvalues: the warnings, one per dead centre of the
    slider, are those of the exact measures word for word."""
    warnings, exact, (lows, highs, ranks) = _checked_run(
        monkeypatch,
        _flywheel_slider_crank(),
        mechlib.Dynamic(end=0.9, step=0.01),
        initial=[InitialValue("A", rate=2.0 * math.pi)],
    )
    assert np.all(lows <= ranks + 1e-12) and np.all(ranks <= highs + 1e-12)
    assert (lows / highs.max()).min() > 0.4
    assert len(_toggle_times(warnings)) == 2 and warnings == exact


def test_a_rank_toggle_is_measured_exactly(monkeypatch) -> None:
    """The slider driven through the crank's dead centre: there the rank measure itself
    falls (its lower bound below 0.1 of the largest), so the run's rows are measured
    exactly: the warnings are the exact measures' word for word."""
    omega = 0.9 * 2.0 * math.pi
    mech, _ = slider_crank(R, L)
    mech.add_motion("push", joint="D", function=SliderOfTurningCrank(omega))
    warnings, exact, (lows, highs, ranks) = _checked_run(
        monkeypatch, mech, mechlib.Kinematic(end=0.5, step=STEP)
    )
    assert np.all(lows <= ranks + 1e-12) and np.all(ranks <= highs + 1e-12)
    assert (lows / highs.max()).min() < 0.1
    assert len(_toggle_times(warnings)) == 1 and warnings == exact
