"""A dense output row's projection as one compiled call (mechlib.solvers.dense.projected_row).

For a small rigid system with no active force element but packed ones (springs, torsion
springs, rotational dampers and `valve` servo-actuators with their states:
mechlib.elements.compiled_forces; no joint friction) (the slider-crank of a campaign, a
free deployment phase, a hydraulic ram), the row's interpolated (q, qd) is projected in
one numba call instead of about 0.2 ms of Python per row:

- (q, qd) from the quintic Hermite interpolant of the step's two ends (generalized-alpha)
  or as given (`s` = 1: Radau's dense output, a step's end);
- q onto phi(q, t) = 0 by minimum-norm Newton, the Jacobian kept after a step below
  `REUSE_BELOW` (mechlib.solvers.assembly.solve_positions, the same iteration);
- qd onto phi_q qd = nu, mass-weighted, then qdd and lam from
  [[M, phi_q^T], [phi_q, 0]] [qdd; lam] = [Q; gamma] (mechlib.solvers.consistent.consistent_state;
  Q with the packed elements' loads at the row's element states),
  here through the Schur complement S = phi_q M^-1 phi_q^T: M is block diagonal with
  positive definite 7 x 7 blocks (m I, and 4 G^T J G + s p p^T for the Euler parameters).

Same equations, so the same row to round-off. Where a matrix is not clearly well
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

__all__ = [
    "DONE",
    "FALLBACK",
    "HERMITE_BASIS",
    "SCHUR_ROWS",
    "WELL_CONDITIONED",
    "interpolated",
    "project_loaded_row",
    "project_loaded_rows",
    "project_row",
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
    """(ok, L): the Cholesky factor of a (symmetric); ok when a is finite and positive
    definite with pivots not below WELL_CONDITIONED of the largest."""
    ok, low = kr.positive_cholesky(a)
    if not ok:
        return False, a
    pivots = np.diag(low) ** 2
    if pivots.shape[0] == 0:
        return True, low
    ok = np.isfinite(pivots).all() and pivots.min() > WELL_CONDITIONED * pivots.max()
    return ok, low


@njit(**KERNEL)
def _well_conditioned(a):
    """a passes `_cholesky`'s check."""
    return _cholesky(a)[0]


@njit(**KERNEL)
def _cho_solve(low, b):
    """x with L L^T x = b, by the two triangular substitutions (numba has no triangular
    solve; np.linalg.solve would factor the matrix again)."""
    n = b.shape[0]
    y = np.empty(n)
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= low[i, j] * y[j]
        y[i] = acc / low[i, i]
    for i in range(n - 1, -1, -1):
        acc = y[i]
        for j in range(i + 1, n):
            acc -= low[j, i] * y[j]
        y[i] = acc / low[i, i]
    return y


@njit(**KERNEL)
def _positions(q, ints, floats, functions, refs, tol, reuse, most):
    """q (copied, then moved) onto phi = 0 by minimum-norm Newton (mechlib.solvers.assembly._newton
    with unit weights). Returns (status, q, fresh Jacobians)."""
    nq = q.shape[0]
    nb = nq // 7
    m = ints[7]
    q = q.copy()
    x, _ = ca.state_arrays(q, q, nb)
    phi = np.empty(m)
    jac = np.empty((m, nq))
    low = np.empty((m, m))
    fresh, have = 0, False
    for _ in range(most):
        if not have:  # phi at q too: the same equations, so the same residual at the start
            ca.phi_and_jacobian(
                x, ints, floats, functions, refs, phi if fresh == 0 else np.empty(m), jac
            )
            ok, low = _cholesky(jac @ jac.T)
            if not ok:
                return FALLBACK, q, fresh
            fresh += 1
            have = True
        if not np.isfinite(phi).all():
            return FALLBACK, q, fresh
        step = jac.T @ _cho_solve(low, -phi)
        size = 0.0
        for j in range(nq):
            q[j] += step[j]
            size = max(size, abs(step[j]))
        x, _ = ca.state_arrays(q, q, nb)
        ca.phi_values(x, ints, floats, functions, refs, phi)
        if size < tol:
            worst = np.abs(phi).max() if m else 0.0
            return (DONE if worst <= 1e3 * tol else FALLBACK), q, fresh
        if size >= reuse:
            have = False
    return FALLBACK, q, fresh


@njit(**KERNEL)
def _inverse_mass(x, body, nb):
    """M^-1's diagonal blocks (nb, 7, 7) at x, or an empty array where a block is not
    well conditioned (a body without inertia)."""
    _, masses, pscale, inertia = ca.body_terms(body, nb)
    blocks = np.empty((nb, 7, 7))
    kr.mass_blocks(x, masses, inertia, pscale, blocks)
    unit = np.zeros(7)
    for b in range(nb):
        ok, low = _cholesky(blocks[b])
        if not ok:
            return np.empty((0, 7, 7))
        for c in range(7):
            unit[:] = 0.0
            unit[c] = 1.0
            blocks[b, :, c] = _cho_solve(low, unit)
    return blocks


@njit(**KERNEL)
def interpolated(ends, h, s):
    """(q, qd) at the fraction s of a step of h (s) from the quintic Hermite interpolant
    of ends (6, nq) = (q0, qd0, qdd0, q1, qd1, qdd1) (mechlib.solvers.dense.hermite's formula);
    s = 1 gives the end's own (q1, qd1)."""
    if s == 1.0:
        return ends[3].copy(), ends[4].copy()
    s2 = s * s
    s3, s4 = s2 * s, s2 * s2
    p = np.array((1.0, s, s2, s3, s4, s4 * s))
    dp = np.array((0.0, 1.0, 2.0 * s, 3.0 * s2, 4.0 * s3, 5.0 * s4))
    scale = np.array((1.0, h, h * h, 1.0, h, h * h))
    values, slopes = (HERMITE_BASIS @ p) * scale, (HERMITE_BASIS @ dp) * scale / h
    return values @ ends, slopes @ ends


@njit(**KERNEL)
def project_row(ends, h, s, ints, floats, functions, refs, body, params, out):
    """The projected row at the fraction s of a step of h (s) with ends (6, nq) (see
    `interpolated`; the module docstring for the projection); params: (position tolerance,
    Jacobian reuse step, most Newton iterations). Writes (q, qd, qdd, lam) stacked into
    `out`; returns (DONE or FALLBACK, Jacobians evaluated). No force element."""
    return project_loaded_row(
        ends, h, s, ints, floats, functions, refs, body, params, np.zeros(0), no_forces(), out
    )


@njit(**KERNEL)
def project_loaded_row(ends, h, s, ints, floats, functions, refs, body, params, z, elements, out):
    """`project_row` with the packed force elements (`elements`: CompiledForces.args,
    mechlib.elements.compiled_forces, no joint friction) at element states z (the row's,
    interpolated)."""
    q, qd = interpolated(ends, h, s)
    nq = q.shape[0]
    nb, m = nq // 7, ints[7]
    if not (np.isfinite(q).all() and np.isfinite(qd).all()):
        return FALLBACK, 0
    tol, reuse, most = params[0], params[1], int(params[2])
    status, q, fresh = _positions(q, ints, floats, functions, refs, tol, reuse, most)
    if status != DONE:
        return FALLBACK, fresh
    x, xd = ca.state_arrays(q, qd, nb)
    phi, jac = np.empty(m), np.empty((m, nq))
    ca.phi_and_jacobian(x, ints, floats, functions, refs, phi, jac)
    minv = _inverse_mass(x, body, nb)
    if minv.shape[0] != nb:
        return FALLBACK, fresh
    weighted = np.empty((m, nq))  # phi_q M^-1
    for b in range(nb):
        o = 7 * b
        weighted[:, o : o + 7] = np.ascontiguousarray(jac[:, o : o + 7]) @ minv[b]
    ok, low = _cholesky(weighted @ jac.T)  # the Schur complement phi_q M^-1 phi_q^T
    if not ok:
        return FALLBACK, fresh
    nu, gamma = np.empty(m), np.empty(m)
    ca.nu_and_gamma(x, xd, ints, floats, functions, refs, nu, gamma)
    drift = nu - jac @ qd
    v = qd.copy()
    if m and np.abs(drift).max() > 0.0:
        v += weighted.T @ _cho_solve(low, drift)
        x, xd = ca.state_arrays(q, v, nb)
        ca.nu_and_gamma(x, xd, ints, floats, functions, refs, nu, gamma)
    forces = np.empty(nq)
    wrench_f, wrench_n = np.zeros((nb + 1, 3)), np.zeros((nb + 1, 3))
    if any_elements(elements):
        element_wrenches(x, xd, z, elements, _NO_BLOCK, _NO_ACTIVE, _NO_LAM, wrench_f, wrench_n)
    gravity, masses, _, inertia = ca.body_terms(body, nb)
    kr.body_forces(x, xd, masses, inertia, gravity, wrench_f, wrench_n, True, forces)
    lam = _cho_solve(low, weighted @ forces - gamma)
    free = forces - jac.T @ lam
    for b in range(nb):
        o = 7 * b
        out[2 * nq + o : 2 * nq + o + 7] = minv[b] @ free[o : o + 7]
    out[:nq] = q
    out[nq : 2 * nq] = v
    out[3 * nq : 3 * nq + m] = lam
    for v_ in out:
        if not np.isfinite(v_):
            return FALLBACK, fresh
    return DONE, fresh


@njit(**KERNEL)
def project_loaded_rows(
    ends, t0, t1, times, ints, floats, functions, refs, body, params, z0, z1, elements,
    rows_state, rows_z,
):  # fmt: skip
    """`project_loaded_row` of each time in `times` (s) within the step t0 -> t1 (s) with
    ends (6, nq), the element states interpolated linearly from z0 (at t0) to z1 (at t1),
    as mechlib.solvers.march records rows one by one, into rows_state[k] (q, qd, qdd, lam)
    and rows_z[k]. Returns (the rows done: the first row the kernel gives back stops it,
    the Jacobians evaluated)."""
    h = t1 - t0
    fresh = 0
    for k in range(times.shape[0]):
        t = times[k]
        w = (t - t0) / h
        s = 1.0 if abs(t - t1) <= 1e-12 * max(1.0, abs(t)) else w
        for i in range(z0.shape[0]):
            rows_z[k, i] = (1.0 - w) * z0[i] + w * z1[i]
        status, more = project_loaded_row(
            ends, h, s, ints, floats, functions, refs, body, params, rows_z[k], elements,
            rows_state[k],
        )  # fmt: skip
        fresh += more
        if status != DONE:
            return k, fresh
    return times.shape[0], fresh
