"""Generalized-alpha's rules, defined once: how the step size is chosen, when Newton has
converged or stalled, how its rate is carried to the next step, and when the iteration
matrix is factored again.

The Python stepper (mechlib.solvers.genalpha.stepper, .integrator) and the compiled kernels
(mechlib.solvers.genalpha.compiled: the Newton loop; .run: whole runs of steps) call these
same functions; numba compiles the constants below into the kernels that call them, so a
change here changes every path alike.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit

__all__ = [
    "ETA_MIN",
    "FAILED_SHRINK",
    "FIRST_STEP",
    "MAX_ITER",
    "NEWTON_CEILING",
    "NEWTON_KAPPA",
    "NOISE_POSITION",
    "POSITION_ROUNDOFF",
    "ROUNDOFF",
    "SLOW_ITERATIONS",
    "STAGNANT",
    "carried",
    "carried_rate",
    "constraint_velocity",
    "converged",
    "is_noise",
    "keeps_tangent",
    "newton_rate",
    "on_grid",
    "pseudo_acceleration",
    "refactors",
    "restalled",
    "retangents",
    "slow",
    "stalled",
    "step_size",
    "substep",
    "towards",
]

# ---- Newton ------------------------------------------------------------------------------
MAX_ITER = 8  # iterations with one iteration matrix before it is refreshed (or the step fails)
NEWTON_KAPPA = 0.05  # Newton's error estimate eta |dq| against this fraction of the tolerance
NEWTON_FLOOR = 1e-10  # an increment this small (x the weights) has converged whatever eta says
DIVERGING = 0.9  # increments shrinking by less than this per iteration: stalled
STAGNANT = 0.5  # increment ratio of an iteration that no longer converges
NOISE_POSITION = 1e-3  # position increment (x the position tolerance) that is round-off
# position increment (x scale + |q|) that is round-off at any tolerance: 45 000 eps, round-off
# amplified by a near-singular iteration matrix (toggle measure down to about 1e-3); above
# NOISE_POSITION's only at tolerances below 1e-8
POSITION_ROUNDOFF = 1e-11
ETA_MIN = 1e-3  # the smallest Newton rate carried to the next step
RATE_MEMORY = 0.8  # the rate carried to the next step: max(eta, ETA_MIN) ** RATE_MEMORY
SLOW_ITERATIONS = 3  # more iterations than this: a fresh iteration matrix for the next step
# relative round-off floor of a Newton increment's acceleration part (kernels._newton_size):
# Newton stops once its estimated remainder is within NEWTON_KAPPA of it. That remainder is
# no round-off but a systematic part of each step's correction (modified Newton converging
# linearly from a biased predictor), and x gamma' a velocity error of every step: an energy
# drift of O(ROUNDOFF / h^2) per second, which grows as the steps shrink. At 1e3 eps IFToMM
# A01 (10 s) lost 3.3e-8 m g L per s at tolerance 3e-11 and 2.2e-7 at 3.75e-12, against
# the truncation's 4e-9 and 6e-10, and that drift was the floor of its error over 2000 s;
# at 10 eps 5.0e-9 and 2.9e-9 (4 % and 14 % more Newton iterations; 1 eps gave 4.5e-9 and
# 2.8e-9). An increment that stagnates at round-off above it is taken by `is_noise`.
ROUNDOFF = 10.0 * np.finfo(float).eps

# ---- iteration matrix --------------------------------------------------------------------
REFACTOR_CHANGE = 0.25  # a step size this far (relative) from the factored one refactors

# ---- step size ---------------------------------------------------------------------------
SAFETY = 0.9  # the error estimate's exponent law, aimed this much below the tolerance
GROW, SHRINK = 4.0, 0.2  # the most a step grows after acceptance, shrinks after rejection
# an accepted step grows the step size whenever the error law allows (no hysteresis): a
# change costs nothing since the pseudo-acceleration is carried to it (pseudo_acceleration);
# a hysteresis of 1.5 (while each change restarted it) shrank the step on a swing's way down
# and grew it back elsewhere: loops that drained a pendulum's energy (IFToMM A01, 50 s at
# tolerance 1e-6: 0.070 m against the closed form, now 0.0057 m in 10 % fewer steps)
REGROW = 1.0
FAILED_SHRINK = 0.25  # a step Newton could not take: the next is a quarter as long
# ... and the steps after it grow at most to a ceiling: half the failed step, rising by the
# step change an iteration matrix is kept for (REFACTOR_CHANGE) with each accepted step
# (`step_size`)
NEWTON_CEILING = 0.5
CEILING_RISE = 1.0 + REFACTOR_CHANGE
# first step, as a fraction of the analysis span: small, because the start acceleration may
# be one the motion leaves at once (joint friction at rest carries nothing until the joint
# slips); the step grows x4 per accepted step, so this costs about five steps
FIRST_STEP = 1e-6


@njit(**KERNEL)
def step_size(
    h_try: float, err: float, h: float, max_step: float, converged: bool, ceiling: float
) -> tuple[float, float]:
    """The step size (s) after a step h_try (s) with scaled local error err, the step size
    having been h (s), and the ceiling (s; inf: none) of the steps after the last Newton
    failure, as (step size, ceiling): the one place they are chosen.
    - Newton did not converge (`converged` False): FAILED_SHRINK h_try, and the ceiling
      NEWTON_CEILING h_try.
    - Rejected by its error (err > 1): h_try max(SHRINK, SAFETY err^(-1/3)).
    - Accepted: h_try min(GROW, SAFETY err^(-1/3)) up to max_step and to the ceiling (or
      h_try, where that is above it) when that grows it by more than REGROW, else h
      unchanged (an accepted step does not shrink the next); the ceiling rises by
      CEILING_RISE.
    Newton's failure bounds the step where the error law does not: the retry's error, far
    below the tolerance, let the law grow the step x4 straight back to the size Newton had
    failed at (near the horizontal crossings of IFToMM A02's chain of four-bars: planar
    N = 40's error-estimate companion failed Newton 224 times in 20 s, 56 with the
    ceiling; docs/performance.md). A ceiling, not Hairer's "no growth after a rejection"
    for every rejection: that changed the steps of runs without Newton failures (IFToMM
    A01 over 50 s at 1e-6: 0.0057 -> 0.0082 m), the ceiling leaves them as they were."""
    if not converged:
        return FAILED_SHRINK * h_try, NEWTON_CEILING * h_try
    if err > 1.0:
        return h_try * max(SHRINK, SAFETY * err ** (-1.0 / 3.0)), ceiling
    grow = GROW if err == 0.0 else min(GROW, SAFETY * err ** (-1.0 / 3.0))
    grow = min(grow, max(1.0, ceiling / h_try))
    if grow > REGROW:
        return min(max_step, h_try * grow), ceiling * CEILING_RISE
    return h, ceiling * CEILING_RISE


@njit(**KERNEL)
def pseudo_acceleration(qdd: np.ndarray, a: np.ndarray, ratio: float) -> np.ndarray:
    """The pseudo-acceleration a (the coordinates' units per s^2) carried to a step `ratio`
    times as long as the one it was made for, from the acceleration qdd of the step's start:
    qdd + min(ratio, 1) (a - qdd). Generalized-alpha's a_n is the acceleration at
    t_n + (alpha_m - alpha_f) h to O(h^2) (Arnold & Bruls 2007; measured in
    tests/mechlib/test_genalpha_order.py): its offset from qdd_n scales with the step. A
    longer step keeps a: the offset also holds the method's decaying transients (of stiff
    contacts), which scaling up would amplify (the rod-end rattle: 17 834 rejected steps in
    0.2 s, against 179). Restarting a from qdd at each change, as done before, left an O(h)
    error in a and an O(h^2) error in the velocity at every change."""
    return qdd + min(ratio, 1.0) * (a - qdd)


@njit(**KERNEL)
def constraint_velocity(qd: np.ndarray, raw_qd: np.ndarray, ratio: float) -> np.ndarray:
    """The integrator's own velocity raw_qd (the coordinates' units per s) carried to a step
    `ratio` times as long as the one it was made for, from the consistent velocity qd (raw_qd
    projected onto the velocity constraints): qd + min(ratio, 1) (raw_qd - qd). Index-3
    generalized-alpha meets the position constraints exactly and leaves its velocity off the
    velocity constraints by O(h^2) (h^2 (1/6 - (alpha_m - alpha_f)/2 - beta) times the
    constraint's third time derivative, from the position update's Taylor expansion;
    measured in tests/mechlib/test_genalpha_order.py). The next step reads that violation
    as an acceleration, violation / (beta h): carried whole from a step H to a shorter h,
    H/h times the one its own step made, and the index-3 transient it starts (undamped at
    rho_inf 1) became a velocity error at the next long step (a hinged bar beside a block
    bouncing on a stiff stop, its steps 4.6 ms -> 0.12 ms: +-3.3 rad/s^2 on its 14.7, then
    1.5e-3 of its energy; tests/verification/test_joint_limit_cases.py). Scaled with the
    step, that acceleration is carried unchanged. By the step squared (the smooth motion's
    own law) it was cut at every shrink and kept at every growth, a one-sided bias: IFToMM
    A01 over 50 s at 1e-6 0.0057 -> 0.0064 m (0.0059 scaled with the step). A longer step
    keeps raw_qd, as `pseudo_acceleration` keeps a."""
    return qd + min(ratio, 1.0) * (raw_qd - qd)


@njit(**KERNEL)
def carried(
    qd: np.ndarray, raw_qd: np.ndarray, raw_qdd: np.ndarray, a: np.ndarray, ratio: float
) -> tuple[np.ndarray, np.ndarray]:
    """(raw_qd, a) carried to a step `ratio` times as long as the one they were made for
    (`constraint_velocity`, `pseudo_acceleration`), from the consistent velocity qd and the
    integrator's own acceleration raw_qdd of the step's start: the one rule at a step-size
    change, of the Python steps and the compiled runs alike. The integrator's own
    acceleration is kept: carrying its offset like a's (branch loose-pins) cost accuracy at
    large steps (the global-error pendulum at tolerance 1e-4: 0.0064 -> 0.0110 rad)."""
    return constraint_velocity(qd, raw_qd, ratio), pseudo_acceleration(raw_qdd, a, ratio)


@njit(**KERNEL)
def substep(interval: float, h: float) -> float:
    """The size (s) of equal sub-steps of at most h (s) landing on an output time
    `interval` s ahead (`output: steps`)."""
    n = max(1, math.ceil(interval / h * (1.0 - 1e-9)))
    return interval / n


@njit(**KERNEL)
def towards(interval: float, h: float) -> float:
    """A dense step of h (s) towards a time `interval` s ahead: h itself while it leaves
    more than h, so that the steps do not depend on how far the end is; then the rest in
    one step, or in two equal ones when one would be longer than h."""
    if interval <= h * (1.0 + 1e-9):
        return interval
    return 0.5 * interval if interval < 2.0 * h else h


@njit(**KERNEL)
def on_grid(t: float, interval: float, ends: np.ndarray, middles: np.ndarray, split: bool) -> float:
    """The step (s) from t along a prescribed grid (mechlib.model.step_grid.StepGrid: its
    `ends` and `middles`, s), at most `interval` s (to the analysis's end): to the first
    end after t; after that step failed Newton (`split`), to its middle where that lies
    ahead (the first of the two steps it merges); past the last end (a run the grid's run
    stopped at an event: this one's may come later), steps as long as the grid's last.
    No error test decides it: on a grid of
    another run's steps two at a time, Richardson compares two runs on a fixed mesh pair
    of ratio 2 (Hairer, Norsett & Wanner I, II.9; loadcases.run.companion)."""
    tiny = 1e-12 * max(1.0, abs(t))
    k = np.searchsorted(ends, t + tiny)
    n = ends.shape[0]
    if k == n:
        last = ends[n - 1] - ends[n - 2] if n > 1 else interval
        return min(interval, last)
    if split and middles[k] - t > tiny:
        return min(interval, middles[k] - t)
    return min(interval, ends[k] - t)


@njit(**KERNEL)
def newton_rate(size: float, prev: float, eta: float) -> float:
    """Newton's rate estimate eta = theta / (1 - theta), theta = size / prev, after an
    increment of `size` following one of `prev` (inf: the first; eta is kept)."""
    if prev < math.inf:
        theta = size / prev
        return theta / (1.0 - theta) if theta < 1.0 else math.inf
    return eta


@njit(**KERNEL)
def is_noise(size: float, prev: float, position_size: float, tol: float) -> bool:
    """Newton has reached its round-off floor: the increments stopped shrinking (ratio
    above STAGNANT) while far below the position tolerance (`position_size`: the increment
    against the position weights tol (scale + |q|) alone, at most NOISE_POSITION) or at
    round-off in q whatever the tolerance (at most POSITION_ROUNDOFF of scale + |q|). Near
    a singular position (the horizontal crossing of a chain of parallelogram four-bars)
    the iteration matrix amplifies round-off in q by 1/sigma_min, and x beta' that noise
    reads as a large acceleration increment no smaller step removes: IFToMM A02 (N = 40)
    stagnates at increments of 1e-12 (3-D, tolerance 2.4e-10) to 2e-12 (planar, 3.1e-11)
    of scale + |q|, the same at every step size, and stalled there while only
    NOISE_POSITION of the tolerance counted as noise."""
    if prev == math.inf or size <= STAGNANT * prev:
        return False
    return position_size <= max(NOISE_POSITION, POSITION_ROUNDOFF / tol)


@njit(**KERNEL)
def converged(eta: float, size: float, noise: bool) -> bool:
    """Newton's error estimate eta |dq| within NEWTON_KAPPA of the local error tolerance
    (Hairer & Wanner, Solving ODEs II, IV.8; positions only, as the error test), or an
    increment at round-off."""
    return (eta * size <= NEWTON_KAPPA and size < 1.0) or size < NEWTON_FLOOR or noise


@njit(**KERNEL)
def stalled(size: float, prev: float, it: int) -> bool:
    """The increments stopped shrinking fast enough, or the iterations ran out."""
    return (prev < math.inf and size > DIVERGING * prev) or it >= MAX_ITER


@njit(**KERNEL)
def carried_rate(eta: float) -> float:
    """The rate estimate a converged step hands to the next."""
    return max(eta, ETA_MIN) ** RATE_MEMORY


@njit(**KERNEL)
def slow(iterations: int) -> bool:
    """A step converged slowly: the next factors a fresh iteration matrix."""
    return iterations > SLOW_ITERATIONS


@njit(**KERNEL)
def refactors(h: float, lu_h: float) -> bool:
    """A step h (s) needs the iteration matrix factored again: it was factored for lu_h."""
    return abs(h / lu_h - 1.0) > REFACTOR_CHANGE


@njit(**KERNEL)
def retangents(tried: bool) -> bool:
    """A step that converged slowly, of a system that keeps its tangent first
    (`keeps_tangent`), asks for a new differenced tangent only when its matrix had already
    been refactored for the last slow step with the tangent kept (`tried`) and that did not
    help; else the next matrix is refactored at its state with the tangent kept. Kane's
    beam at 1e-6 (a modal body's tangent changes with its spin; its mass matrix and the
    constraint Jacobian turn with it) took a new tangent at 980 of 2421 steps, and with a
    refactorisation instead at 240 (8238 Newton iterations instead of 8350, the same
    steps)."""
    return tried


@njit(**KERNEL)
def keeps_tangent(modal: bool, elements: bool) -> bool:
    """Whether a slow step's next iteration matrix is refactored with the differenced
    tangent kept before a new one is made (`retangents`): for rigid bodies, with or without
    force elements, and for modal bodies without them (`modal`: the system has modal
    bodies; `elements`: active force elements); not for modal bodies with force elements
    (BepiColombo's flexible deployment took 3.7 % more steps under this rule).
    Rigid bodies: what ages a matrix from step to step is the bodies' turning (M and phi_q
    in absolute coordinates), the elements' K and C enter it divided by beta' ~ 1/h^2 and
    gamma'/beta' ~ h. The four-bar with spring-dampers and pivot friction at tolerance 1e-9
    (benchmarks/kinds/fourbar_friction.py) took a new tangent (74 us in the whole-run
    kernel, against 22 us for the refactorisation) at 2342 of its 12 820 steps, and with
    the tangent kept at 50 (counted on the Python-stepped path, 3 % more iterations there),
    the same steps and 0.1 % more Newton iterations in the whole runs. Elements that
    give their own tangent (compiled contacts) have it evaluated at every refactorisation
    whatever this says."""
    return not (modal and elements)


GIVE_UP, KEPT, FRESH = 0, 1, 2  # `restalled`: what a stalled step does next


@njit(**KERNEL)
def restalled(refreshed: bool, rebuilt: bool, modal: bool) -> int:
    """What a step whose Newton iterations stalled does next: GIVE_UP when its matrix had
    a fresh differenced tangent (`refreshed`); KEPT: the matrix of a system of modal
    bodies without force elements (`modal`) not factored in this step (`rebuilt`) is
    factored again at the iterate with its tangent kept (Kane's beam at 1e-6: each of its
    239 stalls took a new tangent, and with a refactorisation instead the run took the
    same steps and the same 8238 iterations from one tangent; with force elements,
    BepiColombo's flexible deployment took 3.7 % more steps under this rule and
    `retangents`); else FRESH, a new tangent."""
    if refreshed:
        return GIVE_UP
    return KEPT if modal and not rebuilt else FRESH
