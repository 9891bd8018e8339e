"""Near-singular positions (toggles, dead points): how close the constraints are to rank loss.

A position is near-singular where the constraint Jacobian, active motions and locks
included, comes close to losing rank: there the reactions (and the efforts of the motions)
grow without bound and the mechanism's mobility changes -- a slider-crank driven at its
slider through a dead centre, an over-centre lock driven through its straight position,
the parallelogram chain of IFToMM A02 as its links align. A joint coordinate that merely
stops moving is no such position: a slider-crank driven by its crank, or free, passing
its dead centres keeps a Jacobian of full rank (the slider's travel reverses, the crank's
angle still fixes the position) and bounded reactions; so does a landing gear's leg turning
back where its drag brace goes straight with nothing driving the leg.

The toggle measure of a position is dimensionless, in [0, 1], and the same whatever the
units or the size of the mechanism: the constraint Jacobian is taken per unit motion
(translation columns times the mechanism's length L, Euler-parameter columns times 1/2,
i.e. per radian of rotation) and each equation scaled to a unit row (an equation's scale
does not change what it allows); its smallest singular value is 0 when equations become
dependent. It is taken relative to its largest value in the run (absolute values depend
on the arrangement: a 3D model with nearly parallel axes is weakly conditioned
everywhere). Reactions grow like 1/measure near a toggle. Checked at the recorded output
rows, after the analysis (docs/analyses.md): one warning per event (rows below the
threshold, those between two such runs of rows joined unless the measure recovers to
_RECOVERED times the threshold between them), naming at most NAMED_AT_MOST joints.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dgetrf, dgetrs
from scipy.sparse.linalg import splu

from mechlib.core.jit import njit
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics.constraint_arrays import ConstraintArrays, row_work
from mechlib.linalg.rank import Redundancy
from mechlib.system.system import System

__all__ = [
    "NAMED_AT_MOST",
    "NEAR_SINGULAR",
    "TOGGLE_THRESHOLD",
    "Toggle",
    "toggle_detail",
    "toggle_warnings",
    "weakest_equations",
]

TOGGLE_THRESHOLD = 0.1
NEAR_SINGULAR = "near-singular position (toggle or dead point) at t ="  # each warning's start
_NAMED_SHARE = 0.1  # an equation is named when its weight is this share of the largest
_MAX_ITERATIONS = 50
_ITERATION_TOLERANCE = 1e-6
_GRAM_FLOOR = 1e-14
_DENSE_ROWS = 150  # up to this many equations a dense LU of J J^T is the faster one
_BATCH_ROWS = 60  # up to this many equations, the rows of a run are measured in batches
_BATCH_SIZE = 256  # rows per batch (bounds the memory of many coordinates, long runs)
_RUN_ROWS = 4096  # rows per compiled call (it keeps one row's Jacobian at a time)
# rows: the toggle check's bounds of a row from the last measured row's (`_chained`) while
# its lower bound stays at least this times the threshold of the largest upper bound: the
# check conclusive by a factor 2 where it needs no eigenvalue (the bounds are 2x apart)
_REACH = 2.0
_REASSOCIATE = {"reassoc", "contract"}  # sums in any order: vectorised loops
_RECOVERED = 2.0  # an event ends where the measure is back above this times the threshold
NAMED_AT_MOST = 5  # joints (requests) named per warning at most, the others counted


@dataclass(frozen=True)
class Toggle:
    """A near-singular position: its measure and the dependent equations, by joint."""

    measure: float
    found: Redundancy

    def describe(self) -> str:
        """The equation and the joints it depends on, at most NAMED_AT_MOST joints named in
        all (the equation's own joint among them) and the others counted."""
        r = self.found
        shown = max(NAMED_AT_MOST - (1 if r.owner else 0), 0)
        names, rest = r.depends_on[:shown], len(r.depends_on) - shown
        if not names:
            return f"{r.label}, dependent on itself"
        if rest > 0:
            return f"{r.label}, dependent on {', '.join(names)} and {rest} other joints"
        return f"{r.label}, dependent on {', '.join(names)}"


def _length(system: System) -> float:
    """Size L (m) of the mechanism: extent of its joint points and centres of mass."""
    points = [j.at for j in system.mechanism.joints.values() if j.joints is None]
    cloud = np.vstack([system.cm[:-1], np.array(points, dtype=float).reshape(-1, 3)])
    return max(float(np.ptp(cloud, axis=0).max(initial=0.0)), 1e-3)


def _column_scale(system: System) -> np.ndarray:
    """Per coordinate: L for a translation (m), 1/2 for an Euler parameter (per radian)."""
    per_body = system.body_weights(_length(system), 0.5)
    return np.r_[np.tile(per_body, system.nb), np.ones(system.nz)]


def _unit_rows(matrix: np.ndarray) -> np.ndarray:
    norm = np.linalg.norm(matrix, axis=1)
    return matrix / np.where(norm > 0.0, norm, 1.0)[:, None]


class _Position:
    """The scaled Jacobian at one position, factored through its Gram matrix J J^T (sparse
    LU: a joint row touches two bodies), and its smallest singular value by inverse
    iteration (no SVD). `phi_q`: the constraint Jacobian at k when the caller has it."""

    def __init__(
        self,
        system: System,
        k,
        start: np.ndarray | None = None,
        scale: np.ndarray | None = None,
        phi_q: np.ndarray | None = None,
    ):
        self.system, self.k = system, k
        self.scale = _column_scale(system) if scale is None else scale
        jac = _unit_rows((system.phi_q(k) if phi_q is None else phi_q) * self.scale)
        m = jac.shape[0]
        # a floor of _GRAM_FLOOR on J J^T keeps an exactly singular position factorable
        self.jac: np.ndarray | sp.csr_matrix
        self.lu: Callable[[np.ndarray], np.ndarray] | None = None
        if m > _DENSE_ROWS:
            self.jac = sp.csr_matrix(jac)
            self.lu = splu((self.jac @ self.jac.T + _GRAM_FLOOR * sp.identity(m)).tocsc()).solve
        elif m:
            self.jac = jac
            lu, pivots, _ = dgetrf(jac @ jac.T + _GRAM_FLOOR * np.eye(m))
            self.lu = lambda rhs: dgetrs(lu, pivots, rhs)[0]  # LAPACK direct: no wrapper cost
        else:
            self.jac = jac
        self._start = start

    @cached_property
    def _rank(self) -> tuple[np.ndarray, float]:
        """(weights, sigma) of `_smallest`, found on first use."""
        return self._smallest(self._start) if self.jac.shape[0] else (np.zeros(0), 1.0)

    @property
    def weights(self) -> np.ndarray:
        """The unit left singular vector of the smallest singular value."""
        return self._rank[0]

    @property
    def sigma(self) -> float:
        return self._rank[1]

    def _smallest(self, start: np.ndarray | None) -> tuple[np.ndarray, float]:
        """(unit left singular vector, smallest singular value) of J by inverse iteration
        on J J^T; `start` (the previous position's vector) makes it converge in a few."""
        m = self.jac.shape[0]
        x = start if start is not None and start.size == m else np.ones(m) / np.sqrt(m)
        value = np.inf
        for _ in range(_MAX_ITERATIONS):
            y = self._solve(x)
            if not np.isfinite(y).all():
                return x, 0.0
            x, previous, value = y / np.linalg.norm(y), value, float(1.0 / np.linalg.norm(y))
            if abs(previous - value) <= _ITERATION_TOLERANCE * value:
                break
        return x, float(np.sqrt(max(float(x @ (self.jac @ (self.jac.T @ x))), 0.0)))

    def rank_measure(self) -> float:
        """Smallest singular value of the scaled Jacobian (1 without equations)."""
        return self.sigma

    def _solve(self, rhs: np.ndarray) -> np.ndarray:
        """(J J^T)^-1 rhs; without equations rhs is empty and so is the answer."""
        return rhs if self.lu is None else self.lu(rhs)

    def rank_deficiency(self) -> Redundancy:
        """The equations of the smallest singular vector, the latest joint named first."""
        weights, system = self.weights, self.system
        owners, rank = system.owners, system.owner_rank
        rows = [i for i in _significant(weights) if owners[i] not in system.body_names]
        rows = rows or [int(np.argmax(np.abs(weights)))]
        last = max(rows, key=lambda i: (rank.get(owners[i], 10**6), abs(weights[i])))
        return Redundancy(
            last, system.labels[last], owners[last], _owners_of(weights, system, owners[last])
        )


def _significant(weights: np.ndarray) -> np.ndarray:
    """Indices of the weights of at least _NAMED_SHARE of the largest."""
    return np.flatnonzero(np.abs(weights) >= _NAMED_SHARE * np.abs(weights).max())


def _owners_of(weights: np.ndarray, system: System, own: str) -> tuple[str, ...]:
    """Owners of the rows carrying at least _NAMED_SHARE of the largest weight, largest
    first (body normalisations and `own` left out)."""
    owners, bodies = system.owners, set(system.body_names)
    big = _significant(weights)
    names: list[str] = []
    for i in big[np.argsort(-np.abs(weights[big]))]:
        if owners[i] not in names and owners[i] not in bodies and owners[i] != own:
            names.append(owners[i])
    return tuple(names)


def toggle_detail(system: System, k) -> str:
    """'; near-singular position (...): <equations>' when the scaled Jacobian at state k has
    a smallest singular value below TOGGLE_THRESHOLD times the one at the design position
    (the reference a failure has: no run behind it), else ''."""
    position = _Position(system, k)
    design = _Position(system, system.kin(system.design_q(), None, k.t)).rank_measure()
    value = position.rank_measure() / max(design, _GRAM_FLOOR)
    if value >= TOGGLE_THRESHOLD:
        return ""
    return (
        f"; near-singular position (toggle or dead point, measure {value:.2g}): "
        f"{Toggle(value, position.rank_deficiency()).describe()}"
    )


def weakest_equations(system: System, k) -> tuple[float, str]:
    """(measure, equations): the smallest singular value of the scaled Jacobian at state k
    over the one at the design position, and the equations closest to dependence there
    (those of that singular value), by joint."""
    position = _Position(system, k)
    design = _Position(system, system.kin(system.design_q(), None, k.t)).rank_measure()
    measure = position.rank_measure() / max(design, _GRAM_FLOOR)
    return measure, Toggle(measure, position.rank_deficiency()).describe()


def _episodes(values: np.ndarray, threshold: float) -> list[tuple[int, int]]:
    """(first, last) row index of each event: runs of consecutive values below threshold,
    two runs joined where the values between them stay below _RECOVERED times the
    threshold (a measure wavering about the threshold in one crossing is one event)."""
    below = np.r_[False, values < threshold, False].astype(int)
    edges = np.diff(below)
    runs = [
        (int(a), int(b))
        for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1)
    ]
    events: list[tuple[int, int]] = []
    for first, last in runs:
        if events and values[events[-1][1] + 1 : first].max() < _RECOVERED * threshold:
            events[-1] = (events[-1][0], last)
        else:
            events.append((first, last))
    return events


def _series(system: System, trajectory) -> np.ndarray:
    """Per recorded row: the rank measure (the smallest singular value of the scaled
    Jacobian)."""
    return _walk(system, trajectory, bounds=False)[0]


def _walk(
    system: System, trajectory, bounds: bool, level: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Per recorded row: (lower, upper) bounds of the rank measure -- with `bounds`, from
    the trace and a diagonal of (J J^T)^-1 (`_rank_bounds`) for the rows measured in
    batches (in the compiled calls with a `level`, of the rows `_chained` measures, the
    others bounded from them and measured too where that bound is below `level` of the
    call's largest), else both the measure itself. Rows of up to _BATCH_ROWS equations are
    measured together: in one compiled call per run of rows with the same active equations
    where the system packs its constraints (`_compiled_measures`), else in batches
    (`_Batch`); larger ones one by one (`_Position`, sparse and warm-started)."""
    n = len(trajectory)
    ranks, highs, start = np.empty(n), np.empty(n), None
    scale = _column_scale(system)  # the mechanism's size, the same at every row
    batch = _Batch(bounds)
    arrays = system.packed_constraints()
    active = None
    i = 0
    while i < n:
        system.restore_snapshot(trajectory.references[i])
        if system.active is not active:  # a batch holds the rows of one active set
            batch.flush(ranks, highs)
            active = system.active
        if arrays is not None and 0 < system.active.size <= _BATCH_ROWS:
            end = trajectory.same_active(i, _RUN_ROWS)
            rows = np.arange(i, end)
            ranks[rows], highs[rows] = _compiled_measures(
                arrays, trajectory.stacked("q", i, end), scale, bounds, level
            )
            i = end
            continue
        k = system.kin(trajectory.q[i], None, trajectory.time[i])
        jac = system.phi_q(k)
        if jac.shape[0] <= _BATCH_ROWS:
            batch.add(i, _unit_rows(jac * scale))
            if len(batch.rows) >= _BATCH_SIZE:
                batch.flush(ranks, highs)
        else:
            position = _Position(system, k, start, scale, jac)
            ranks[i], start = position.rank_measure(), position.weights
            highs[i] = ranks[i]
        i += 1
    batch.flush(ranks, highs)
    system.restore_snapshot(trajectory.references[n - 1])
    return ranks, highs


def _compiled_measures(
    arrays: ConstraintArrays,
    qs: np.ndarray,
    scale: np.ndarray,
    bounds: bool,
    level: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """(lows, highs) of the rows at states `qs` (n, nq), in one compiled call: the
    measures `_Batch` takes of the scaled unit constraint rows, without keeping them
    (mechlib.kinematics.constraint_arrays.scaled_row); with `bounds` and a `level`, the
    rows chained from the measured ones (`_chained`)."""
    ints, floats = arrays.packed()
    n, nq = qs.shape
    work = row_work(ints, nq)
    lows, highs = np.empty(n), np.empty(n)
    _rows_measures(
        np.ascontiguousarray(qs),
        ints,
        floats,
        scale,
        work,
        _GRAM_FLOOR,
        bounds,
        level,
        lows,
        highs,
    )
    return lows, highs


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _rows_measures(qs, ints, floats, scale, work, floor, bounds, level, lows, highs):
    """Per state of qs: `_row_measures` of its scaled unit rows
    (mechlib.kinematics.constraint_arrays.scaled_row) into lows and highs; with `bounds`
    and a `level` above 0, the rows chained instead (`_chained`)."""
    nq = qs.shape[1]
    m = ints[7]
    jac = np.zeros((m, nq))
    gram, inverse, column = np.empty((m, m)), np.empty((m, m)), np.empty((2, m))
    packed = ca.unpack(ints, floats)
    if bounds and level > 0.0:
        _chained(qs, packed, scale, work, floor, level, lows, highs, jac, gram, inverse, column)
        return
    for r in range(qs.shape[0]):
        ca.scaled_row(qs[r], packed, scale, work, jac)
        lows[r], highs[r] = _row_measures(jac, floor, bounds, gram, inverse, column)


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _chained(qs, packed, scale, work, floor, level, lows, highs, jac, gram, inverse, column):
    """Bounds of each row's rank measure, the first row's measured (`_rank_bounds`), each
    later row's from the last measured row's by Weyl's inequality (`_frobenius_distance`)
    while its lower bound stays at least _REACH times `level` of the largest upper bound so
    far, else measured (and bounding the rows after it); then the rows whose lower bound is
    below `level` of the largest upper bound of all are measured too (the tighter of the
    two bounds kept). Each row's scaled unit rows are made once (jac, the measured row's
    in `kept`); gram, inverse (m, m) and column (2, m): work arrays."""
    n = qs.shape[0]
    kept = np.zeros_like(jac)
    measured = np.zeros(n, np.bool_)
    ca.scaled_row(qs[0], packed, scale, work, kept)
    lows[0], highs[0] = _row_measures(kept, floor, True, gram, inverse, column)
    measured[0] = True
    low, high, top = lows[0], highs[0], highs[0]
    for r in range(1, n):
        ca.scaled_row(qs[r], packed, scale, work, jac)
        moved = _frobenius_distance(jac, kept)
        if low - moved >= _REACH * level * top:
            lows[r], highs[r] = low - moved, high + moved
        else:
            lows[r], highs[r] = _row_measures(jac, floor, True, gram, inverse, column)
            measured[r] = True
            kept, jac = jac, kept
            low, high = lows[r], highs[r]
        top = max(top, highs[r])
    near = level * highs.max()
    for r in range(n):
        if lows[r] < near and not measured[r]:
            ca.scaled_row(qs[r], packed, scale, work, jac)
            low, high = _row_measures(jac, floor, True, gram, inverse, column)
            lows[r], highs[r] = max(lows[r], low), min(highs[r], high)


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _frobenius_distance(a, b):
    """||a - b||_F of two (m, nq) arrays: by Weyl's inequality no singular value of a is
    more than this from b's (the spectral norm of a - b is at most its Frobenius norm),
    whatever the motion between the two rows."""
    acc = 0.0
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            d = a[i, j] - b[i, j]
            acc += d * d
    return math.sqrt(acc)


class _Batch:
    """Rows of one active set with few equations, measured in one go: the smallest
    singular value of each scaled Jacobian from the eigenvalues of J J^T (with `bounds`:
    bounds of it, `_rank_bounds`), in one compiled call."""

    def __init__(self, bounds: bool = False) -> None:
        self.bounds = bounds
        self.rows: list[int] = []
        self.jacs: list[np.ndarray] = []  # each (m, nq)

    def add(self, row: int, jac: np.ndarray) -> None:
        self.rows.append(row)
        self.jacs.append(jac)

    def flush(self, ranks: np.ndarray, highs: np.ndarray) -> None:
        """Write the measures of the rows held into `ranks` (with `bounds`: their lower
        bounds) and `highs` (their upper bounds); empty the batch."""
        if not self.rows:
            return
        jac = np.ascontiguousarray(np.stack(self.jacs))  # (n, m, nq)
        n = len(self.rows)
        rank, high = np.empty(n), np.empty(n)
        _batch_measures(jac, _GRAM_FLOOR, self.bounds, rank, high)
        ranks[self.rows], highs[self.rows] = rank, high
        self.rows, self.jacs = [], []


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _batch_measures(jacs, floor, bounds, lows, highs):
    """`_row_measures` of each row i (its scaled Jacobian jacs[i] (m, nq)) into lows and
    highs."""
    n, m, _ = jacs.shape
    gram, inverse, column = np.empty((m, m)), np.empty((m, m)), np.empty((2, m))
    for i in range(n):
        lows[i], highs[i] = _row_measures(jacs[i], floor, bounds, gram, inverse, column)


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _row_measures(jac, floor, bounds, gram, inverse, column):
    """(low, high) of one row: the smallest singular value of the scaled Jacobian jac
    (m, nq) from the eigenvalues of J J^T (1 without equations) -- with `bounds`, bounds
    of it instead (`_rank_bounds`, J J^T floored by `floor`). gram, inverse (m, m) and
    column (2, m): work arrays."""
    m, nq = jac.shape
    if m == 0:
        return 1.0, 1.0
    for a in range(m):
        for b in range(a + 1):
            acc = 0.0
            for j in range(nq):
                acc += jac[a, j] * jac[b, j]
            gram[a, b] = gram[b, a] = acc
    if not bounds:
        value = math.sqrt(max(np.linalg.eigvalsh(gram)[0], 0.0))
        return value, value
    for k in range(m):
        gram[k, k] += floor
    if not _lower_inverse(gram, inverse):  # measured exactly by the caller
        return 0.0, 1.0
    return _rank_bounds(inverse, floor, column[0], column[1])


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _rank_bounds(inverse, floor, diagonal, column):
    """(lower, upper) bounds of the smallest singular value of J from L^-1, the inverse
    Cholesky factor of G = J J^T + floor I (G^-1 = L^-T L^-1): lambda_min >= 1 /
    trace(G^-1), and lambda_min <= the Rayleigh quotient of G^-1 e_k for the k of G^-1's
    largest diagonal entry (one step of inverse iteration), each less the floor.
    diagonal, column (m,): work arrays."""
    m = inverse.shape[0]
    diagonal[:] = 0.0  # of G^-1: the columns of L^-1 squared
    for a in range(m):
        for k in range(a + 1):
            diagonal[k] += inverse[a, k] * inverse[a, k]
    k = int(np.argmax(diagonal))
    for b in range(m):  # G^-1 e_k = L^-T (L^-1 e_k)
        acc = 0.0
        for a in range(max(b, k), m):
            acc += inverse[a, b] * inverse[a, k]
        column[b] = acc
    squares = 0.0
    for b in range(m):
        squares += column[b] * column[b]
    low = math.sqrt(max(1.0 / diagonal.sum() - floor, 0.0))
    return low, math.sqrt(max(diagonal[k] / squares - floor, 0.0))


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _lower_inverse(gram, inverse):
    """L^-1 into `inverse` (lower; its upper triangle left as it was) of the Cholesky
    factor L of `gram`, which is overwritten with L in its lower triangle; False where
    gram is not positive definite or not finite (then `inverse` is undefined). By rows,
    with reciprocals of the pivots: no division in the loops."""
    m = gram.shape[0]
    for k in range(m):
        pivot = gram[k, k]
        for p in range(k):
            pivot -= gram[k, p] * gram[k, p]
        if not pivot > 0.0 or not math.isfinite(pivot):
            return False
        pivot = math.sqrt(pivot)
        gram[k, k] = pivot
        reciprocal = 1.0 / pivot
        inverse[k, k] = reciprocal
        for a in range(k + 1, m):
            acc = gram[a, k]
            for p in range(k):
                acc -= gram[a, p] * gram[k, p]
            if not math.isfinite(acc):
                return False
            gram[a, k] = acc * reciprocal
    for a in range(1, m):  # row a of L^-1: -(sum over b < a of L[a, b] (L^-1)[b, :]) / L[a, a]
        for k in range(a):
            inverse[a, k] = 0.0
        for b in range(a):
            weight = gram[a, b]
            for k in range(b + 1):
                inverse[a, k] -= weight * inverse[b, k]
        for k in range(a):
            inverse[a, k] *= inverse[a, a]
    return True


def _relative(ranks: np.ndarray) -> np.ndarray:
    """Each row's rank measure over the largest of the run: the toggle measure."""
    return ranks / max(float(ranks.max()), _GRAM_FLOOR)


def _toggle_measures(system: System, trajectory, threshold: float) -> np.ndarray | None:
    """The toggle measure of each row, or None where the rank measure's bounds show that
    no row's is below `threshold` (then no row warns). The bounds take about a third of
    the eigenvalues' time (`_rank_bounds`); taken at the rows `_chained` measures, the
    others bounded from them, on the campaign slider-crank's 1001 rows at 93 (the scaled
    Jacobian of every row is most of what is left)."""
    lows, highs = _walk(system, trajectory, bounds=True, level=threshold)
    if not np.any(lows / max(float(highs.max()), _GRAM_FLOOR) < threshold):
        return None
    return _relative(_series(system, trajectory))


def toggle_warnings(system: System, trajectory, threshold: float = TOGGLE_THRESHOLD) -> list[str]:
    """One warning per event of recorded rows whose toggle measure is below `threshold`
    (`_episodes`): its time span, the minimum and its time, and the dependent equations
    there, by joint."""
    if not len(trajectory):
        return []
    values = _toggle_measures(system, trajectory, threshold)
    if values is None:
        return []
    out = []
    for first, last in _episodes(values, threshold):
        worst = first + int(np.argmin(values[first : last + 1]))
        system.restore_snapshot(trajectory.references[worst])
        t = trajectory.time[worst]
        position = _Position(system, system.kin(trajectory.q[worst], None, t))
        toggle = Toggle(float(values[worst]), position.rank_deficiency())
        out.append(_message(toggle, t, trajectory.time[first], trajectory.time[last], threshold))
    system.restore_snapshot(trajectory.references[len(trajectory) - 1])
    return out


def _message(toggle: Toggle, t: float, start: float, end: float, threshold: float) -> str:
    return (
        f"{NEAR_SINGULAR} {t:.6g} s: toggle measure "
        f"{toggle.measure:.3g} (below {threshold:g} from t = {start:.6g} to {end:.6g} s); "
        f"{toggle.describe()}; the constraints, motions included, are close to losing rank: "
        "reactions there grow like 1/measure; check the geometry (a brace or link going "
        "straight) or keep the motion away from this position"
    )
