"""Generalized-alpha's rules (mechlib.solvers.genalpha.rules), the one definition that the
Python stepper and the compiled kernels share, against their formulas worked by hand, and
the march's reading of a step's status and error (mechlib.solvers.march.accepted)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib
from mechlib.core.outcome import SolverFailure, Status
from mechlib.solvers.contract import State, StepResult
from mechlib.solvers.genalpha import rules
from mechlib.solvers.march import accepted


def _size(h_try: float, err: float, h: float, max_step: float, converged: bool) -> float:
    """rules.step_size's step size with no Newton ceiling in force (inf), which it keeps
    (inf x CEILING_RISE)."""
    size, ceiling = rules.step_size(h_try, err, h, max_step, converged, math.inf)
    assert ceiling == math.inf or not converged
    return size


def test_step_grows_by_the_error_law_whenever_it_grows() -> None:
    # err = 1/8: 0.9 * 8^(1/3) = 1.8 -> h_try * 1.8
    assert _size(0.01, 0.125, 0.01, 1.0, True) == pytest.approx(0.018, rel=1e-15)
    # err = 0.5: 0.9 * 2^(1/3) = 1.134 > 1 -> h_try * 1.134 (no hysteresis: REGROW 1)
    assert _size(0.01, 0.5, 0.007, 1.0, True) == pytest.approx(0.01134, rel=1e-3)
    # err = 0.8: 0.9 / 0.8^(1/3) = 0.969 < 1 -> an accepted step keeps the step size
    assert _size(0.01, 0.8, 0.007, 1.0, True) == 0.007
    # err = 0: x4, capped by the largest step
    assert _size(0.01, 0.0, 0.01, 1.0, True) == pytest.approx(0.04)
    assert _size(0.01, 0.0, 0.01, 0.03, True) == 0.03


def test_step_shrinks_by_the_error_law_down_to_a_fifth_or_a_quarter_after_newton() -> None:
    # err = 8: 0.9 / 2 = 0.45
    assert _size(0.01, 8.0, 0.01, 1.0, True) == pytest.approx(0.0045, rel=1e-15)
    # err = 1e6: 0.9 / 100 = 0.009 < 0.2 -> a fifth
    assert _size(0.01, 1e6, 0.01, 1.0, True) == pytest.approx(0.002, rel=1e-15)
    # Newton did not converge: a quarter, whatever the (infinite) error
    assert _size(0.01, math.inf, 0.01, 1.0, False) == pytest.approx(0.0025)


def test_steps_after_a_newton_failure_grow_to_a_rising_ceiling() -> None:
    # Newton failed at 0.01: the retry a quarter as long, the ceiling half the failed step
    assert rules.step_size(0.01, math.inf, 0.01, 1.0, False, math.inf) == pytest.approx(
        (0.0025, 0.005)
    )
    # the retry accepted with err 1e-3 (the law: x4 -> 0.01): to the ceiling 0.005, which
    # rises x1.25 (REFACTOR_CHANGE) with each accepted step
    h, ceiling = rules.step_size(0.0025, 1e-3, 0.0025, 1.0, True, 0.005)
    assert (h, ceiling) == pytest.approx((0.005, 0.00625))
    h, ceiling = rules.step_size(h, 1e-3, h, 1.0, True, ceiling)
    assert (h, ceiling) == pytest.approx((0.00625, 0.0078125))
    # a step already above the ceiling keeps its size (the ceiling never shrinks it) ...
    assert rules.step_size(0.008, 1e-3, 0.008, 1.0, True, 0.005)[0] == 0.008
    # ... and one the law grows less than to the ceiling takes the law's size
    assert rules.step_size(0.001, 0.125, 0.001, 1.0, True, 0.005)[0] == pytest.approx(0.0018)
    # a rejection by the error keeps the ceiling as it is
    assert rules.step_size(0.005, 8.0, 0.005, 1.0, True, 0.004)[1] == 0.004


def test_pseudo_acceleration_is_carried_to_the_new_step() -> None:
    """qdd + min(ratio, 1) (a - qdd): the offset of a from the acceleration scales with a
    shorter step; the same step or a longer one keeps a, a step of zero length has a = qdd."""
    qdd, a = np.array([1.0, -2.0]), np.array([1.5, -1.0])
    np.testing.assert_allclose(rules.pseudo_acceleration(qdd, a, 0.5), [1.25, -1.5])
    np.testing.assert_allclose(rules.pseudo_acceleration(qdd, a, 1.0), a)
    np.testing.assert_allclose(rules.pseudo_acceleration(qdd, a, 3.0), a)
    np.testing.assert_allclose(rules.pseudo_acceleration(qdd, a, 0.0), qdd)


def test_own_velocity_and_pseudo_acceleration_are_carried_together() -> None:
    """rules.carried: the integrator's velocity's offset from the consistent one (its
    velocity-constraint violation) scales with a shorter step like a's offset from the
    integrator's acceleration; the same step or a longer one keeps both, a step of zero
    length has raw_qd = qd and a = raw_qdd."""
    qd, raw_qd = np.array([0.0, 1.0]), np.array([0.2, 1.0])
    raw_qdd, a = np.array([1.0, -2.0]), np.array([1.5, -1.0])

    def carried(ratio: float) -> list:
        return [list(x) for x in rules.carried(qd, raw_qd, raw_qdd, a, ratio)]

    np.testing.assert_allclose(carried(0.5), [[0.1, 1.0], [1.25, -1.5]])
    np.testing.assert_allclose(carried(1.0), [raw_qd, a])
    np.testing.assert_allclose(carried(3.0), [raw_qd, a])
    np.testing.assert_allclose(carried(0.0), [qd, raw_qdd])
    np.testing.assert_allclose(rules.constraint_velocity(qd, raw_qd, 0.25), [0.05, 1.0])


def test_substeps_land_on_the_output_time() -> None:
    assert rules.substep(0.01, 0.004) == pytest.approx(0.01 / 3)
    assert rules.substep(0.01, 0.01) == 0.01  # one step, not two, at round-off
    assert rules.towards(1.0, 0.3) == 0.3  # dense: h while it leaves more than h
    assert rules.towards(0.5, 0.3) == 0.25  # then two equal steps
    assert rules.towards(0.2, 0.3) == 0.2


def test_newton_rate_convergence_and_stall() -> None:
    assert rules.newton_rate(0.1, math.inf, 1.0) == 1.0  # first increment: kept
    assert rules.newton_rate(0.1, 0.4, 1.0) == pytest.approx(0.25 / 0.75)
    assert rules.newton_rate(0.5, 0.4, 1.0) == math.inf
    assert rules.converged(0.1, 0.4, False)  # 0.04 <= 0.05
    assert not rules.converged(0.2, 0.4, False)  # 0.08
    assert rules.converged(math.inf, 1e-11, False)  # at the floor
    assert rules.stalled(0.95, 1.0, 2) and not rules.stalled(0.85, 1.0, 2)
    assert rules.stalled(0.1, 1.0, rules.MAX_ITER)
    assert rules.carried_rate(1e-6) == pytest.approx(1e-3**0.8)
    assert rules.slow(4) and not rules.slow(3)
    assert rules.refactors(0.0126, 0.01) and not rules.refactors(0.0124, 0.01)
    assert rules.is_noise(0.6, 1.0, 1e-4, 1e-6) and not rules.is_noise(0.4, 1.0, 1e-4, 1e-6)
    # round-off at any tolerance: 1e-11 of scale + |q|; at 1e-6 the tolerance's 1e-3 rules
    assert not rules.is_noise(0.6, 1.0, 0.002, 1e-6) and not rules.is_noise(0.6, 1.0, 0.05, 2e-10)
    assert rules.is_noise(0.6, 1.0, 0.03, 2.5e-10) and rules.is_noise(1.3, 1.0, 0.3, 3e-11)


def _state(t: float) -> State:
    zero = np.zeros(1)
    return State(t, zero, zero, zero, zero)


def test_march_reads_status_and_error() -> None:
    """A rejected step is retried; a step reported successful with an error above 1, or a
    failure status, ends the run with a SolverFailure that names it."""
    assert accepted(StepResult(None, 3.0, Status.STEP_REJECTED), 0.1) is None
    good = _state(0.2)
    assert accepted(StepResult(good, 0.7, Status.SUCCESSFUL), 0.1) is good
    assert accepted(StepResult(good, None, Status.SUCCESSFUL), 0.1) is good
    with pytest.raises(SolverFailure, match="local error estimate of 2") as bad:
        accepted(StepResult(good, 2.0, Status.SUCCESSFUL), 0.1)
    assert bad.value.status is Status.INTEGRATOR_FAILED and bad.value.time == 0.1
    with pytest.raises(SolverFailure, match="Newton") as failed:
        accepted(StepResult(None, math.inf, Status.NEWTON_FAILED), 0.3)
    assert failed.value.status is Status.NEWTON_FAILED


def test_the_compiled_path_is_a_setting() -> None:
    assert mechlib.Dynamic(1.0, 0.01).compiled == "runs"
    with pytest.raises(ValueError, match="compiled"):
        mechlib.Dynamic(1.0, 0.01, compiled="fast")
