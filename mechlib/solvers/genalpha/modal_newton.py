"""Generalized-alpha's Newton loop and state correction compiled for systems with modal
bodies (issue 40), as mechlib.solvers.genalpha.compiled does them for rigid systems.

What a Newton iteration of mechlib.solvers.genalpha.integrator.Integrator.step does between
two factorisations -- the constraint residual and Jacobian (the rigid rows of
mechlib.kinematics.constraint_arrays, the welds of mechlib.flexible.weld_kernels in their
place among them), M qdd (the rigid bodies' kernel and each modal body's M_q), the applied
forces (gravity, the rigid bodies' velocity terms, each modal body's Q_q with its geometric
stiffening loaded by the weld multipliers: mechlib.flexible.kernels), phi_q^T lam, the solve
with the iteration matrix's flat LU factors, the correction and the convergence test by
mechlib.solvers.genalpha.rules -- runs in one call, and so does the correction of the
accepted state on all three constraint levels. The factorisation (with the differenced
tangent) and the step-size control stay in Python (mechlib.solvers.genalpha.modal_step).
The systems served have no force elements (mechlib.flexible.packed.modal_arrays). The same
formulas, summed in another order: results equal the Python loop's to round-off
(tests/mechlib/test_modal_newton.py). Array layout: mechlib.flexible.packed.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.flexible.kernels import body_mass, coordinate_forces, coordinate_mass, load_maps
from mechlib.flexible.weld_kernels import weld_gamma, weld_jacobian, weld_phi
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics import kernels as kr
from mechlib.solvers.genalpha.compiled import (
    CONVERGED,
    STALLED,
    level_fix,
    newton_loop,
    newton_parts,
    stack_levels,
)

__all__ = [
    "CONVERGED",
    "STALLED",
    "modal_matrices",
    "modal_matrices_into",
    "modal_newton",
    "modal_rows",
    "row_arrays",
]


@njit(**KERNEL)
def modal_rows(x, z, packed, functions, refs, bodies, welds, full, rows):
    """Residuals `full` (all rows) and working Jacobian rows `rows` (all rows, 7 (nb + 1)
    + nz, zeroed here) at x (nb+1, 7) and modal coordinates z; `packed`: the rigid rows
    unpacked (constraint_arrays.unpack), `welds`: (first weld row, weld rows)."""
    (
        nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj,
        ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, _, _,
    ) = packed  # fmt: skip
    rows[:, :] = 0.0
    first = ca._full_rows(
        x, nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj, full, rows
    )
    z0 = 7 * (nb + 1)
    for body in bodies:
        ints, nodes = body[0], body[1]
        frame, offset, n, w0 = ints[0], ints[1], ints[2], ints[3]
        zeta = z[offset : offset + n]
        w1 = w0 + 6 * nodes.shape[0]
        weld_phi(x, frame, nodes, body[15], body[16], body[17], zeta, full[w0:w1])
        jac = rows[w0:w1]
        weld_jacobian(x, frame, nodes, body[15], body[16], body[17], zeta, z0 + offset, jac)
    ca._coordinate_rows(
        x, ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, functions, refs,
        first + welds[1], full, rows,
    )  # fmt: skip


@njit(**KERNEL)
def _transpose_times(rows, active, lam, nb, out):
    """out (nq,) = phi_q^T lam over the active rows (ground's columns dropped)."""
    out[:] = 0.0
    g = 7 * nb
    for i in range(active.shape[0]):
        r, weight = active[i], lam[i]
        if weight == 0.0:
            continue
        for c in range(g):
            out[c] += weight * rows[r, c]
        for c in range(g + 7, rows.shape[1]):
            out[c - 7] += weight * rows[r, c]


@njit(**KERNEL)
def _times(rows, active, v, nb, out):
    """out (m,) = phi_q v over the active rows."""
    g = 7 * nb
    for i in range(active.shape[0]):
        r = active[i]
        acc = 0.0
        for c in range(g):
            acc += rows[r, c] * v[c]
        for c in range(g + 7, rows.shape[1]):
            acc += rows[r, c] * v[c - 7]
        out[i] = acc


@njit(**KERNEL)
def _node_loads(x, zeta, lam_full, body, loads):
    """The loads (k, 6) on a stiffened modal body at its kept nodes, body axes, from the
    weld multipliers among `lam_full` (all rows) (mechlib.flexible.attached.NodeWelds)."""
    ints, nodes, phi_star, maps = body[0], body[1], body[17], body[23]
    w0 = ints[3]
    p_nodes = np.empty((nodes.shape[0], 4))
    for i in range(nodes.shape[0]):
        p_nodes[i, :] = x[nodes[i], 3:]
    load_maps(x[ints[0], 3:], p_nodes, phi_star, zeta, maps)
    for i in range(nodes.shape[0]):
        for r in range(6):
            acc = 0.0
            for c in range(6):
                acc += maps[i, r, c] * lam_full[w0 + 6 * i + c]
            loads[i, r] = acc


@njit(**KERNEL)
def _modal_terms(x, xd, q, qd, qdd, lam_full, bodies, gravity, m_qdd, forces):
    """Add each modal body's M_q qdd to m_qdd and its Q_q (gravity, elastic and damping
    forces, velocity terms, stiffening) to forces (nq,)."""
    g = 7 * (x.shape[0] - 1)
    for body in bodies:
        ints = body[0]
        frame, offset, n = ints[0], ints[1], ints[2]
        z0 = g + offset
        zeta, zeta_d = q[z0 : z0 + n], qd[z0 : z0 + n]
        force = body[21]
        loads = body[22] if ints[4] else body[24]  # no node loads: an empty array
        f0 = 7 * frame
        _mass_times(x[frame, 3:], zeta, body, qdd, f0, z0, m_qdd)
        if ints[4]:
            _node_loads(x, zeta, lam_full, body, loads)
        coordinate_forces(
            x[frame, 3:], xd[frame, 3:], zeta, zeta_d, gravity, True, body[2][0], body[3],
            body[4], body[5], body[6], body[8], body[9], body[10], body[11], body[12],
            body[13], body[14], loads, body[19], force,
        )  # fmt: skip
        for a in range(7 + n):
            forces[f0 + a if a < 7 else z0 + a - 7] += force[a]


@njit(**KERNEL)
def _mass_times(p, zeta, body, qdd, f0, z0, out):
    """out += M_q qdd over a modal body's columns (frame f0, modes z0) without forming
    M_q = T^T M_w T + (4 tr Theta / 3) p p^T (mechlib.flexible.kernels.coordinate_mass):
    M_w (body_mass) times T qdd, then T^T, and the term fixing |p|."""
    n = zeta.shape[0]
    m_w = body[18]
    body_mass(
        kr.rotation_matrix(p), zeta, body[2][0], body[3], body[4], body[5], body[6], body[7],
        body[8], body[9], body[10], m_w,
    )  # fmt: skip
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    rate = np.array([[-e1, e0, e3, -e2], [-e2, -e3, e0, e1], [-e3, e2, -e1, e0]])  # G(p)
    w, f = np.empty(6 + n), np.empty(6 + n)
    pqdd = 0.0
    for c in range(3):
        w[c] = qdd[f0 + c]
    for r in range(3):
        acc = 0.0
        for c in range(4):
            acc += rate[r, c] * qdd[f0 + 3 + c]
        w[3 + r] = 2.0 * acc
    for c in range(4):
        pqdd += p[c] * qdd[f0 + 3 + c]
    for j in range(n):
        w[6 + j] = qdd[z0 + j]
    for a in range(6 + n):
        acc = 0.0
        for b in range(6 + n):
            acc += m_w[a, b] * w[b]
        f[a] = acc
    scale = 4.0 * (m_w[3, 3] + m_w[4, 4] + m_w[5, 5]) / 3.0
    for c in range(3):
        out[f0 + c] += f[c]
    for c in range(4):
        acc = 0.0
        for r in range(3):
            acc += rate[r, c] * f[3 + r]
        out[f0 + 3 + c] += 2.0 * acc + scale * p[c] * pqdd
    for j in range(n):
        out[z0 + j] += f[6 + j]


@njit(**KERNEL)
def _residual(x, xd, q, qd, qdd, lam, rows, active, body, bodies, work, out):
    """out[:nq] = M qdd + phi_q^T lam - Q at (q, qd) (x, xd its rigid rows); work: (3, nq)
    products, the multipliers over all rows, the rigid bodies' (zero) loads."""
    nq = qdd.shape[0]
    nb = x.shape[0] - 1
    g = 7 * nb
    gravity, masses, pscale, inertia = ca.body_terms(body, nb)
    products, lam_full, no_loads = work[0], work[1], work[2]
    m_qdd, forces, reactions = products[0], products[1], products[2]
    kr.mass_times(x, masses, inertia, pscale, qdd, m_qdd)
    kr.body_forces(x, xd, masses, inertia, gravity, no_loads, no_loads, True, forces)
    m_qdd[g:] = 0.0
    forces[g:] = 0.0
    lam_full[:] = 0.0
    for i in range(active.shape[0]):
        lam_full[active[i]] = lam[i]
    _modal_terms(x, xd, q, qd, qdd, lam_full, bodies, gravity, m_qdd, forces)
    _transpose_times(rows, active, lam, nb, reactions)
    for j in range(nq):
        out[j] = m_qdd[j] + reactions[j] - forces[j]


@njit(**KERNEL)
def _nu_and_gamma(x, xd, q, qd, packed, functions, refs, bodies, welds, active, nu, gamma):
    """The right sides of phi_q qd = nu and phi_q qdd = gamma of the active rows: the rigid
    rows' (constraint_arrays) and the welds' (weld_gamma; nu = 0: the welds do not move)."""
    nr = packed[25].shape[0]  # the rigid rows, all active in their pack
    nu_r, gamma_r = np.empty(nr), np.empty(nr)
    ca.unpacked_nu_and_gamma(x, xd, packed, functions, refs, nu_r, gamma_r)
    first, nw = welds[0], welds[1]
    full_nu, full_g = np.zeros(nr + nw), np.zeros(nr + nw)
    for r in range(nr):
        s = r if r < first else r + nw
        full_nu[s], full_g[s] = nu_r[r], gamma_r[r]
    g = 7 * (x.shape[0] - 1)
    for body in bodies:
        ints, nodes = body[0], body[1]
        frame, offset, n, w0 = ints[0], ints[1], ints[2], ints[3]
        zeta, zeta_d = q[g + offset : g + offset + n], qd[g + offset : g + offset + n]
        w1 = w0 + 6 * nodes.shape[0]
        weld_gamma(
            x, xd, frame, nodes, body[15], body[16], body[17], zeta, zeta_d, full_g[w0:w1]
        )  # fmt: skip
    for i in range(active.shape[0]):
        nu[i], gamma[i] = full_nu[active[i]], full_g[active[i]]


@njit(**KERNEL)
def _modal_nu(packed, functions, welds, active, nu):
    """nu (m,) of the active rows: `_nu_and_gamma`'s nu without its gamma (the coordinate
    rows' rates of their time functions, zero elsewhere: the welds do not move)."""
    nr = packed[25].shape[0]
    nu_r = np.empty(nr)
    ca.unpacked_nu_values(packed, functions, nu_r)
    first, nw = welds[0], welds[1]
    full_nu = np.zeros(nr + nw)
    for r in range(nr):
        full_nu[r if r < first else r + nw] = nu_r[r]
    for i in range(active.shape[0]):
        nu[i] = full_nu[active[i]]


@njit(**KERNEL)
def modal_newton(
    q1, qd1, qdd1, lam1, ints, floats, functions, refs, body, bodies, welds, active, fi, ff,
    q_abs, a_ref, params, it, prev, eta, qdd, a, true, lent,
):  # fmt: skip
    """mechlib.solvers.genalpha.compiled.newton_loop (its arguments, rules and returns) for a
    system with modal bodies: (ints, floats) the rigid rows' pack, `body` the rigid bodies'
    mass terms (ConstraintArrays.bodies), `bodies`, `welds`, `active`:
    mechlib.flexible.packed.ModalArrays'; `lent`: `row_arrays`' (the rows at q1 already
    there when its flag says so: the factorisation's at this q1)."""
    nq = q1.shape[0]
    nb = ints[0]
    packed = ca.unpack(ints, floats)
    full, rows, fresh = lent
    work = (np.empty((3, nq)), np.empty(full.shape[0]), np.zeros((nb + 1, 3)), fresh)
    x, xd = np.empty((nb + 1, 7)), np.empty((nb + 1, 7))
    ctx = (packed, functions, refs, body, bodies, welds, active, full, rows, work, x, xd)
    return newton_loop(
        ctx, q1, qd1, qdd1, lam1, fi, ff, q_abs, a_ref, params, it, prev, eta, qdd, a, true
    )


@njit(**KERNEL)
def _modal_residual(ctx, q1, qd1, qdd1, lam1, res):
    """res = (M qdd + phi_q^T lam - Q, phi) of the active rows at the iterate
    (`modal_newton`'s ctx: its rows left for `_modal_consistent`). The rows are taken as
    they are where work[3]'s flag says the factorisation just made them at this q1 (the
    same values: they depend on q1 and the functions only), and the flag cleared."""
    packed, functions, refs, body, bodies, welds, active, full, rows, work, x, xd = ctx
    nq, nb = q1.shape[0], x.shape[0] - 1
    ca.state_into(q1, qd1, x, xd)
    fresh = work[3]
    if fresh[0] != 0.0:
        fresh[0] = 0.0
    else:
        modal_rows(x, q1[7 * nb :], packed, functions, refs, bodies, welds, full, rows)
    _residual(x, xd, q1, qd1, qdd1, lam1, rows, active, body, bodies, work, res)
    for i in range(active.shape[0]):
        res[nq + i] = full[active[i]]


@njit(**KERNEL)
def _modal_consistent(ctx, q1, qd1, qdd1, lam1, fi, ff, out):
    """`_true_acceleration` with `modal_newton`'s ctx."""
    packed, functions, refs, body, bodies, welds, active, _, rows, work, _, _ = ctx
    _true_acceleration(
        q1, qd1, qdd1, lam1, rows, active, packed, functions, refs, body, bodies, welds, work,
        fi, ff, out,
    )  # fmt: skip


@njit(**KERNEL)
def _true_acceleration(
    q1, qd1, qdd1, lam1, rows, active, packed, functions, refs, body, bodies, welds, work,
    fi, ff, out,
):  # fmt: skip
    """(qd, qdd, lam) on all three constraint levels into `out`, by two corrections with
    the iteration matrix (Integrator._true_acceleration; `rows`: phi_q of the last
    iterate)."""
    nq, m = q1.shape[0], lam1.shape[0]
    nb = packed[0]
    nu, gamma, product = np.empty(m), np.empty(m), np.empty(m)
    _modal_nu(packed, functions, welds, active, nu)
    rhs = np.zeros(nq + m)
    _times(rows, active, qd1, nb, product)
    qd = qd1 + level_fix(fi, ff, rhs, nu, product, nq)[:nq]
    x, xd = ca.state_arrays(q1, qd, nb)
    _nu_and_gamma(x, xd, q1, qd, packed, functions, refs, bodies, welds, active, nu, gamma)
    _residual(x, xd, q1, qd, qdd1, lam1, rows, active, body, bodies, work, rhs)
    _times(rows, active, qdd1, nb, product)
    stack_levels(qd, qdd1, lam1, level_fix(fi, ff, rhs, product, gamma, nq), out)


@njit(**KERNEL)
def row_arrays(nq, ints, floats, welds):
    """(residuals (all rows), Jacobian rows (all rows, nq + 7), flag (1,) = 0): the rows
    `modal_matrices_into` leaves for `modal_newton`'s first residual (flag 1: made at its q1)."""
    nall = ca.unpack(ints, floats)[25].shape[0] + welds[1]
    return np.empty(nall), np.empty((nall, nq + 7)), np.zeros(1)


@njit(**KERNEL)
def modal_matrices(q, ints, floats, functions, refs, body, bodies, welds, active, mass, jac):
    """M (nq, nq) and phi_q (m, nq) of the active rows at q, into `mass` and `jac` (what
    System.mass and System.phi_q give, for the iteration matrix's factorisation)."""
    full, rows, _ = row_arrays(q.shape[0], ints, floats, welds)
    modal_matrices_into(
        q, ints, floats, functions, refs, body, bodies, welds, active, mass, jac, full, rows
    )  # fmt: skip


@njit(**KERNEL)
def modal_matrices_into(
    q, ints, floats, functions, refs, body, bodies, welds, active, mass, jac, full, rows
):  # fmt: skip
    """`modal_matrices` with the rows at q (`modal_rows`) left in `full` and `rows`."""
    nq = q.shape[0]
    packed = ca.unpack(ints, floats)
    nb = packed[0]
    g = 7 * nb
    x, _ = ca.state_arrays(q, q, nb)
    modal_rows(x, q[g:], packed, functions, refs, bodies, welds, full, rows)
    for i in range(active.shape[0]):
        r = active[i]
        for c in range(g):
            jac[i, c] = rows[r, c]
        for c in range(g + 7, nq + 7):
            jac[i, c - 7] = rows[r, c]
    _, masses, pscale, inertia = ca.body_terms(body, nb)
    mass[:, :] = 0.0
    kr.mass_matrix(x, masses, inertia, pscale, mass)
    for item in bodies:
        frame, offset, n = item[0][0], item[0][1], item[0][2]
        block = item[20]
        coordinate_mass(
            x[frame, 3:], q[g + offset : g + offset + n], item[2][0], item[3], item[4],
            item[5], item[6], item[7], item[8], item[9], item[10], item[18], block,
        )  # fmt: skip
        f0, z0 = 7 * frame, g + offset
        for a in range(7 + n):
            row = f0 + a if a < 7 else z0 + a - 7
            for b in range(7 + n):
                mass[row, f0 + b if b < 7 else z0 + b - 7] += block[a, b]


newton_parts(12, _modal_residual, _modal_consistent)  # modal_newton's ctx
