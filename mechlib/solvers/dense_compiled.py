"""A dense output row's projection as one compiled call (mechlib.solvers.dense.projected_row).

For a small rigid system with no active force element but packed ones (springs, torsion
springs, rotational dampers and `valve` servo-actuators with their states:
mechlib.elements.compiled_forces; no joint friction) (the slider-crank of a campaign, a
free deployment phase, a hydraulic ram), the row's interpolated (q, qd) is projected in
one numba call instead of about 0.2 ms of Python per row:

- (q, qd) from the quintic Hermite interpolant of the step's two ends (generalized-alpha)
  or as given (`s` = 1: Radau's dense output, a step's end);
- q onto phi(q, t) = 0 by minimum-norm Newton, the Jacobian kept after a step below
  `REUSE_BELOW` (mechlib.solvers.assembly.solve_positions, the same iteration and the
  same iterates); converged once a step is below that tolerance (1e-10), as the Python
  rows take it, or once an exact step is below `once` (mechlib.solvers.dense.ONE_STEP,
  1e-9: `_positions`); the row takes the Jacobian of the iterate before Newton's last
  step, evaluated with that iterate's residual, not once more at q (no residual evaluated
  at q);
- qd onto phi_q qd = nu, mass-weighted, then qdd and lam from
  [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q; gamma] (mechlib.solvers.consistent.consistent_state;
  Q with the packed elements' loads at the row's element states),
  here through the Schur complement S = phi_q M^-1 phi_q^T: M is block diagonal with
  positive definite 7 x 7 blocks (m I, and 4 G^T J G + s p p^T for the Euler parameters).

A block of rows (a step's, a whole run's) takes the constraints unpacked
(constraint_arrays.unpack), each body's J'^-1 (`inverse_inertia`) and the arrays a row
works in once for all of them (`row_work`, `project_worked_row`): a row allocates no
array.

Same equations, so the same row to Newton's last step: the Jacobian (and the
velocities, accelerations and reactions through it) is taken up to 1e-9 in q away from the
row's q. Where a matrix is not clearly well
conditioned (Cholesky pivots of S or of phi_q phi_q^T below `WELL_CONDITIONED` of the
largest: near a toggle), where Newton does not converge, or where a number is not finite,
the kernel gives up (`FALLBACK`) and the Python path takes the row: it names singular
positions and failures as before.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.compiled_forces import any_elements, element_wrenches, no_forces
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics import kernels as kr
from mechlib.solvers.dense_states import hermite_states

__all__ = [
    "DONE",
    "FALLBACK",
    "HERMITE_BASIS",
    "SCHUR_ROWS",
    "WELL_CONDITIONED",
    "interpolated",
    "inverse_inertia",
    "project_loaded_row",
    "project_loaded_rows",
    "project_row",
    "project_worked_row",
    "row_work",
    "small_enough",
]

DONE, FALLBACK = 1, 0
# a Cholesky pivot ratio (squared) above this: the solve is as good as the Python path's LU;
# below it the row goes to Python, whose checks (rcond 1e-14) decide
WELL_CONDITIONED = 1e-8
# equations up to which the dense Schur complement (m x m, m^3 / 3 per row) costs less than
# the Python row's band or sparse solves: measured on the falling chains, 40 equations
# (10 links) 2.6x faster, 60 about even to 1.2x faster, 80 (20 links) slower
SCHUR_ROWS = 64

# quintic Hermite basis on s in [0, 1], coefficients of 1, s, .., s^5: the weights of q0,
# h qd0, h^2 qdd0, q1, h qd1, h^2 qdd1
_NO_BLOCK, _NO_ACTIVE, _NO_LAM = np.zeros((0, 0)), np.zeros(0, np.int64), np.zeros(0)
HERMITE_BASIS = np.array(
    [
        [1, 0, 0, -10, 15, -6],
        [0, 1, 0, -6, 8, -3],
        [0, 0, 0.5, -1.5, 1.5, -0.5],
        [0, 0, 0, 10, -15, 6],
        [0, 0, 0, -4, 7, -3],
        [0, 0, 0, 0.5, -1, 0.5],
    ]
)


def small_enough(system) -> bool:
    """Whether the rows of `system` (its active equations) are projected here."""
    return system.active.size <= SCHUR_ROWS


@njit(**KERNEL)
def _cholesky(a):
    """(ok, L): the Cholesky factor of a (symmetric, its lower triangle read); ok when a is
    finite and positive definite with pivots not below WELL_CONDITIONED of the largest
    (`_factored`)."""
    low = np.zeros(a.shape)
    return _factored(a, low), low


@njit(**KERNEL)
def _factored(a, low):
    """Whether a (symmetric, its lower triangle read) is finite and positive definite with
    pivots not below WELL_CONDITIONED of the largest; its Cholesky factor into the lower
    triangle of `low` (n, n; the rest not written). Loops, not LAPACK: for the few tens of
    rows taken here its call costs more than the factorisation."""
    n = a.shape[0]
    for i in range(n):  # the lower triangle: all that is read
        for j in range(i + 1):
            if not np.isfinite(a[i, j]):
                return False
    largest, least = 0.0, np.inf
    for j in range(n):
        acc = a[j, j]
        for k in range(j):
            acc -= low[j, k] * low[j, k]
        if not acc > 0.0:
            return False
        pivot = np.sqrt(acc)
        low[j, j] = pivot
        largest, least = max(largest, acc), min(least, acc)
        for i in range(j + 1, n):
            acc = a[i, j]
            for k in range(j):
                acc -= low[i, k] * low[j, k]
            low[i, j] = acc / pivot
    return n == 0 or (np.isfinite(largest) and least > WELL_CONDITIONED * largest)


@njit(**KERNEL)
def _well_conditioned(a):
    """a passes `_cholesky`'s check."""
    return _cholesky(a)[0]


@njit(**KERNEL)
def _cho_solve(low, b):
    """x with L L^T x = b (`_cho_solve_into`)."""
    y, inverse = np.empty(b.shape[0]), np.empty(b.shape[0])
    _inverted_pivots(low, inverse)
    _cho_solve_into(low, inverse, b, y)
    return y


@njit(**KERNEL)
def _inverted_pivots(low, inverse):
    """inverse (n,) = 1 / L's diagonal (the lower triangle of `low`, n x n): what
    `_cho_solve_into` multiplies by."""
    for i in range(inverse.shape[0]):
        inverse[i] = 1.0 / low[i, i]


@njit(**KERNEL)
def _cho_solve_into(low, inverse, b, y):
    """y (n,) with L L^T y = b, by the two triangular substitutions (numba has no
    triangular solve; np.linalg.solve would factor the matrix again); L the lower triangle
    of `low`, `inverse` its diagonal's reciprocals (`_inverted_pivots`): each substitution
    waits on the one before, and a product ends that wait sooner than a division (0.35 ->
    0.26 us a 20-row solve; the same to a rounding)."""
    n = b.shape[0]
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= low[i, j] * y[j]
        y[i] = acc * inverse[i]
    for i in range(n - 1, -1, -1):
        acc = y[i]
        for j in range(i + 1, n):
            acc -= low[j, i] * y[j]
        y[i] = acc * inverse[i]


@njit(**KERNEL)
def _times(a, x, touched, out):
    """out (m,) = a (m, n) x (n,) in loops (numba's @ calls BLAS, which costs more than
    these few products), row i over the blocks of 7 columns of the bodies it touches
    (`touched` (m, nb): `row_work`), in order: the terms left out are zeros, so the sum
    is the full one's, bit for bit."""
    for i in range(a.shape[0]):
        acc = 0.0
        for b in range(touched.shape[1]):
            if touched[i, b]:
                for j in range(7 * b, 7 * b + 7):
                    acc += a[i, j] * x[j]
        out[i] = acc


@njit(**KERNEL)
def _transpose_times(a, y, touched, out):
    """out (n,) = a (m, n)^T y (m,) in loops over the touched blocks (`_times`)."""
    out[:] = 0.0
    for i in range(a.shape[0]):
        w = y[i]
        for b in range(touched.shape[1]):
            if touched[i, b]:
                for j in range(7 * b, 7 * b + 7):
                    out[j] += a[i, j] * w


@njit(**KERNEL)
def _lower_product(a, b, touched, out):
    """The lower triangle of a b^T (m, m) (a, b (m, n), rows over the blocks they touch:
    `_times`) into out's (the rest not written): what `_factored` reads of a symmetric
    product. Entry (i, k) sums over the blocks both rows touch, in order."""
    for i in range(a.shape[0]):
        for k in range(i + 1):
            acc = 0.0
            for c in range(touched.shape[1]):
                if touched[i, c] and touched[k, c]:
                    for j in range(7 * c, 7 * c + 7):
                        acc += a[i, j] * b[k, j]
            out[i, k] = acc


@njit(**KERNEL)
def _touched(packed, m, nb):
    """(m, nb): whether active row i's Jacobian row has a column in body b's block (the
    pack's row bodies, constraint_arrays.unpack; a row over more bodies than it records
    touches all): elsewhere its entries are zeros."""
    active, row_bodies = packed[25], packed[26]
    touched = np.zeros((m, nb), np.bool_)
    for i in range(m):
        r = active[i]
        if row_bodies[r, 0] == ca.DENSE_ROW:
            touched[i, :] = True
            continue
        for c in range(row_bodies.shape[1]):
            b = row_bodies[r, c]
            if 0 <= b < nb:
                touched[i, b] = True
    return touched


@njit(**KERNEL)
def _finite(a):
    """Every entry of the 1-d array a is finite (no temporary array, as np.isfinite's)."""
    for v in a:  # noqa: SIM110 -- numba compiles no generator in all()
        if not np.isfinite(v):
            return False
    return True


@njit(**KERNEL)
def row_work(ints, floats, body, nq, m):
    """The arrays a block of rows works in, made once for all of them (a step's rows,
    a whole run's): the constraints unpacked (constraint_arrays.unpack) and each body's
    J'^-1 (`inverse_inertia`), both constant over a run; the state (q, qd, v, step, Q,
    Q - phi_q^T lam) (6, nq); the m-vectors (phi, solve, nu, gamma, drift, rhs, lam, the
    factor's inverted pivots: `_inverted_pivots`) (8, m);
    x, xd (2, nb+1, 7); the Jacobian, that of the latest iterate and phi_q M^-1 (3, m, nq);
    the symmetric product and its Cholesky factor (2, m, m: their upper triangles stay
    zero); M^-1's blocks (nb, 7, 7); the elements' forces and torques (2, nb+1, 3); the
    constraints' residuals and rows (constraint_arrays.phi_and_jacobian_in); the bodies
    each active row touches (m, nb: `_touched`), which the products read; the Hermite
    interpolant's weights (5, 6: `_interpolate`)."""
    nb = nq // 7
    nall = ca.row_count(ints) if nq else 0  # nq = 0: no row to work in
    packed = ca.unpack(ints, floats)
    return (
        packed, inverse_inertia(body, nb), np.empty((6, nq)),
        np.empty((8, m)), np.empty((2, nb + 1, 7)), np.empty((3, m, nq)), np.zeros((2, m, m)),
        np.empty((nb, 7, 7)), np.zeros((2, nb + 1, 3)), np.empty(nall),
        np.empty((nall, 7 * (nb + 1))), _touched(packed, m, nb), np.empty((5, 6)),
    )  # fmt: skip


@njit(**KERNEL, inline="always")
def _positions(work, functions, refs, tol, reuse, most, once):
    """work's q (moved in place) onto phi = 0 by minimum-norm Newton (mechlib.solvers.
    assembly._newton with unit weights) from phi and its Jacobian at q in work's phi and
    latest-iterate Jacobian (evaluated by the caller: the first of the fresh Jacobians).
    Returns (status, fresh Jacobians: those the iteration factored); the latest-iterate
    Jacobian is then the one at the iterate before the last step (within that step of q).
    Each iterate a further step follows gets its Jacobian with its residual
    (phi_and_jacobian's phi is phi_values'): the iteration's next where the step was not
    below `reuse`, else kept for the row (the one a row evaluates besides those it factors,
    as consistent_state's). Converged once a step is below `tol`, as the Python path's rows
    take it (dense._projected reads no residual), or once an exact step (its Jacobian
    evaluated at the iterate it starts from) is below `once` (`ONE_STEP`): Newton's next
    step would be of the order of its square (about 1e-18 for `once` = 1e-9, far below
    `tol`), so the iterate after it is the converged one to that order, and evaluating
    phi and its Jacobian once more there (5.5 us) bought nothing. Either way the step
    solves phi_q step = -phi with phi_q phi_q^T's factor well conditioned (`_factored`),
    so the residual after it is of the order of |step|^2 (at most 3.3e-16 on 2000 rows of
    the campaign's slider-crank)."""
    packed, _, state, vectors, xs, mats, squares, _, _, full, rows, touched, _ = work
    q, step, phi, neg, solved = state[0], state[3], vectors[0], vectors[5], vectors[1]
    pivots = vectors[7]
    x, rates = xs[0], xs[1]  # rates: unread
    jac, at_iterate, product, low = mats[0], mats[1], squares[0], squares[1]
    nq, m = q.shape[0], phi.shape[0]
    ca.state_into(q, q, x, rates)
    fresh, have = 0, False
    for _ in range(most):
        exact = not have  # factored at the iterate this step starts from
        if not have:
            jac[:] = at_iterate
            _lower_product(jac, jac, touched, product)
            if not _factored(product, low):
                return FALLBACK, fresh
            _inverted_pivots(low, pivots)
            fresh += 1
            have = True
        if not _finite(phi):
            return FALLBACK, fresh
        for i in range(m):
            neg[i] = -phi[i]
        _cho_solve_into(low, pivots, neg, solved)
        _transpose_times(jac, solved, touched, step)
        size = 0.0
        for j in range(nq):
            q[j] += step[j]
            size = max(size, abs(step[j]))
        ca.state_into(q, q, x, rates)
        if size < tol or (exact and size < once):  # converged (the docstring)
            return DONE, fresh
        ca.phi_and_jacobian_in(x, packed, functions, refs, phi, at_iterate, full, rows)
        if size >= reuse:
            have = False
    return FALLBACK, fresh


@njit(**KERNEL)
def inverse_inertia(body, nb):
    """Each body's J'^-1 (nb, 3, 3) from `body` (ConstraintArrays.bodies: constant over a
    run, so a block of rows takes it once), or an empty array where a body's mass terms are
    not well conditioned (a body without inertia: m, the Euler parameters' scale and the
    Cholesky pivots of 4 J' not within WELL_CONDITIONED of each other)."""
    _, masses, pscale, inertia = ca.body_terms(body, nb)
    inverse = np.empty((nb, 3, 3))
    unit = np.zeros(3)
    for b in range(nb):
        ok, low = _cholesky(4.0 * inertia[b])
        if not ok:
            return np.empty((0, 3, 3))
        pivots = np.diag(low) ** 2
        largest = max(pivots.max(), masses[b], pscale[b])
        if not min(pivots.min(), masses[b], pscale[b]) > WELL_CONDITIONED * largest:
            return np.empty((0, 3, 3))
        for c in range(3):
            unit[:] = 0.0
            unit[c] = 4.0  # (4 J')^-1 4 e_c = J'^-1 e_c
            inverse[b, :, c] = _cho_solve(low, unit)
    return inverse


@njit(**KERNEL)
def _inverse_mass(x, body, inverse):
    """M^-1's diagonal blocks (nb, 7, 7) at x in closed form
    (mechlib.kinematics.kernels.inverse_mass_blocks) from each body's J'^-1 `inverse`
    (nb, 3, 3: `inverse_inertia`, well conditioned)."""
    nb = inverse.shape[0]
    _, masses, pscale, _ = ca.body_terms(body, nb)
    blocks = np.empty((nb, 7, 7))
    kr.inverse_mass_blocks(x, masses, inverse, pscale, blocks)
    return blocks


@njit(**KERNEL, inline="always")
def _schur(work, body):
    """Into work: M^-1's blocks at x (xs[0]) from each body's J'^-1 (`inverse_inertia`),
    phi_q M^-1 (m, nq, in the blocks each row touches) with the row's Jacobian (the latest
    iterate's), and the Cholesky
    factor of the Schur complement phi_q M^-1 phi_q^T; False where the complement is not
    well conditioned (`_factored`)."""
    _, inverse, _, vectors, xs, mats, squares, minv, _, _, _, touched, _ = work
    jac, weighted = mats[1], mats[2]
    m, nb = jac.shape[0], inverse.shape[0]
    _, masses, pscale, _ = ca.body_terms(body, nb)
    kr.inverse_mass_blocks(xs[0], masses, inverse, pscale, minv)
    for b in range(nb):
        o = 7 * b
        for i in range(m):
            if not touched[i, b]:  # zeros there, which no product reads
                continue
            for c in range(3):
                weighted[i, o + c] = jac[i, o + c] * minv[b, c, c]
            for c in range(3, 7):
                acc = 0.0
                for d in range(3, 7):
                    acc += jac[i, o + d] * minv[b, d, c]
                weighted[i, o + c] = acc
    _lower_product(weighted, jac, touched, squares[0])
    if not _factored(squares[0], squares[1]):
        return False
    _inverted_pivots(squares[1], vectors[7])
    return True


@njit(**KERNEL)
def interpolated(ends, h, s):
    """(q, qd) at the fraction s of a step of h (s) from the quintic Hermite interpolant
    of ends (6, nq) = (q0, qd0, qdd0, q1, qd1, qdd1) (mechlib.solvers.dense.hermite's formula);
    s = 1 gives the end's own (q1, qd1)."""
    q, qd = np.empty(ends.shape[1]), np.empty(ends.shape[1])
    _interpolate(ends, h, s, q, qd, np.empty((5, 6)))
    return q, qd


@njit(**KERNEL)
def _interpolate(ends, h, s, q, qd, weights):
    """`interpolated` into q, qd (nq,), its weights in `weights` (5, 6: the powers of s and
    their derivatives, the ends' scales, then the weights of q and of qd): no array made.
    The products in loops (0.34 -> 0.12 us a row of the campaign's slider-crank against
    numba's BLAS calls, np.dot, whose sums they round differently: up to 1.5e-13 of qd's
    peak before the projection)."""
    if s == 1.0:
        q[:] = ends[3]
        qd[:] = ends[4]
        return
    s2 = s * s
    s3, s4 = s2 * s, s2 * s2
    p, dp, scale, values, slopes = weights[0], weights[1], weights[2], weights[3], weights[4]
    p[0], p[1], p[2], p[3], p[4], p[5] = 1.0, s, s2, s3, s4, s4 * s
    dp[0], dp[1], dp[2], dp[3], dp[4], dp[5] = 0.0, 1.0, 2.0 * s, 3.0 * s2, 4.0 * s3, 5.0 * s4
    scale[0], scale[1], scale[2], scale[3], scale[4], scale[5] = 1.0, h, h * h, 1.0, h, h * h
    for k in range(6):
        value, slope = 0.0, 0.0
        for c in range(6):
            value += HERMITE_BASIS[k, c] * p[c]
            slope += HERMITE_BASIS[k, c] * dp[c]
        values[k] = value * scale[k]
        slopes[k] = slope * scale[k] / h
    for j in range(q.shape[0]):
        at, rate = 0.0, 0.0
        for k in range(6):
            at += values[k] * ends[k, j]
            rate += slopes[k] * ends[k, j]
        q[j] = at
        qd[j] = rate


@njit(**KERNEL)
def project_row(ends, h, s, ints, floats, functions, refs, body, params, out):
    """The projected row at the fraction s of a step of h (s) with ends (6, nq) (see
    `interpolated`; the module docstring for the projection); params: (position tolerance,
    Jacobian reuse step, most Newton iterations, and the exact step taken as converged:
    `_positions`' `once`, 0 or left out for none). Writes (q, qd, qdd, lam) stacked into
    `out`; returns (DONE or FALLBACK, Jacobians evaluated). No force element."""
    return project_loaded_row(
        ends, h, s, ints, floats, functions, refs, body, params, np.zeros(0), no_forces(), out
    )


@njit(**KERNEL)
def project_loaded_row(ends, h, s, ints, floats, functions, refs, body, params, z, elements, out):
    """`project_row` with the packed force elements (`elements`: CompiledForces.args,
    mechlib.elements.compiled_forces, no joint friction) at element states z (the row's,
    interpolated). The row's Jacobian is that of Newton's last iterate before its last
    step (`_positions`), within the position tolerance of q."""
    nq = ends.shape[1]
    work = row_work(ints, floats, body, nq, out.shape[0] - 3 * nq)
    return project_worked_row(ends, h, s, work, functions, refs, body, params, z, elements, out)


@njit(**KERNEL)
def project_worked_row(ends, h, s, work, functions, refs, body, params, z, elements, out):
    """`project_loaded_row` in the arrays `work` (`row_work`: the constraints unpacked,
    each body's J'^-1 and the row's arrays made once for a block of rows, 1-2 us a row
    each)."""
    packed, inverse, state, vectors, xs, mats, _, _, _, full, rows, _, weights = work
    q, qd = state[0], state[1]
    _interpolate(ends, h, s, q, qd, weights)
    nq = q.shape[0]
    nb = nq // 7
    if inverse.shape[0] != nb or not (_finite(q) and _finite(qd)):
        return FALLBACK, 0
    x, xd = xs[0], xs[1]
    ca.state_into(q, qd, x, xd)
    ca.phi_and_jacobian_in(x, packed, functions, refs, vectors[0], mats[1], full, rows)
    tol, reuse, most = params[0], params[1], int(params[2])
    once = params[3] if params.shape[0] > 3 else 0.0
    status, fresh = _positions(work, functions, refs, tol, reuse, most, once)
    if status != DONE:
        return FALLBACK, fresh
    ca.state_into(q, qd, x, xd)
    if not _schur(work, body):
        return FALLBACK, fresh
    return _dynamics(work, functions, refs, body, z, elements, out), fresh


@njit(**KERNEL, inline="always")
def _dynamics(work, functions, refs, body, z, elements, out):
    """The row at work's position q (x, xd: its state arrays, rewritten) with the
    Jacobian, M^-1 blocks, phi_q M^-1 and the Schur complement's factor there (`_schur`):
    qd onto phi_q qd = nu (mass-weighted), then qdd and lam; (q, qd, qdd, lam) stacked into
    out. DONE, or FALLBACK where a number is not finite."""
    packed, _, state, vectors, xs, mats, squares, minv, wrenches, full, _, touched, _ = work
    q, qd, v, forces, free = state[0], state[1], state[2], state[4], state[5]
    solved, nu, gamma = vectors[1], vectors[2], vectors[3]
    drift, rhs, lam, pivots = vectors[4], vectors[5], vectors[6], vectors[7]
    jac, weighted, low = mats[1], mats[2], squares[1]
    x, xd = xs[0], xs[1]
    nq, nb, m = q.shape[0], q.shape[0] // 7, jac.shape[0]
    ca.unpacked_nu_values(packed, functions, nu)
    _times(jac, qd, touched, drift)
    largest = 0.0
    for i in range(m):
        drift[i] = nu[i] - drift[i]
        largest = max(largest, abs(drift[i]))
    v[:] = qd
    if m and largest > 0.0:
        _cho_solve_into(low, pivots, drift, solved)
        _transpose_times(weighted, solved, touched, free)
        for j in range(nq):
            v[j] += free[j]
        ca.state_into(q, v, x, xd)
    ca.unpacked_gamma(x, xd, packed, functions, refs, gamma, full)  # nu is the one above
    wrench_f, wrench_n = wrenches[0], wrenches[1]  # zero without elements
    if any_elements(elements):
        element_wrenches(x, xd, z, elements, _NO_BLOCK, _NO_ACTIVE, _NO_LAM, wrench_f, wrench_n)
    gravity, masses, _, inertia = ca.body_terms(body, nb)
    kr.body_forces(x, xd, masses, inertia, gravity, wrench_f, wrench_n, True, forces)
    _times(weighted, forces, touched, rhs)
    for i in range(m):
        rhs[i] -= gamma[i]
    _cho_solve_into(low, pivots, rhs, lam)
    _transpose_times(jac, lam, touched, free)
    for j in range(nq):
        free[j] = forces[j] - free[j]
    for b in range(nb):
        o = 7 * b
        for c in range(3):
            out[2 * nq + o + c] = minv[b, c, c] * free[o + c]
        for c in range(3, 7):
            acc = 0.0
            for d in range(3, 7):
                acc += minv[b, c, d] * free[o + d]
            out[2 * nq + o + c] = acc
    out[:nq] = q
    out[nq : 2 * nq] = v
    out[3 * nq : 3 * nq + m] = lam
    for v_ in out:
        if not np.isfinite(v_):
            return FALLBACK
    return DONE


@njit(**KERNEL)
def project_loaded_rows(
    ends, t0, t1, times, ints, floats, functions, refs, body, params, ends_z, elements,
    rows_state, rows_z,
):  # fmt: skip
    """`project_loaded_row` of each time in `times` (s) within the step t0 -> t1 (s) with
    ends (6, nq), the element states from their values and rates at both ends, ends_z
    (4, nz) = (z0, f0, z1, f1), by the cubic Hermite interpolant (mechlib.solvers.
    dense_states.hermite_states), as mechlib.solvers.march records rows one by one, into
    rows_state[k] (q, qd, qdd, lam) and rows_z[k]. Returns (the rows done: the first row
    the kernel gives back stops it, the Jacobians evaluated)."""
    h = t1 - t0
    fresh = 0
    nq = ends.shape[1]
    work = row_work(ints, floats, body, nq, rows_state.shape[1] - 3 * nq)
    for k in range(times.shape[0]):
        t = times[k]
        w = (t - t0) / h
        s = 1.0 if abs(t - t1) <= 1e-12 * max(1.0, abs(t)) else w
        hermite_states(ends_z[0], ends_z[1], ends_z[2], ends_z[3], h, w, rows_z[k])
        status, more = project_worked_row(
            ends, h, s, work, functions, refs, body, params, rows_z[k], elements, rows_state[k]
        )
        fresh += more
        if status != DONE:
            return k, fresh
    return times.shape[0], fresh
