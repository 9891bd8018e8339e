"""Near-singular positions (toggles, dead points): how close the constraints are to rank loss.

The toggle measure of a position is dimensionless, in [0, 1], and the same whatever the
units or the size of the mechanism:

- the constraint Jacobian is taken per unit motion (translation columns times the
  mechanism's length L, Euler-parameter columns times 1/2, i.e. per radian of rotation) and
  each equation scaled to a unit row (an equation's scale does not change what it allows);
  its smallest singular value is 0 when equations become dependent (a driven joint at a
  toggle, a change point);
- with degrees of freedom left, each joint coordinate that no motion or lock drives has the
  sine of the angle between its gradient and the constraint rows: 0 where the other joints
  leave it no motion (the leg of a landing gear when its drag brace goes straight), i.e.
  where the Jacobian would be singular if that joint were driven.

Each is taken relative to its largest value in the run (absolute values depend on the
arrangement: a 3D model with nearly parallel axes is weakly conditioned everywhere), and
the measure of a position is the smallest of them. Reactions grow like 1/measure near a
toggle. Checked at the recorded output rows, after the analysis (docs/analyses.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dgetrf, dgetrs
from scipy.sparse.linalg import splu

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics.constraint_arrays import ConstraintArrays, measure_args, row_work
from mechlib.kinematics.coordinates import AngleMeasure, CoordinateEquation, TravelMeasure
from mechlib.linalg.rank import Redundancy
from mechlib.system.system import System

__all__ = ["TOGGLE_THRESHOLD", "Toggle", "toggle_detail", "toggle_warnings", "weakest_equations"]

TOGGLE_THRESHOLD = 0.1
_NAMED_SHARE = 0.1  # an equation is named when its weight is this share of the largest
_MAX_ITERATIONS = 50
_ITERATION_TOLERANCE = 1e-6
_GRAM_FLOOR = 1e-14
_DENSE_ROWS = 150  # up to this many equations a dense LU of J J^T is the faster one
_BATCH_ROWS = 60  # up to this many equations, the rows of a run are measured in batches
_BATCH_SIZE = 256  # rows per batch (bounds the memory of many coordinates, long runs)
_RUN_ROWS = 4096  # rows per compiled call (it keeps one row's Jacobian at a time)
_REASSOCIATE = {"reassoc", "contract"}  # sums in any order: vectorised loops
_HELD = 1e-8  # sine of a coordinate the constraints hold exactly (round-off level)


@dataclass(frozen=True)
class Toggle:
    """A near-singular position: its measure and the dependent equations, by joint."""

    measure: float
    found: tuple[Redundancy, ...]

    def describe(self) -> str:
        return "; ".join(r.describe() for r in self.found[:4])


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


def _free_measures(system: System) -> list[tuple[str, AngleMeasure | TravelMeasure]]:
    """(joint, coordinate measure) of the joint coordinates no active motion or lock drives."""
    driven = set()
    for i, eq in enumerate(system.coordinates):
        if not isinstance(eq, CoordinateEquation):
            continue  # a curve joint's equations are not coordinates
        if system.n_geometric + i in system.active and len(eq.terms) == 1:
            driven.add(id(eq.terms[0][1]))
    return [(joint, m) for (joint, _), m in system.measures.items() if id(m) not in driven]


class _Position:
    """The scaled Jacobian at one position, factored through its Gram matrix J J^T (sparse
    LU: a joint row touches two bodies), and the measures built on it. No SVD: the smallest
    singular value comes from inverse iteration, projections onto the motion space from
    solves with J J^T. `phi_q`: the constraint Jacobian at k when the caller has it."""

    def __init__(
        self,
        system: System,
        k,
        start: np.ndarray | None = None,
        scale: np.ndarray | None = None,
        free: list[tuple[str, AngleMeasure | TravelMeasure]] | None = None,
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
        self.free: list[tuple[str, AngleMeasure | TravelMeasure]] = []
        if m < system.nq:
            self.free = _free_measures(system) if free is None else free

    @cached_property
    def _rank(self) -> tuple[np.ndarray, float]:
        """(weights, sigma) of `_smallest`, found on first use: a dead coordinate's
        warning needs neither."""
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

    def _gradient(self, measure) -> np.ndarray:
        return self.system.coordinate_gradient(measure, self.k) * self.scale

    def _solve(self, rhs: np.ndarray) -> np.ndarray:
        """(J J^T)^-1 rhs; without equations rhs is empty and so is the answer."""
        return rhs if self.lu is None else self.lu(rhs)

    def _row_weights(self, g: np.ndarray) -> np.ndarray:
        """y with J^T y the part of g in the span of the constraint rows (least squares)."""
        return self._solve(self.jac @ g)

    def sines(self) -> dict[tuple[str, str], float]:
        """Per free coordinate: sine of the angle between its scaled gradient and the
        constraint rows (the share of it the constraints leave free); all coordinates in
        one solve."""
        if not self.free:
            return {}
        grads = np.array([self._gradient(m) for _, m in self.free]).T  # (nq, coordinates)
        norms = np.linalg.norm(grads, axis=0)
        free = grads - self.jac.T @ self._row_weights(grads)
        share = np.linalg.norm(free, axis=0) / np.where(norms > 0.0, norms, 1.0)
        return {
            (joint, m.kind): float(value)
            for (joint, m), value, norm in zip(self.free, share, norms)
            if norm > 0.0
        }

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

    def dead_coordinate(self, joint: str, kind: str) -> Redundancy:
        """A coordinate that cannot change, with the joints whose equations hold it."""
        g = self._gradient(self.system.measure(joint, kind))
        weights = self._row_weights(g)
        return Redundancy(
            -1, f"{joint}: {kind} cannot change", joint, _owners_of(weights, self.system, joint)
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
        f"{position.rank_deficiency().describe()}"
    )


def weakest_equations(system: System, k) -> tuple[float, str]:
    """(measure, equations): the smallest singular value of the scaled Jacobian at state k
    over the one at the design position, and the equations closest to dependence there
    (those of that singular value), by joint."""
    position = _Position(system, k)
    design = _Position(system, system.kin(system.design_q(), None, k.t)).rank_measure()
    measure = position.rank_measure() / max(design, _GRAM_FLOOR)
    return measure, position.rank_deficiency().describe()


def _episodes(values: np.ndarray, threshold: float) -> list[tuple[int, int]]:
    """(first, last) row index of each run of consecutive values below threshold."""
    below = np.r_[False, values < threshold, False].astype(int)
    edges = np.diff(below)
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _series(system: System, trajectory) -> tuple[np.ndarray, _Sines]:
    """Per recorded row: the rank measure and the sines of the free coordinates."""
    ranks, _, sines = _walk(system, trajectory, bounds=False)
    return ranks, sines


def _walk(system: System, trajectory, bounds: bool) -> tuple[np.ndarray, np.ndarray, _Sines]:
    """Per recorded row: (lower, upper) bounds of the rank measure -- with `bounds`, from
    the trace and a diagonal of (J J^T)^-1 (`_rank_bounds`) for the rows measured in
    batches, else both the measure itself -- and the sines of the free coordinates. Rows
    of up to _BATCH_ROWS equations are measured together: in one compiled call per run of
    rows with the same active equations where the system packs its constraints
    (`_compiled_measures`), else in batches (`_Batch`); larger ones one by one
    (`_Position`, sparse and warm-started)."""
    n = len(trajectory)
    ranks, highs, start = np.empty(n), np.empty(n), None
    sines = _Sines(n)
    scale = _column_scale(system)  # the mechanism's size, the same at every row
    active, free = None, []  # the free coordinates change only with the active rows
    batch = _Batch(bounds)
    arrays = system.packed_constraints()
    i = 0
    while i < n:
        snapshot = trajectory.references[i]
        system.restore_snapshot(snapshot)
        if system.active is not active:
            batch.flush(ranks, highs, sines)
            active, free = system.active, _free_measures(system)
        if arrays is not None and 0 < system.active.size <= _BATCH_ROWS:
            end = trajectory.same_active(i, _RUN_ROWS)
            row_free = free if system.active.size < system.nq else []
            rows = np.arange(i, end)
            ranks[rows], highs[rows], values = _compiled_measures(
                arrays, trajectory.stacked("q", i, end), row_free, scale, bounds
            )
            sines.add(rows, [(joint, meas.kind) for joint, meas in row_free], values)
            i = end
            continue
        k = system.kin(trajectory.q[i], None, trajectory.time[i])
        jac = system.phi_q(k)
        if jac.shape[0] <= _BATCH_ROWS:
            batch.free = free if jac.shape[0] < system.nq else []
            batch.add(i, _unit_rows(jac * scale), _gradients(system, k, batch.free, scale))
            if len(batch.rows) >= _BATCH_SIZE:
                batch.flush(ranks, highs, sines)
        else:
            position = _Position(system, k, start, scale, free, jac)
            ranks[i], start = position.rank_measure(), position.weights
            highs[i] = ranks[i]
            row = position.sines()
            sines.add(np.array([i]), list(row), np.array([list(row.values())]).reshape(1, -1))
        i += 1
    batch.flush(ranks, highs, sines)
    system.restore_snapshot(trajectory.references[n - 1])
    return ranks, highs, sines


def _compiled_measures(
    arrays: ConstraintArrays, qs: np.ndarray, free: list, scale: np.ndarray, bounds: bool
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lows, highs, sines) of the rows at states `qs` (n, nq), in one compiled call: the
    measures `_Batch` takes of the scaled unit constraint rows and the free coordinates'
    scaled gradients, without keeping them (mechlib.kinematics.constraint_arrays.scaled_row). sines
    (n, coordinates): NaN where a coordinate has no gradient."""
    ints, floats = arrays.packed()
    angles = [m for _, m in free if isinstance(m, AngleMeasure)]
    travels = [m for _, m in free if isinstance(m, TravelMeasure)]
    measures = measure_args([m.sine_cosine for m in angles], 4) + measure_args(
        [m.distance for m in travels], 5
    )
    order = {id(m): c for c, m in enumerate([*angles, *travels])}
    n, nq = qs.shape
    work = row_work(ints, nq, len(angles), len(travels))
    lows, highs = np.empty(n), np.empty(n)
    shares, norms = np.empty((n, len(free))), np.empty((n, len(free)))
    _rows_measures(
        np.ascontiguousarray(qs), ints, floats, scale, measures, work, _GRAM_FLOOR, bounds,
        lows, highs, shares, norms,
    )  # fmt: skip
    columns = [order[id(m)] for _, m in free]
    return lows, highs, np.where(norms > 0.0, shares, np.nan)[:, columns]


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _rows_measures(
    qs, ints, floats, scale, measures, work, floor, bounds, lows, highs, shares, norms
):  # fmt: skip
    """Per state of qs: `_row_measures` of its scaled unit rows and gradients
    (mechlib.kinematics.constraint_arrays.scaled_row) into lows, highs, shares and norms."""
    ai, aj, au, av, ti, tj, tv, tsi, tsj = measures
    nq = qs.shape[1]
    m = ints[7]
    jac, grad = np.zeros((m, nq)), np.zeros((nq, norms.shape[1]))
    gram, inverse, column = np.empty((m, m)), np.empty((m, m)), np.empty((3, m))
    packed = ca.unpack(ints, floats)
    for r in range(qs.shape[0]):
        ca.scaled_row(qs[r], packed, scale, ai, aj, au, av, ti, tj, tv, tsi, tsj, work, jac, grad)
        lows[r], highs[r] = _row_measures(
            jac, grad, floor, bounds, gram, inverse, column, shares[r], norms[r]
        )


def _gradients(system: System, k, free: list, scale: np.ndarray) -> np.ndarray:
    """The free coordinates' scaled gradients at state k as columns (nq, coordinates)."""
    columns = [system.coordinate_gradient(m, k) * scale for _, m in free]
    return np.array(columns).T if columns else np.zeros((system.nq, 0))


class _Batch:
    """Rows of one active set with few equations, measured in one go: the smallest
    singular value of each scaled Jacobian from the eigenvalues of J J^T (with `bounds`:
    bounds of it, `_rank_bounds`), the sines from a solve with J J^T (the same quantities
    as `_Position`), in one compiled call."""

    def __init__(self, bounds: bool = False) -> None:
        self.bounds = bounds
        self.rows: list[int] = []
        self.jacs: list[np.ndarray] = []  # chunks (n, m, nq)
        self.grads: list[np.ndarray] = []  # chunks (n, nq, c)
        self.free: list = []

    def add(self, row: int, jac: np.ndarray, grads: np.ndarray) -> None:
        self.extend(row, jac[None], grads[None])

    def extend(self, first: int, jacs: np.ndarray, grads: np.ndarray) -> None:
        """Rows first, first + 1, ... with their jacs (n, m, nq) and grads (n, nq, c)."""
        self.rows.extend(range(first, first + len(jacs)))
        self.jacs.append(jacs)
        self.grads.append(grads)

    def flush(self, ranks: np.ndarray, highs: np.ndarray, sines: _Sines) -> None:
        """Write the measures of the rows held into `ranks` (with `bounds`: their lower
        bounds), `highs` (their upper bounds) and `sines`; empty the batch."""
        if not self.rows:
            return
        jac = np.ascontiguousarray(np.concatenate(self.jacs))  # (n, m, nq)
        grads = np.ascontiguousarray(np.concatenate(self.grads))  # (n, nq, c)
        n, c = len(self.rows), grads.shape[2]
        rank, high = np.empty(n), np.empty(n)
        shares, norms = np.empty((n, c)), np.empty((n, c))
        _batch_measures(jac, grads, _GRAM_FLOOR, self.bounds, rank, high, shares, norms)
        ranks[self.rows], highs[self.rows] = rank, high
        keys = [(joint, meas.kind) for joint, meas in self.free]
        sines.add(np.array(self.rows), keys, np.where(norms > 0.0, shares, np.nan))
        self.rows, self.jacs, self.grads = [], [], []


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _batch_measures(jacs, grads, floor, bounds, lows, highs, shares, norms):
    """`_row_measures` of each row i (its scaled Jacobian jacs[i] (m, nq), its free
    coordinates' gradient columns grads[i] (nq, c)) into lows, highs, shares and norms."""
    n, m, _ = jacs.shape
    gram, inverse, column = np.empty((m, m)), np.empty((m, m)), np.empty((3, m))
    for i in range(n):
        lows[i], highs[i] = _row_measures(
            jacs[i], grads[i], floor, bounds, gram, inverse, column, shares[i], norms[i]
        )


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _row_measures(jac, grad, floor, bounds, gram, inverse, column, shares, norms):
    """(low, high) of one row: the smallest singular value of the scaled Jacobian jac
    (m, nq) from the eigenvalues of J J^T (1 without equations) -- with `bounds`, bounds
    of it instead (`_rank_bounds`) -- and per free coordinate (gradient column of grad
    (nq, c)) its length into norms and the part of it outside the span of the rows over
    that length into shares (J J^T floored by `floor` for the solve). gram, inverse (m, m)
    and column (3, m): work arrays."""
    m, nq = jac.shape
    _column_norms(grad, norms)
    if m == 0:
        shares[:] = 1.0
        return 1.0, 1.0
    for a in range(m):
        for b in range(a + 1):
            acc = 0.0
            for j in range(nq):
                acc += jac[a, j] * jac[b, j]
            gram[a, b] = gram[b, a] = acc
    if not bounds:
        value = math.sqrt(max(np.linalg.eigvalsh(gram)[0], 0.0))
        for k in range(m):
            gram[k, k] += floor
        if grad.shape[1]:
            free = grad - jac.T @ np.linalg.solve(gram, jac @ grad)
            _shares(free, norms, shares)
        return value, value
    for k in range(m):
        gram[k, k] += floor
    if not _lower_inverse(gram, inverse):  # measured exactly by the caller
        shares[:] = 1.0
        return 0.0, 1.0
    low, high = _rank_bounds(inverse, floor, column[0], column[1])
    for c in range(grad.shape[1]):
        _outside_share(jac, grad, c, inverse, column, norms, shares)
    return low, high


@njit(cache=True, nogil=True, fastmath=_REASSOCIATE)
def _outside_share(jac, grad, c, inverse, work, norms, shares):
    """shares[c] = the length of g - J^T G^-1 J g (g = grad[:, c], G^-1 = L^-T L^-1 from
    inverse = L^-1, lower) over norms[c] (1 where that is 0); work (3, m)."""
    m, nq = jac.shape
    y, z = work[0], work[1]
    for a in range(m):  # y = L^-1 J g
        acc = 0.0
        for j in range(nq):
            acc += jac[a, j] * grad[j, c]
        work[2, a] = acc
    for a in range(m):
        acc = 0.0
        for b in range(a + 1):
            acc += inverse[a, b] * work[2, b]
        y[a] = acc
    for b in range(m):  # z = L^-T y
        acc = 0.0
        for a in range(b, m):
            acc += inverse[a, b] * y[a]
        z[b] = acc
    total = 0.0
    for j in range(nq):
        acc = grad[j, c]
        for a in range(m):
            acc -= jac[a, j] * z[a]
        total += acc * acc
    shares[c] = math.sqrt(total) / (norms[c] if norms[c] > 0.0 else 1.0)


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


@njit(**KERNEL)
def _column_norms(matrix, out):
    """out[k] = the length of matrix[:, k]."""
    for k in range(matrix.shape[1]):
        acc = 0.0
        for j in range(matrix.shape[0]):
            acc += matrix[j, k] * matrix[j, k]
        out[k] = math.sqrt(acc)


@njit(**KERNEL)
def _shares(free, norms, out):
    """out[k] = the length of free[:, k] over norms[k] (1 where that is 0)."""
    _column_norms(free, out)
    for k in range(out.shape[0]):
        out[k] /= norms[k] if norms[k] > 0.0 else 1.0


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


class _Sines:
    """The free coordinates' sines of a run's rows, by segment of rows with the same free
    coordinates: the rows, the coordinates' keys (joint, kind) and their sines (rows x
    keys; NaN where a coordinate has no gradient, or is left out). `sines[i]`: row i's
    {key: sine} (in the order of the free coordinates)."""

    def __init__(self, n: int) -> None:
        self.segments: list[tuple[np.ndarray, list, np.ndarray]] = []
        self._segment = np.full(n, -1)  # of each row (-1: none, no free coordinate)
        self._place = np.zeros(n, dtype=np.int64)  # in it

    def add(self, rows: np.ndarray, keys: list, values: np.ndarray) -> None:
        self._segment[rows] = len(self.segments)
        self._place[rows] = np.arange(len(rows))
        self.segments.append((rows, keys, values))

    def __len__(self) -> int:
        return len(self._segment)

    def __getitem__(self, i: int) -> dict:
        if self._segment[i] < 0:
            return {}
        _, keys, values = self.segments[self._segment[i]]
        row = values[self._place[i]].tolist()
        return {key: value for key, value in zip(keys, row) if not math.isnan(value)}

    def __iter__(self) -> Iterator[dict]:
        return (self[i] for i in range(len(self)))

    def relative(self) -> _Sines:
        """Each coordinate's sine over its largest in the run; sines at round-off level (a
        coordinate the motions hold through the constraints) are left out."""
        best: dict = {}
        for _, keys, values in self.segments:
            if values.size:
                tops = np.where(np.isnan(values), -np.inf, values).max(axis=0).tolist()
                for key, top in zip(keys, tops):
                    best[key] = max(best.get(key, 0.0), top)
        out = _Sines(len(self))
        out._segment, out._place = self._segment, self._place
        for rows, keys, values in self.segments:
            over = np.array([best.get(key, 0.0) for key in keys])
            with np.errstate(divide="ignore", invalid="ignore"):
                kept = np.where(values > _HELD, values / over, np.nan)
            out.segments.append((rows, keys, kept))
        return out

    def smallest(self, rank: np.ndarray) -> np.ndarray:
        """Per row: the smallest of `rank` and its sines."""
        out = np.array(rank, dtype=float)
        for rows, _, values in self.segments:
            if values.shape[1]:
                least = np.where(np.isnan(values), np.inf, values).min(axis=1)
                out[rows] = np.minimum(out[rows], least)
        return out


def _measures(ranks: np.ndarray, sines: _Sines) -> tuple[np.ndarray, np.ndarray, _Sines]:
    """Toggle measure per row: the smallest of the rank measure and the coordinates'
    sines, each over its largest in the run (so that a mechanism whose 3D Jacobian is
    weakly conditioned everywhere, or whose joints move slowly everywhere, is not taken
    for a toggle); also the relative rank measures and the coordinates' relative sines
    per row."""
    return _with_sines(ranks / max(float(ranks.max()), _GRAM_FLOOR), sines)


def _with_sines(rank: np.ndarray, sines: _Sines) -> tuple[np.ndarray, np.ndarray, _Sines]:
    """(toggle measure, rank, relative sines) per row from the relative rank measures."""
    relative = sines.relative()
    return relative.smallest(rank), rank, relative


def _bounded_measures(
    system: System, trajectory, threshold: float
) -> tuple[np.ndarray, np.ndarray, _Sines]:
    """`_measures` of the run where the rank measure's bounds show that no row's is below
    `threshold` of the largest (then each row's toggle measure below the threshold is one
    of its sines, exactly, and a row at or above it stays so); else the exact measures.
    The bounds take about a third of the eigenvalues' time (`_rank_bounds`)."""
    lows, highs, sines = _walk(system, trajectory, bounds=True)
    rank = lows / max(float(highs.max()), _GRAM_FLOOR)  # below each row's relative measure
    if np.any(rank < threshold):
        return _measures(*_series(system, trajectory))
    return _with_sines(rank, sines)


def toggle_warnings(system: System, trajectory, threshold: float = TOGGLE_THRESHOLD) -> list[str]:
    """One warning per episode of recorded rows whose toggle measure is below `threshold`:
    its time span, the minimum and its time, and the dependent equations there."""
    if not len(trajectory):
        return []
    values, rank, relative = _bounded_measures(system, trajectory, threshold)
    out = []
    for first, last in _episodes(values, threshold):
        worst = first + int(np.argmin(values[first : last + 1]))
        system.restore_snapshot(trajectory.references[worst])
        t = trajectory.time[worst]
        position = _Position(system, system.kin(trajectory.q[worst], None, t))
        found = [position.rank_deficiency()] if rank[worst] < threshold else []
        found += [
            position.dead_coordinate(*key)
            for key, value in relative[worst].items()
            if value < threshold
        ]
        out.append(
            _message(
                Toggle(float(values[worst]), tuple(found)),
                t,
                trajectory.time[first],
                trajectory.time[last],
                threshold,
            )
        )
    return out


def _message(toggle: Toggle, t: float, start: float, end: float, threshold: float) -> str:
    return (
        f"near-singular position (toggle or dead point) at t = {t:.6g} s: toggle measure "
        f"{toggle.measure:.3g} (below {threshold:g} from t = {start:.6g} to {end:.6g} s); "
        f"{toggle.describe()}; reactions there grow like 1/measure: check the geometry "
        "(a brace or link going straight) or keep the motion away from this position"
    )
