"""Dense output (`analysis.output: dense`, mechlib.solvers.dense): steps independent of the output
interval, rows interpolated and projected (issue 14 item 2).

References: a quintic polynomial (the Hermite interpolant is exact for it); the run itself
at another output interval (the rows at common times must not change); the pendulum's
equation of motion at each row's own state (the reaction m (a - g) of the point mass from
the row's angle and rate); the exact time of a latch event (theta = pi (1 - cos wn t)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.solvers.dense import hermite

G, L = 9.81, 1.0  # m/s^2, m: a 1 kg point mass on a 1 m massless link, released horizontal


def _pendulum() -> ml.Mechanism:
    mech = ml.Mechanism(gravity=(0.0, -G, 0.0))
    mech.add_body("ball", mass=1.0, cm=(L, 0, 0), inertia=[1e-6, 1e-6, 1e-6])
    mech.add_joint("hinge", "revolute", bodies=("ball", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    return mech


_REQUESTS = [
    ml.JointCoordinate("angle", "hinge", "angle"),
    ml.JointCoordinate("rate", "hinge", "omega"),
    ml.JointReaction("hinge_force", "hinge"),
]


def _run(step: float, integrator: str = "generalized-alpha") -> ml.Solution:
    spec = ml.Dynamic(end=END, step=step, dense=True, integrator=integrator)
    sol = ml.solve(_pendulum(), spec, requests=_REQUESTS)
    assert sol.ok, sol.message
    return sol


END = 0.5  # s: the pendulum from horizontal to 40 deg below it


@pytest.fixture(scope="module")
def fine() -> ml.Solution:
    return _run(1e-3)


def test_hermite_is_exact_for_a_quintic() -> None:
    """Given (q, qd, qdd) of a quintic at both ends, the interpolant returns its q and qd
    anywhere between them (to 1e-14)."""
    c = np.random.default_rng(1).normal(size=(6, 3))
    q = lambda t: sum(c[k] * t**k for k in range(6))  # noqa: E731
    qd = lambda t: sum(k * c[k] * t ** (k - 1) for k in range(1, 6))  # noqa: E731
    qdd = lambda t: sum(k * (k - 1) * c[k] * t ** (k - 2) for k in range(2, 6))  # noqa: E731
    t0, t1 = 0.3, 0.9
    for t in (0.3, 0.47, 0.77, 0.9):
        got = hermite(t0, t1, (q(t0), qd(t0), qdd(t0)), (q(t1), qd(t1), qdd(t1)), t)
        assert np.abs(got[0] - q(t)).max() < 1e-14
        assert np.abs(got[1] - qd(t)).max() < 1e-13


@pytest.mark.parametrize("integrator", ["generalized-alpha", "radau"])
def test_rows_do_not_depend_on_the_output_step(request, integrator: str) -> None:
    """The pendulum over 0.5 s at output steps 1e-3 and 1e-1: the same steps (their count
    does not depend on the output step), and at the common times the same values to 1e-12
    of each channel's peak (measured: identical). Every output time has its row."""
    if integrator == "radau":
        fine = _run(1e-3, integrator)
    else:
        fine = request.getfixturevalue("fine")
    coarse = _run(1e-1, integrator)
    assert fine.stats.steps == coarse.stats.steps
    assert len(fine.time) == 501 and len(coarse.time) == 6
    common = np.isin(np.round(fine.time, 9), np.round(coarse.time, 9))
    for name, values in coarse.channels.items():
        peak = max(np.abs(values).max(), 1e-9)
        assert np.abs(fine.channels[name][common] - values).max() <= 1e-12 * peak, name


def test_interpolated_rows_hold_the_equations_of_motion(fine) -> None:
    """At every row, also between the steps, the hinge reaction is the point mass's
    m (a - g) from the row's own angle and rate (a = L (alpha t - w^2 r), alpha =
    -(g / L) cos theta): within 2e-6 of m g (the ball's 1e-6 kg*m^2 inertia is the
    difference, measured 1.0e-6: the rows' qdd and lam are solved there, not
    interpolated). The energy integral w^2 = 2 g sin(-theta) / L within 1e-3 of 2 g
    (measured 4.3e-4 with 81 steps at the default tolerance 1e-6: the steps grow to the
    natural time sqrt(L / g) = 0.32 s; capped at the output interval, the `steps` mode's
    are 10 ms and its error smaller)."""
    sol = fine
    assert sol.stats.steps < 100  # the steps are not the output times (500)
    theta, w = sol.channels["angle.value"], sol.channels["rate.value"]
    alpha = -(G / L) * np.cos(theta)
    r = np.stack([np.cos(theta), np.sin(theta)])
    tang = np.stack([-np.sin(theta), np.cos(theta)])
    acc = L * (alpha * tang - w**2 * r)
    force = np.stack([sol.channels["hinge_force.fx"], sol.channels["hinge_force.fy"]])
    # the reaction on the ball from ground: m a = F + m g
    assert np.abs(force - (acc - np.array([[0.0], [-G]]))).max() < 2e-6 * G
    # energy: w^2 = 2 g sin(-theta) / L for the release from horizontal
    assert np.abs(w**2 - 2 * G * np.sin(-theta) / L).max() < 1e-3 * 2 * G


def test_events_land_exactly_in_dense_runs() -> None:
    """test_events' latch (torsion spring k = 2 N*m/rad free at pi, lock at 90 deg,
    exact time (pi/3)/wn) with dense output at tolerance 1e-10: the event within 1e-6 s
    of its exact time with its own row; every output time has its row, in order."""
    mech = ml.Mechanism(gravity=(0.0, 0.0, 0.0))
    mech.add_body("panel", mass=1.0, cm=(0, 0, 0), inertia=[0.5, 0.5, 0.5])
    mech.add_joint("hinge", "revolute", bodies=("panel", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_force(ml.TorsionSpring("drive", "hinge", stiffness=2.0, angle0=math.pi))
    latch = ml.Event(
        "latch", lambda t, view: view.angle("hinge") - math.pi / 2, (ml.Action("lock", "hinge"),)
    )
    sol = ml.solve(
        mech,
        ml.Dynamic(end=1.0, step=0.01, tolerance=1e-10, dense=True),
        events=[latch],
        requests=[ml.JointCoordinate("w", "hinge", "omega")],
    )
    exact = (math.pi / 3) / math.sqrt(2.0 / 0.5)
    assert abs(sol.events[0].time - exact) < 1e-6
    assert np.any(np.abs(sol.time - sol.events[0].time) < 1e-12)
    grid = np.round(np.arange(101) * 0.01, 9)
    assert np.all(np.isin(grid, np.round(sol.time, 9)))
    assert np.all(np.diff(sol.time) >= 0.0)
    after = sol.time > sol.events[0].time + 1e-9
    assert np.abs(sol.channels["w.value"][after]).max() < 1e-9


def test_rows_do_not_depend_on_the_end_time(fine) -> None:
    """The pendulum to 0.5 s and to 1 s, output step 1e-3: the longer run takes the same
    steps over the shorter one's time but for the last two (the steps no longer spread
    over the span to land on its end: mechlib.solvers.genalpha.stepper._towards), so their rows
    on [0, 0.5] s agree: the same to 1e-12 of each channel's peak up to 0.489 s, where
    the shorter run's last two steps begin (0.4894 s; 0.495 s before the step grew
    whenever the error law allows), within 3e-4 after (measured 1.7e-4, the hinge
    reaction: the integration error of steps of another size)."""
    longer = ml.solve(_pendulum(), ml.Dynamic(end=1.0, step=1e-3, dense=True), requests=_REQUESTS)
    assert longer.ok, longer.message
    n = len(fine.time)
    assert np.array_equal(np.round(longer.time[:n], 9), np.round(fine.time, 9))
    for name, values in fine.channels.items():
        peak = max(np.abs(values).max(), 1e-9)
        gap = np.abs(longer.channels[name][:n] - values) / peak
        assert gap.max() < 3e-4, name
        assert gap[fine.time < 0.489 - 1e-9].max() <= 1e-12, name


@pytest.mark.parametrize(("rows", "columns"), [(20, 21), (150, 210), (300, 420)])
def test_minimum_norm_step_is_the_least_squares_one(rows: int, columns: int) -> None:
    """The projection's minimum-norm step (normal equations, dense below
    _SPARSE_NORMAL_FROM = 250 rows, sparse above) equals numpy's least-squares solution
    within 1e-12; with a dependent row (no factor, or a failed check) it falls back to
    least squares itself."""
    from mechlib.solvers.assembly import _MinimumNorm

    rng = np.random.default_rng(rows)
    a = rng.standard_normal((rows, columns)) * (rng.random((rows, columns)) < 0.1)
    a[np.arange(rows), np.arange(rows)] += 3.0  # full row rank, sparse like a Jacobian
    b = rng.standard_normal(rows)
    expected = np.linalg.lstsq(a, b, rcond=None)[0]
    assert np.abs(_MinimumNorm(a)(b) - expected).max() < 1e-12 * np.abs(expected).max()
    a[-1] = a[0]  # dependent rows: a consistent right side has a least-squares answer
    b[-1] = b[0]
    expected = np.linalg.lstsq(a, b, rcond=None)[0]
    assert np.abs(_MinimumNorm(a)(b) - expected).max() < 1e-10 * np.abs(expected).max()
