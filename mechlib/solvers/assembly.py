"""Assembly: positions on the constraints (Newton), consistent velocities and accelerations.

Given initial values that the constraints contradict are projected onto them (least
squares, smallest change from the design position) and reported. The way there keeps the
assembly branch of the drawn geometry, or goes near the guesses given
(mechlib.solvers.branches). The modal coordinates of
flexible bodies weigh _MODAL_WEIGHT^-2 times more in that smallest change: a given angle is
reached by rigid motion, and a body deforms only where the constraints need it (otherwise
the least-squares step spreads the motion over the modes and starts a run strained).
Given modal coordinates and rates (`InitialModes`) are targets like given joint values:
reached exactly where the constraints allow, the rigid coordinates moving to meet them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.linalg import qr, solve_triangular
from scipy.linalg.lapack import dgetrf, dgetrs
from scipy.sparse.linalg import splu

from mechlib.checks.singularity import toggle_detail
from mechlib.core.outcome import SolverFailure, Status
from mechlib.core.work import count
from mechlib.kinematics.kin import Kin
from mechlib.linalg.factor import SINGULAR_RATIO
from mechlib.model.analysis import BranchCheck, InitialBodyVelocity, InitialValue
from mechlib.solvers.branches import (
    BranchChange,
    angle_values,
    guess_changes,
    orientation,
    stage_jumps,
)
from mechlib.solvers.initial_modes import (
    ModalTarget,
    modal_notes,
    modal_rate_rows,
    modal_targets,
)
from mechlib.solvers.least_energy import least_energy_velocities, velocity_metric
from mechlib.solvers.start_memo import Placed, placed_start
from mechlib.system.system import System

__all__ = [
    "MAX_NEWTON",
    "MAX_STAGES",
    "POSITION_TOLERANCE",
    "REUSE_BELOW",
    "InitialBodyVelocity",
    "InitialValue",
    "assemble",
    "reassemble",
    "solve_accelerations",
    "solve_positions",
    "solve_rates",
    "solve_velocities",
]

POSITION_TOLERANCE = 1e-10
# rad: the largest angle a coordinate equation may set. Beyond it the spacing of doubles
# (2.2e-16 x angle) exceeds the residual a position analysis accepts (1e3 x tolerance):
# 4.5e8 rad, 72 million turns.
ANGLE_LIMIT = 1e3 * POSITION_TOLERANCE / float(np.finfo(float).eps)
MAX_NEWTON = 50
_REPORT_CHANGE = 1e-8
_STAGE = math.pi / 6  # rad: largest change of a given angle per assembly stage
# stages of _STAGE the way from the drawn geometry may take: 5236 rad (833 turns) or 5.2 km,
# some 2 s of CPU on a one-joint mechanism
MAX_STAGES = 10_000
_SPLITS = 6  # a stage leaving the drawn branch is halved at most this many times
_SLOW_NEWTON = 12  # iterations: a stage's Newton slower than this passes a singular position
_MODAL_WEIGHT = 1e-6  # column scale of modal coordinates in the assembly's least squares
_NORMAL_CHECK = 1e-6  # a normal-equations solution must meet its equations this well
REUSE_BELOW = 1e-6  # a Newton step below this keeps its Jacobian for the next
# a a^T of this many rows and more is factored sparse: below, the dense LU is cheaper
# (2026-11-28, chains of 7-coordinate bodies, 5 rows per joint: 103 rows 0.14 ms dense
# against 0.61 ms sparse, 235 rows 0.86 against 1.0, 355 rows 2.6 against 1.5; the door's
# 105 rows 0.13 against 0.54 ms)
_SPARSE_NORMAL_FROM = 250
_RANK_RATIO = 1e-8  # solve_rates: smaller pivots of the QR leave it to least squares


@dataclass
class Assembled:
    """Initial state and the notes on given values that had to change."""

    q: np.ndarray
    qd: np.ndarray
    newton_iterations: int
    notes: list[str] = field(default_factory=list)
    branches: list[BranchChange] = field(default_factory=list)


def _assembly_weights(system: System) -> np.ndarray:
    """Column scales (nq,) of the assembly's least squares: 1, _MODAL_WEIGHT for modes."""
    weights = np.ones(system.nq)
    weights[system.nq - system.nz :] = _MODAL_WEIGHT
    return weights


class _BeyondDoubles(ArithmeticError):
    """Newton met equations or a Jacobian beyond the range of doubles (inf or nan): no step
    can be solved from there (LAPACK would print its own complaints and fail)."""


def _newton(
    residual, jacobian, q: np.ndarray, tol: float, weights: np.ndarray | None = None
) -> tuple[np.ndarray, int, float]:
    """_solved_newton with numpy's overflow warnings off: a value beyond doubles raises
    _BeyondDoubles, which the caller turns into a failure saying why."""
    with np.errstate(over="ignore", invalid="ignore"):
        return _solved_newton(residual, jacobian, q, tol, weights)


def _finite(values: np.ndarray) -> np.ndarray:
    """`values` if all are finite, else _BeyondDoubles."""
    if not np.isfinite(values).all():
        raise _BeyondDoubles
    return values


def _solved_newton(
    residual, jacobian, q: np.ndarray, tol: float, weights: np.ndarray | None
) -> tuple[np.ndarray, int, float]:
    """Minimum-norm Newton (Gauss-Newton when over-determined), the norm of the step
    divided by `weights` per column; returns q, iterations, |res| once a step is below
    `tol` (|res| above tol then: the least-squares point of inconsistent equations, such as
    an assembly stage's interpolated targets, or a stuck Newton; callers judge). After a
    step below
    REUSE_BELOW the Jacobian is kept (its change is of the order of that step, so the
    next step converges as fast as with a fresh one): a dense row, already on the
    constraints to 1e-9, is polished with one Jacobian instead of two."""
    res = _finite(residual(q))
    w = np.ones(len(q)) if weights is None else weights
    solver: _MinimumNorm | None = None
    for it in range(1, MAX_NEWTON + 1):
        if solver is None:
            count(factorizations=1, jacobian_evaluations=1)
            solver = _MinimumNorm(jacobian(q) * w)
        step = w * solver(-res)
        q = q + step
        res = _finite(residual(q))
        size = np.abs(step).max(initial=0.0)
        if size < tol:  # converged, or (residual above tol) stuck: Gauss-Newton's fixed point
            return q, it, float(np.abs(res).max(initial=0.0))
        if size >= REUSE_BELOW:
            solver = None
    return q, MAX_NEWTON, float(np.abs(res).max(initial=0.0))


class _MinimumNorm:
    """x of least norm with a x = b for the right sides b given: a^T (a a^T)^-1 b, a a^T
    factored once (dense LU; sparse LU from _SPARSE_NORMAL_FROM rows on, as a joint's rows
    touch two bodies), 10x cheaper than an SVD; each x checked by its own residual (which also
    catches a factor of non-finite numbers); least squares (SVD) where that fails
    (dependent rows, a singular position, more rows than columns)."""

    def __init__(self, a: np.ndarray):
        self.a = _finite(a)  # LAPACK's least squares refuses inf and nan, printing why
        self.solve: Callable[[np.ndarray], np.ndarray] | None = None
        if a.shape[0] == 0 or a.shape[0] > a.shape[1]:
            return
        if a.shape[0] >= _SPARSE_NORMAL_FROM:
            sparse = sp.csr_matrix(a)
            normal = (sparse @ sparse.T).tocsc()
            if not np.isfinite(normal.data).all():  # overflowed: least squares scales a
                return
            with suppress(RuntimeError):  # exactly singular: dependent rows
                factors = splu(normal, permc_spec="COLAMD")
                if _well_pivoted(factors.U.diagonal()):
                    self.solve = factors.solve
            return
        normal = a @ a.T
        if not np.isfinite(normal).all():  # overflowed: least squares scales a
            return
        lu, pivots, info = dgetrf(normal)  # LAPACK directly: its wrappers cost more
        if info == 0 and _well_pivoted(np.diag(lu)):
            self.solve = lambda rhs: dgetrs(lu, pivots, rhs)[0]

    def __call__(self, b: np.ndarray) -> np.ndarray:
        a = self.a
        if self.solve is not None:
            x = a.T @ self.solve(b)
            if np.abs(a @ x - b).max(initial=0.0) <= _NORMAL_CHECK * np.abs(b).max(initial=0.0):
                return x
            self.solve = None  # it failed once: least squares for the next right sides too
        x, *_ = np.linalg.lstsq(a, b, rcond=None)
        return x


def _well_pivoted(diagonal: np.ndarray) -> bool:
    """The LU of a a^T is far from singular: its pivots' ratio above SINGULAR_RATIO (a
    nearly dependent row would otherwise leave a large null-space part in a^T y, which
    the residual check cannot see; least squares cuts it)."""
    size = np.abs(diagonal)
    return bool(np.isfinite(size).all() and size.min() > SINGULAR_RATIO * size.max())


def solve_positions(
    system: System,
    q: np.ndarray,
    t: float,
    *,
    tol: float = POSITION_TOLERANCE,
    weights: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """q with phi(q, t) = 0 from the guess q (`weights`: see _newton); raises SolverFailure
    naming the worst rows. The angles that equations on angles hold (drives, gears) are
    first aimed at their values at t (CoordinateBlock.aim_references)."""
    beyond = system.coordinate_rows().aim_references(t, ANGLE_LIMIT)
    if beyond:
        label, value = beyond[0]
        raise SolverFailure(
            f"position analysis at t = {t:.6g} s: {label} is set to {value:.6g} rad, beyond "
            f"+-{ANGLE_LIMIT:.3g} rad, where a double no longer holds an angle to the "
            "position tolerance (a speed, an angle or a time far too large?)",
            time=t,
            where=tuple(label for label, _ in beyond),
            status=Status.NEWTON_FAILED,
        )
    try:
        q, its, worst = _newton(
            lambda x: system.phi(system.kin(x, None, t)),
            lambda x: system.phi_q(system.kin(x, None, t)),
            q,
            tol,
            weights,
        )
    except _BeyondDoubles:
        raise SolverFailure(
            f"position analysis at t = {t:.6g} s: the constraint equations exceed the range "
            "of double-precision numbers on the way (a value far too large?)",
            time=t,
            status=Status.NEWTON_FAILED,
        ) from None
    if worst > 1e3 * tol:
        res = system.phi(system.kin(q, None, t))
        rows = np.argsort(-np.abs(res))[:3]
        where = tuple(system.labels[i] for i in rows)
        raise SolverFailure(
            f"position analysis did not converge at t = {t:.6g} s "
            f"(largest residuals: {'; '.join(where)}"
            f"{toggle_detail(system, system.kin(q, None, t))}): the mechanism "
            "cannot be assembled there (out of reach, or a motion beyond a "
            "toggle)",
            time=t,
            where=where,
            status=Status.NEWTON_FAILED,
        )
    return q, its


def solve_velocities(system: System, k: Kin) -> np.ndarray:
    """qd with phi_q qd = nu (minimum norm when degrees of freedom remain)."""
    count(factorizations=1)
    qd, *_ = np.linalg.lstsq(system.phi_q(k), system.nu(k), rcond=None)
    return qd


def solve_accelerations(system: System, k: Kin) -> np.ndarray:
    """qdd with phi_q qdd = gamma (minimum norm when degrees of freedom remain)."""
    count(factorizations=1)
    qdd, *_ = np.linalg.lstsq(system.phi_q(k), system.gamma(k), rcond=None)
    return qdd


def solve_rates(system: System, q: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(qd, qdd) at q: solve_velocities, then solve_accelerations at (q, qd), from one
    factorization of their common phi_q: phi_q^T = Q R (QR), the minimum-norm x of
    phi_q x = b is Q R^-T b. The same solutions as least squares (an SVD each) to round-off
    where phi_q has full row rank, at a tenth of the cost; least squares where a pivot of R
    is below _RANK_RATIO of the largest (dependent rows, a singular position)."""
    k = system.kin(q, None, t)
    jac = system.phi_q(k)
    count(factorizations=1)
    if 0 < jac.shape[0] <= jac.shape[1]:
        basis, upper = qr(jac.T, mode="economic", check_finite=False)
        pivots = np.abs(np.diag(upper))
        if np.isfinite(pivots).all() and pivots.min() > _RANK_RATIO * pivots.max():

            def solve(b: np.ndarray) -> np.ndarray:
                return basis @ solve_triangular(upper, b, trans="T", check_finite=False)

            qd = solve(system.nu(k))
            return qd, solve(system.gamma(system.kin(q, qd, t)))
    qd, *_ = np.linalg.lstsq(jac, system.nu(k), rcond=None)
    qdd, *_ = np.linalg.lstsq(jac, system.gamma(system.kin(q, qd, t)), rcond=None)
    return qd, qdd


def _given_positions(system: System, initial) -> list[tuple]:
    out = []
    for item in initial:
        if isinstance(item, InitialValue) and item.value is not None:
            out.append((item, system.coordinate_of(item.joint, item.coordinate)))
    return out


def _position_notes(system: System, k: Kin, given) -> list[str]:
    notes = []
    for item, m in given:
        actual = m.value(k)
        if abs(actual - item.value) > _REPORT_CHANGE * max(1.0, abs(item.value)):
            notes.append(
                f"initial {m.kind} of joint '{item.joint}' changed from "
                f"{item.value:.6g} to {actual:.6g} to satisfy the constraints"
            )
    return notes


def _given_residual(system: System, given, targets, t: float):
    def residual(x):
        k = system.kin(x, None, t)
        extra = [m.value(k) - target for (_, m), target in zip(given, targets)]
        return np.concatenate([system.phi(k), extra])

    return residual


def _given_jacobian(system: System, given, t: float):
    def jacobian(x):
        k = system.kin(x, None, t)
        extra = [system.coordinate_gradient(m, k) for _, m in given]
        return np.vstack([system.phi_q(k)] + extra)

    return jacobian


def _driven(system: System, t: float) -> list[tuple[str, tuple]]:
    """The motions as (name, (value at t, measure)) entries of the assembly's path."""
    out = []
    for name, motion in system.mechanism.motions.items():
        item = InitialValue(motion.joint, motion.function.value(t), coordinate=motion.coordinate)
        out.append((name, (item, system.coordinate_of(motion.joint, motion.coordinate))))
    return out


def _guesses(system: System, initial) -> dict[str, float]:
    """The guessed joint coordinates by joint (rad or m)."""
    return {
        item.joint: item.guess
        for item in initial
        if isinstance(item, InitialValue) and item.guess is not None
    }


@dataclass
class _Path:
    """The assembly's way from the drawn geometry to the given values and guesses: stage
    targets (given, then guessed coordinates) at a fraction of the way. `given` and
    `guessed` are (InitialValue, measure) pairs, a guess as the value its pair aims at."""

    system: System
    t: float
    given: list
    guessed: list
    check: BranchCheck
    weights: np.ndarray

    @property
    def aims(self) -> list:
        """The (InitialValue, measure) pairs the way ends at: given, then guessed."""
        return self.given + self.guessed

    def targets(self, start: list[float], reached: int, units: int) -> list[float]:
        """The targets `reached` / `units` of the way from `start`."""
        ends = [item.value for item, _ in self.aims]
        return [v + (end - v) * reached / units for v, end in zip(start, ends)]

    def solve(self, q: np.ndarray, targets: list[float]) -> tuple[np.ndarray, int]:
        rows = self.aims
        q, n, _ = _newton(
            _given_residual(self.system, rows, targets, self.t),
            _given_jacobian(self.system, rows, self.t),
            q,
            POSITION_TOLERANCE,
            self.weights,
        )
        return q, n


def _follow(path: _Path, q: np.ndarray) -> tuple[np.ndarray, int, list[str]]:
    """q at the given values (and near the guesses), reached from the drawn geometry in
    stages of at most _STAGE rad, the unwrapping references committed between stages (one
    Newton jump of 170 deg would wrap); also the joints that left the drawn branch. Without
    guesses a stage that turns the loop's orientation, ends where it is singular (a toggle
    or a bifurcation, where the branch is ambiguous: also where Newton needs more than
    _SLOW_NEWTON iterations, as it does near one) or makes a joint jump by more than the
    branch angle is halved (at most _SPLITS times): the assembly stays on the drawn branch;
    the joints of a stage that cannot be kept so are returned (those that jumped, else
    those that moved, the largest move first)."""
    system, t = path.system, path.t
    k = system.kin(q, None, t)
    start = [m.value(k) for _, m in path.aims]
    # the way in units of the smallest stage, counted in integers: the fraction of an
    # unhalved stage is exactly stage / stages (IEEE division of exact integers)
    full = 2**_SPLITS
    units = _stages(path, start) * full
    watch = not path.guessed  # guesses choose the branch themselves
    skip = {item.joint for item, _ in path.given}
    sign = orientation(system, k, [m for _, m in path.given]) if watch else 0
    angles = angle_values(system, k)
    done, step, its, flagged = 0, full, 0, list[str]()
    before: tuple[np.ndarray, int] | None = None  # the last stage's start, once near one
    while done < units:
        reached = min(units, done + step)
        trial, n = path.solve(
            _predicted(q, done, reached, before), path.targets(start, reached, units)
        )
        its += n
        k = system.kin(trial, None, t)
        now = angle_values(system, k)
        now_sign = orientation(system, k, [m for _, m in path.given]) if watch else 0
        turned = sign != 0 and sign != now_sign  # a sign of 0: on the singular position
        turned |= watch and n > _SLOW_NEWTON  # no quadratic convergence: a singular Jacobian
        jumps = stage_jumps(angles, now, path.check.angle, skip) if watch else []
        if (turned or jumps) and step > 1:
            step //= 2
            before = before or (q, done)  # near a singular position: predicted from here on
            continue
        if turned or jumps:
            moved = jumps or stage_jumps(angles, now, 0.0, skip)
            flagged += [j for j, _, _ in moved if j not in flagged]
        sign = now_sign or sign
        before = (q, done) if before is not None or turned or jumps else None
        q, angles, done = trial, now, reached
        step = min(full, 2 * step)
        system.commit(k)
    return q, its, flagged


def _stages(path: _Path, start: list[float]) -> int:
    """The stages of _STAGE (rad, or m for a travel) the way from `start` takes at least;
    SolverFailure beyond MAX_STAGES: a value so far from the drawn geometry (a unit slip
    of 1e6 m) would take minutes to follow, or for ever."""
    spans = [abs(item.value - v) for (item, _), v in zip(path.aims, start)]
    far = max(range(len(spans)), key=spans.__getitem__)
    stages = max(1, math.ceil(spans[far] / _STAGE))
    if stages <= MAX_STAGES:
        return stages
    item, measure = path.aims[far]
    unit = "rad" if measure.kind == "angle" else "m"
    raise SolverFailure(
        f"the initial positions could not be assembled: joint '{item.joint}' is given "
        f"{item.value:.6g} {unit}, {spans[far]:.6g} {unit} from the drawn geometry "
        f"({start[far]:.6g} {unit}), too far to assemble: the assembly follows the drawn "
        f"geometry in stages of at most {_STAGE:.3g} {unit}, and it would take {stages:.3g} "
        f"stages, more than {MAX_STAGES}; give a value nearer the drawn geometry",
        time=path.t,
        where=(item.joint,),
        status=Status.NEWTON_FAILED,
    )


def _predicted(
    q: np.ndarray, done: int, reached: int, before: tuple[np.ndarray, int] | None
) -> np.ndarray:
    """Newton's start for the stage from `done` to `reached` (units of the way) at q: q
    itself, or near a singular position (`before`: the last stage's start q and units,
    kept once a stage was halved or flagged there) the secant through the last two stages
    carried on. At a bifurcation two branches cross (a parallelogram four-bar with its four
    links aligned: it may fold into an antiparallelogram) and Newton from q converges to
    either, as round-off in its nearly singular steps decides (another machine's LAPACK
    kernels took the other branch); the secant continues the way the mechanism came, on the
    drawn branch."""
    if before is None or before[1] >= done:
        return q
    previous, at = before
    return q + (q - previous) * ((reached - done) / (done - at))


_OFF_BRANCH = (
    "the given initial values (or the motions at the start) are not reached from the drawn "
    "geometry without passing a toggle or a bifurcation, where the loop may snap through "
    "to another assembly; give `guess:` values of these joints in `initial:` to choose the "
    "branch, or check the given values"
)


def assemble(
    system: System, t: float, initial: Sequence = (), check: BranchCheck | None = None
) -> Assembled:
    """Initial q, qd: design position moved onto the constraints and the given values,
    on the branch of the drawn geometry or near the guesses (mechlib.solvers.branches).
    The positions are kept per process by the values they are found from
    (mechlib.solvers.start_memo: a sweep of initial rates places its mechanism once)."""
    check = check or BranchCheck()
    with _within_doubles(system, t, initial):
        placed = placed_start(system, t, initial, check, lambda: _placed(system, t, initial, check))
    qd, vnotes = _initial_velocities(system, placed.q, t, initial, _assembly_weights(system))
    return Assembled(placed.q, qd, placed.iterations, placed.notes + vnotes, placed.changes)


@contextmanager
def _within_doubles(system: System, t: float, initial: Sequence) -> Iterator[None]:
    """The assembly's _BeyondDoubles as the run's failure: the initial positions could not
    be assembled, with the largest given value (the likely culprit, e.g. a modal coordinate
    of 1e300)."""
    try:
        yield
    except _BeyondDoubles:
        raise SolverFailure(
            "the initial positions could not be assembled: the constraint equations on the "
            "way to the given values exceed the range of double-precision numbers"
            f"{_largest_given(system, initial)}; give values the mechanism can reach",
            time=t,
            status=Status.NEWTON_FAILED,
        ) from None


def _largest_given(system: System, initial: Sequence) -> str:
    """` (the largest given value: modal coordinate 1 of flexible body 'strip', 1e+300)`,
    or nothing when no position is given."""
    given = [
        (abs(item.value), f"joint '{item.joint}' at {item.value:.6g}")
        for item, _ in _given_positions(system, initial)
    ]
    given += [
        (abs(m.value), f"modal coordinate {m.mode + 1} of flexible body '{m.body}', {m.value:.6g}")
        for m in modal_targets(system, initial)
    ]
    if not given:
        return ""
    return f" (the largest given value: {max(given, key=lambda pair: pair[0])[1]})"


def _placed(system: System, t: float, initial: Sequence, check: BranchCheck) -> Placed:
    """The positions of `assemble` (m, Euler parameters, modal coordinates), its Newton
    iterations, notes and branch changes."""
    given = _given_positions(system, initial)
    guessed = [
        (InitialValue(j, g), system.coordinate_of(j)) for j, g in _guesses(system, initial).items()
    ]
    q = system.design_q()
    weights = _assembly_weights(system)
    its, flagged = 0, list[str]()
    driven = _driven(system, t)
    k0 = system.kin(q, None, t)
    drawn = angle_values(system, k0)
    moved = any(abs(m.value(k0) - item.value) > _REPORT_CHANGE for _, (item, m) in driven)
    if given or guessed or moved:
        motions = [name for name, _ in driven]
        held = {item.joint for item, _ in given}  # one target per joint: a repeated row is
        driven = [(name, d) for name, d in driven if d[0].joint not in held]  # an SVD's cost
        for name in motions:  # their values at t become stage targets too (every motion
            system.set_active(name, False)  # is active at the start: no event has run yet)
        try:
            path = _Path(system, t, given + [d for _, d in driven], guessed, check, weights)
            q, its, flagged = _follow(path, q)
        finally:
            for name in motions:
                system.set_active(name, True)
        if guessed:  # the given values exactly, from the point nearest the guesses
            q, n = _Path(system, t, given, [], check, weights).solve(
                q, [item.value for item, _ in given]
            )
            its += n
    modal = modal_targets(system, initial)  # after the path: no branch hangs on the modes
    q, its2 = _on_constraints(system, q, t, given, modal, weights)
    k = system.kin(q, None, t)
    notes = _position_notes(system, k, given)
    notes += modal_notes(modal, q[[m.column for m in modal]], "modal coordinate")
    changes = guess_changes(system, k, _guesses(system, initial), check)
    if flagged:
        final = angle_values(system, k)
        joints = tuple((j, drawn[j], final[j]) for j in flagged)
        changes.insert(0, BranchChange(t, joints, "drawn", _OFF_BRANCH))
    return Placed(q, its + its2, notes, changes)


def reassemble(
    system: System, q: np.ndarray, t: float, initial: Sequence
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(q, qd, notes) as `assemble` gives them, from a q already near (no path from the
    drawing): on the constraints, the given joint values and modal coordinates and rates."""
    weights = _assembly_weights(system)
    modal = modal_targets(system, initial)
    with _within_doubles(system, t, initial):
        q, _ = _on_constraints(system, q, t, _given_positions(system, initial), modal, weights)
    notes = modal_notes(modal, q[[m.column for m in modal]], "modal coordinate")
    qd, vnotes = _initial_velocities(system, q, t, initial, weights)
    return q, qd, notes + vnotes


def _on_constraints(
    system: System, q: np.ndarray, t: float, given, modal: list[ModalTarget], weights
) -> tuple[np.ndarray, int]:
    """(q, Newton iterations): the given modal coordinates reached (with the given joint
    values), then the constraints met exactly; committed (the angles' references)."""
    its = 0
    if modal:
        q, its = _reach_modes(system, q, t, given, modal, weights)
    q, n = solve_positions(system, q, t, weights=weights)
    system.commit(system.kin(q, None, t))
    return q, its + n


def _reach_modes(
    system: System, q: np.ndarray, t: float, given, modal: list[ModalTarget], weights
) -> tuple[np.ndarray, int]:
    """q on the constraints, the given joint values and the given modal coordinates
    (least squares where they contradict each other). The modal rows are divided by
    _MODAL_WEIGHT: unit rows in the scaled columns of the least squares."""
    columns = np.array([m.column for m in modal])
    targets = np.array([m.value for m in modal])
    unit = np.zeros((len(modal), system.nq))
    unit[np.arange(len(modal)), columns] = 1.0 / _MODAL_WEIGHT
    joint_rows = _given_residual(system, given, [item.value for item, _ in given], t)
    joint_jacobian = _given_jacobian(system, given, t)

    def residual(x: np.ndarray) -> np.ndarray:
        return np.concatenate([joint_rows(x), (x[columns] - targets) / _MODAL_WEIGHT])

    def jacobian(x: np.ndarray) -> np.ndarray:
        return np.vstack([joint_jacobian(x), unit])

    q, n, _ = _newton(residual, jacobian, q, POSITION_TOLERANCE, weights)
    return q, n


def _velocity_rows(system: System, k: Kin, initial) -> tuple[list, list, list]:
    rows, rhs, names = [], [], []
    for item in initial:
        if isinstance(item, InitialValue) and item.rate is not None:
            m = system.coordinate_of(item.joint, item.coordinate)
            rows.append(system.coordinate_gradient(m, k))
            rhs.append(item.rate)
            names.append((f"rate of joint '{item.joint}'", rows[-1][None, :], [item.rate]))
        elif isinstance(item, InitialBodyVelocity):
            b = system.body_index(item.body)
            block = system.body_rates(k, b)
            for sl, vec, what in (
                (slice(0, 3), item.velocity, "velocity"),
                (slice(3, 6), item.omega, "omega"),
            ):
                if vec is not None:
                    rows.extend(block[sl])
                    rhs.extend(vec)
                    names.append((f"{what} of body '{item.body}'", block[sl], list(vec)))
    return rows, rhs, names


def _initial_velocities(system: System, q: np.ndarray, t: float, initial, weights: np.ndarray):
    """qd on the velocity constraints and the given rates, smallest in the `weights` norm
    (with flexible bodies: of least kinetic energy, mechlib.solvers.least_energy)."""
    k = system.kin(q, None, t)
    phi_q, nu = system.phi_q(k), system.nu(k)
    rows, rhs, names = _velocity_rows(system, k, initial)
    modal_rows, modal_rhs, modal = modal_rate_rows(system, initial)
    if modal:  # unit rows in the scaled columns, as in _reach_modes
        rows = [*rows, *(modal_rows / _MODAL_WEIGHT)]
        rhs = [*rhs, *(modal_rhs / _MODAL_WEIGHT)]
    given, values = np.array(rows).reshape(len(rows), system.nq), np.array(rhs, dtype=float)
    if system.nz:
        metric = velocity_metric(system, k, weights)
        qd = weights * least_energy_velocities(phi_q * weights, nu, given * weights, values, metric)
    else:
        qd = _smallest_velocities(phi_q, nu, given, values, weights)
    notes = []
    for what, block, wanted in names:
        actual = block @ qd
        if np.abs(actual - wanted).max() > _REPORT_CHANGE * max(1.0, np.abs(wanted).max()):
            notes.append(
                f"initial {what} changed from {_shown(wanted)} to {_shown(actual)} to "
                "satisfy the constraints"
            )
    notes += modal_notes(modal, modal_rows @ qd, "modal rate")
    return qd, notes


def _smallest_velocities(
    phi_q: np.ndarray, nu: np.ndarray, rows: np.ndarray, rhs: np.ndarray, weights: np.ndarray
) -> np.ndarray:
    """qd of a rigid mechanism: the constraints and the given `rows` in one least squares,
    smallest in the `weights` column norm, then moved onto the constraints."""
    count(factorizations=2 if len(rows) else 1)
    qd = np.zeros(len(weights))
    if len(rows):
        scaled, *_ = np.linalg.lstsq(
            np.vstack([phi_q, rows]) * weights, np.concatenate([nu, rhs]), rcond=None
        )
        qd = weights * scaled
    fix, *_ = np.linalg.lstsq(phi_q * weights, nu - phi_q @ qd, rcond=None)
    return qd + weights * fix


def _shown(values: Sequence[float] | np.ndarray) -> str:
    """A given or projected initial rate as its note shows it (SI, to 9 decimals): a
    joint's rate as a number, a body's velocity or omega as a list."""
    rounded = np.round(np.asarray(values, dtype=float), 9).tolist()
    return str(rounded[0]) if len(rounded) == 1 else str(rounded)
