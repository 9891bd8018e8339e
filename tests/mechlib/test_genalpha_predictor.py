"""The predictor of systems with modal bodies and no force elements
(mechlib.solvers.genalpha.kernels.predict_swing): the consistent acceleration's trend with
the integrator acceleration's step-to-step swing about it reversed, (q, qd) by the Newmark
relations of that guess.

Closed forms: an acceleration linear in time (no swing) is extrapolated exactly, and a swing
that alternates exactly is predicted exactly; (q1, qd1) satisfy generalized-alpha's update
for the predicted acceleration. On Kane's spin-up beam (benchmarks.flexible, 4 s at
tolerance 1e-6, each step from Python) it takes the same steps in fewer Newton iterations
than the constant-acceleration predictor (measured: 268 against 279; over the bench's
20 s, 7201 against 7998), and the tip lag moves by 2e-9 of its range (bound 1e-7, against
the run's own error of about 1e-3 of the range at this tolerance,
benchmarks.flexible_compare): Newton reaches the same solution to its tolerance.
"""

from __future__ import annotations

import numpy as np

import mechlib
from benchmarks.flexible import SpinUp, spin_up_beam
from mechlib.solvers.genalpha import integrator
from mechlib.solvers.genalpha.integrator import Coefficients
from mechlib.solvers.genalpha.kernels import predict, predict_swing

C = Coefficients.from_rho(0.9)


def _swing(q, qd, qdd, a, cons, t, h, past_t, past):
    return predict_swing(
        q, qd, qdd, a, cons, t, h, past_t, past, C.alpha_m, C.alpha_f, C.beta, C.gamma
    )


def test_a_linear_acceleration_is_extrapolated_exactly() -> None:
    slope, h = np.array([2.0, -3.0]), 0.01
    past_t, past = np.full(2, np.nan), np.zeros((2, 2))
    state = np.zeros(2)
    for t in (0.0, 0.02):  # two step starts remembered, the second 0.02 s after the first
        cons = 1.0 + slope * t
        _, _, qdd1 = _swing(state, state, cons, state, cons, t, h, past_t, past)
    np.testing.assert_allclose(qdd1, 1.0 + slope * (0.02 + h), rtol=0, atol=1e-14)
    np.testing.assert_array_equal(past_t, [0.0, 0.02])


def test_an_alternating_swing_is_reversed() -> None:
    cons, swing = np.array([0.5, -1.0]), np.array([3.6, -1.1])
    past_t, past = np.full(2, np.nan), np.zeros((2, 2))
    zero = np.zeros(2)
    _, _, qdd1 = _swing(zero, zero, cons + swing, zero, cons, 0.0, 0.01, past_t, past)
    np.testing.assert_allclose(qdd1, cons - swing, rtol=0, atol=1e-15)


def test_the_guess_keeps_the_newmark_relations() -> None:
    rng = np.random.default_rng(3)
    q, qd, qdd, a, cons = rng.standard_normal((5, 4))
    h, past_t, past = 0.003, np.full(2, np.nan), np.zeros((2, 4))
    q1, qd1, qdd1 = _swing(q, qd, qdd, a, cons, 1.0, h, past_t, past)
    a1 = ((1 - C.alpha_f) * qdd1 + C.alpha_f * qdd - C.alpha_m * a) / (1 - C.alpha_m)
    np.testing.assert_allclose(q1, q + h * qd + h * h * ((0.5 - C.beta) * a + C.beta * a1))
    np.testing.assert_allclose(qd1, qd + h * ((1 - C.gamma) * a + C.gamma * a1))
    # no swing, no past: the constant-acceleration predictor
    q2, qd2, qdd2 = _swing(q, qd, qdd, a, qdd, 1.0, h, np.full(2, np.nan), np.zeros((2, 4)))
    for got, want in zip((q2, qd2, qdd2), predict(q, qd, qdd, a, h, C.alpha_m, C.beta, C.gamma)):
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-15)


def test_a_retried_start_keeps_its_past() -> None:
    past_t, past = np.full(2, np.nan), np.zeros((2, 1))
    one = np.ones(1)
    _swing(one, one, one, one, one, 0.0, 0.1, past_t, past)
    _swing(one, one, one, one, 2 * one, 0.1, 0.1, past_t, past)
    _swing(one, one, one, one, 2 * one, 0.1, 0.05, past_t, past)  # rejected, tried shorter
    np.testing.assert_array_equal(past_t, [0.0, 0.1])
    np.testing.assert_array_equal(past[:, 0], [1.0, 2.0])


def _kane(monkeypatch, old: bool):
    with monkeypatch.context() as patch:
        if old:  # the constant-acceleration predictor, read by the Python step
            patch.setattr(
                integrator,
                "predict_swing",
                lambda q, qd, qdd, a, cons, t, h, pt, p, am, af, beta, gamma: predict(
                    q, qd, qdd, a, h, am, beta, gamma
                ),
            )
        sol = mechlib.solve(
            spin_up_beam(False),
            mechlib.Dynamic(end=4.0, step=0.1, tolerance=1e-6, compiled="python"),
            requests=[mechlib.PointKinematics("tip", "tip")],
        )
    assert sol.ok, sol.message
    angle = np.array([SpinUp().value(t) for t in sol.time])
    return sol, -np.sin(angle) * sol.channels["tip.x"] + np.cos(angle) * sol.channels["tip.y"]


def test_kane_beam_takes_fewer_newton_iterations(monkeypatch) -> None:
    new, new_lag = _kane(monkeypatch, old=False)
    old, old_lag = _kane(monkeypatch, old=True)
    assert new.stats.steps == old.stats.steps
    assert new.stats.newton_iterations <= 0.97 * old.stats.newton_iterations
    assert np.abs(new_lag - old_lag).max() <= 1e-7 * np.ptp(old_lag)
