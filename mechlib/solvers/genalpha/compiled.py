"""Generalized-alpha's Newton loop and state correction as compiled kernels.

For a rigid system with no element states but the packed elements', whose active force
elements all have a compiled form (the one packer: mechlib.elements.compiled_forces:
springs, torsion springs, rotational dampers, the friction of sliding revolute and
cylindrical joints, `valve` servo-actuators with their states; or none: the bench models, a
free deployment phase), everything a Newton iteration of
`mechlib.solvers.genalpha.integrator.Integrator.step` does between two factorisations -- state
arrays, the element states' advance over the step (ElementStates.advance), constraint
residual and Jacobian (mechlib.kinematics.constraint_arrays), mass times acceleration,
gravity, velocity terms and the elements' loads, the solve with the iteration matrix's LU factors
(mechlib.linalg.flat_lu: dense or band LAPACK, or SuperLU's L and U), the correction and the
convergence test -- runs in one numba call, and so does the three-level correction of the
accepted state. Here the factorisation, the step-size control and everything else stay in
Python (mechlib.solvers.genalpha.run compiles whole runs of steps). Same equations, same order of
operations but for summation order: results equal the Python loop's to round-off
(tests/mechlib/test_genalpha_compiled.py).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from mechlib.core.jit import KERNEL, njit, on_compile
from mechlib.elements.compiled_forces import advance_states, any_elements, element_wrenches
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics import kernels as kr
from mechlib.linalg.flat_lu import lu_solve, lu_solve_into
from mechlib.solvers.genalpha import kernels as gk
from mechlib.solvers.genalpha import rules

__all__ = [
    "CONVERGED",
    "STALLED",
    "loaded_newton",
    "newton",
    "newton_loop",
    "rigid_work",
    "worked_newton",
]

CONVERGED, STALLED = 1, 2

# the Newton parts of each kind of system, by the length of its `ctx` tuple (`newton_parts`)
_PARTS: dict[int, tuple[Callable[..., None], Callable[..., None]]] = {}


def newton_parts(size: int, residual: Callable[..., None], consistent: Callable[..., None]):
    """Register the Newton parts of a kind of system whose `newton_loop` arrays `ctx` are
    tuples of `size` items: residual(ctx, q1, qd1, qdd1, lam1, res) fills res = (M qdd +
    phi_q^T lam - Q, phi of the active rows) at the iterate; consistent(ctx, q1, qd1,
    qdd1, lam1, fi, ff, out) the state's (qd, qdd, lam) on all three constraint levels
    (both kernels)."""
    assert size not in _PARTS, "one kind of system per ctx length"
    _PARTS[size] = (residual, consistent)


def system_residual(ctx, q1, qd1, qdd1, lam1, res):
    """The residual part of `ctx`'s kind of system (`newton_parts`); compiled, the choice is
    made when `newton_loop` compiles for that kind (`_bind_parts`): no call through Python."""
    _PARTS[len(ctx)][0](ctx, q1, qd1, qdd1, lam1, res)


def system_consistent(ctx, q1, qd1, qdd1, lam1, fi, ff, out):
    """The consistent-state part of `ctx`'s kind of system (`system_residual`)."""
    _PARTS[len(ctx)][1](ctx, q1, qd1, qdd1, lam1, fi, ff, out)


def _compiled(kernel):
    """A registered kernel as numba calls it (its dispatcher once compiled)."""
    return getattr(kernel, "dispatcher", None) or kernel


def _bind_parts() -> None:
    """numba's overloads of `system_residual` and `system_consistent`: the registered
    kernels of the ctx's kind, resolved by its length when a caller compiles."""
    from numba.extending import overload

    @overload(system_residual, inline="always")
    def _residual(ctx, q1, qd1, qdd1, lam1, res):
        kernel = _compiled(_PARTS[len(ctx)][0])

        def residual(ctx, q1, qd1, qdd1, lam1, res):
            kernel(ctx, q1, qd1, qdd1, lam1, res)

        return residual

    @overload(system_consistent, inline="always")
    def _consistent(ctx, q1, qd1, qdd1, lam1, fi, ff, out):
        kernel = _compiled(_PARTS[len(ctx)][1])

        def consistent(ctx, q1, qd1, qdd1, lam1, fi, ff, out):
            kernel(ctx, q1, qd1, qdd1, lam1, fi, ff, out)

        return consistent


on_compile(_bind_parts)


@njit(**KERNEL)
def _residual_work(nq):
    """Work arrays of `_dynamic_residual`: its three products (3, nq), the elements'
    forces and torques (2, nb + 1, 3)."""
    return np.empty((3, nq)), np.zeros((2, nq // 7 + 1, 3))


@njit(**KERNEL, inline="always")
def _dynamic_residual(x, xd, qdd, lam, rows, active, row_bodies, body, z, elements, work, out):
    """out[:nq] = M qdd + phi_q^T lam - Q (gravity, velocity terms and the loads of the
    packed `elements` at element states z, mechlib.elements.compiled_forces); work:
    `_residual_work`'s arrays."""
    nq = qdd.shape[0]
    nb = nq // 7
    gravity, masses, pscale, inertia = ca.body_terms(body, nb)
    products, loads = work
    m_qdd, forces, reactions = products[0], products[1], products[2]
    kr.mass_times(x, masses, inertia, pscale, qdd, m_qdd)
    if any_elements(elements):
        element_wrenches(x, xd, z, elements, rows, active, lam, loads[0], loads[1])
    kr.body_forces(x, xd, masses, inertia, gravity, loads[0], loads[1], True, forces)
    ca.transpose_times(rows, active, row_bodies, lam, reactions)
    for j in range(nq):
        out[j] = m_qdd[j] + reactions[j] - forces[j]


@njit(**KERNEL)
def newton(
    q1, qd1, qdd1, lam1, ints, floats, functions, refs, body, fi, ff, q_abs, a_ref, params,
    it, prev, eta, qdd, a, true, elements,
):  # fmt: skip
    """`loaded_newton` for a system without element states (`elements`: its packed force
    elements, mechlib.elements.compiled_forces)."""
    none = np.zeros(0)
    return loaded_newton(
        q1, qd1, qdd1, lam1, ints, floats, functions, refs, body, fi, ff, q_abs, a_ref, params,
        it, prev, eta, qdd, a, true, 0.0, none, none, none, elements,
    )  # fmt: skip


@njit(**KERNEL)
def loaded_newton(
    q1, qd1, qdd1, lam1, ints, floats, functions, refs, body, fi, ff, q_abs, a_ref, params,
    it, prev, eta, qdd, a, true, h, z0, f0, z, elements,
):  # fmt: skip
    """`newton_loop` for a rigid system: at each iterate the element states z (in place)
    advance over the step h (s) from z0 (rates f0), and the packed force elements
    (`elements`: CompiledForces.args, mechlib.elements.compiled_forces) load the bodies;
    (ints, floats): the constraints' pack (constraint_arrays), `body` the bodies' mass terms."""
    return worked_newton(
        q1, qd1, qdd1, lam1, rigid_work(ints, floats, q1.shape[0]), functions, refs, body, fi,
        ff, q_abs, a_ref, params, it, prev, eta, qdd, a, true, h, z0, f0, z, elements,
    )  # fmt: skip


@njit(**KERNEL)
def rigid_work(ints, floats, nq):
    """The arrays a rigid system's Newton iterations work in (`worked_newton`): the
    constraints' pack unpacked (ca.unpack), the residuals and Jacobian rows of all rows
    (each iteration fills its rows' blocks only), `_residual_work`'s, x and xd (nb+1, 7).
    A whole run (mechlib.solvers.genalpha.run) makes them once, not at every step."""
    nb = nq // 7
    nall = ca.row_count(ints)
    return (
        ca.unpack(ints, floats), np.empty(nall), np.empty((nall, nq + 7)), _residual_work(nq),
        np.empty((nb + 1, 7)), np.empty((nb + 1, 7)),
    )  # fmt: skip


@njit(**KERNEL)
def worked_newton(
    q1, qd1, qdd1, lam1, work, functions, refs, body, fi, ff, q_abs, a_ref, params, it, prev,
    eta, qdd, a, true, h, z0, f0, z, elements,
):  # fmt: skip
    """`loaded_newton` in the arrays `work` (`rigid_work`)."""
    packed, full, rows, residual, x, xd = work
    ctx = (packed, functions, refs, body, h, z0, f0, z, elements, full, rows, residual, x, xd)
    return newton_loop(
        ctx, q1, qd1, qdd1, lam1, fi, ff, q_abs, a_ref, params, it, prev, eta, qdd, a, true
    )


# The rigid system's parts are inlined into `newton_loop` (numba's IR inlining, as the
# overloads that choose them): a call handing on `ctx`, a tuple of about 50 arrays, by value
# cost 1.3 us of a four-bar's 4.7 us residual at every Newton iteration
# (benchmarks/kinds/fourbar_friction.py; docs/performance.md).
@njit(**KERNEL, inline="always")
def _rigid_residual(ctx, q1, qd1, qdd1, lam1, res):
    """res = (M qdd + phi_q^T lam - Q, phi) of the active rows at the iterate
    (`loaded_newton`'s ctx: its rows left for `_rigid_consistent`)."""
    packed, functions, refs, body, h, z0, f0, z, elements, full, rows, work, x, xd = ctx
    ca.state_into(q1, qd1, x, xd)
    if z.shape[0]:
        advance_states(x, xd, z0, f0, h, elements, z)
    active, row_bodies = ca.unpacked_rows(x, packed, functions, refs, full, rows)
    _dynamic_residual(x, xd, qdd1, lam1, rows, active, row_bodies, body, z, elements, work, res)
    nq = q1.shape[0]
    for i in range(active.shape[0]):
        res[nq + i] = full[active[i]]


@njit(**KERNEL, inline="always")
def _rigid_consistent(ctx, q1, qd1, qdd1, lam1, fi, ff, out):
    """`_true_acceleration` with `loaded_newton`'s ctx (its residuals' and state arrays
    worked in: the iterations that wrote them are over)."""
    packed, functions, refs, body, _, _, _, z, elements, full, rows, work, x, xd = ctx
    _true_acceleration(
        q1, qd1, qdd1, lam1, rows, packed[25], packed[26], packed, functions, refs, body, z,
        elements, work, fi, ff, out, full, x, xd,
    )  # fmt: skip


@njit(**KERNEL)
def newton_loop(
    ctx, q1, qd1, qdd1, lam1, fi, ff, q_abs, a_ref, params, it, prev, eta, qdd, a, true
):
    """Newton iterations on (q1, qd1, qdd1, lam1), in place, with fixed LU factors (fi, ff)
    from iteration `it` with the last increment size `prev` and rate estimate `eta`, as
    mechlib.solvers.genalpha.integrator.Integrator.step does them, by the same rules
    (mechlib.solvers.genalpha.rules); params: (beta', gamma', tolerance, alpha_m, alpha_f).
    The system's part is chosen by its Newton arrays `ctx` when compiled (`newton_parts`:
    the rigid system's here, the modal bodies' in mechlib.solvers.genalpha.modal_newton).
    Stops on convergence (CONVERGED: `true` then holds the state's (qd, qdd, lam) on all
    three constraint levels and the new pseudo-acceleration a from the step's start values
    (qdd, a), stacked) or when the increments stop shrinking fast enough or the iterations
    run out (STALLED: the caller refactors or gives up). Returns (status, it, prev, eta,
    iterations done)."""
    bp, gp, tol = params[0], params[1], params[2]
    nq, m = q1.shape[0], lam1.shape[0]
    res, dx = np.empty(nq + m), np.empty(nq + m)
    done = 0
    while True:
        system_residual(ctx, q1, qd1, qdd1, lam1, res)
        for j in range(nq):
            res[j] = -res[j] / bp
        for i in range(m):
            res[nq + i] = -res[nq + i]
        lu_solve_into(fi, ff, res, dx)
        gk.correct(q1, qd1, qdd1, lam1, dx, gp, bp)
        done += 1
        it += 1
        dq = dx[:nq]
        size = gk._newton_size(dq, q1, qdd1, bp, q_abs, a_ref, tol, rules.ROUNDOFF)
        eta = rules.newton_rate(size, prev, eta)
        noise = rules.is_noise(size, prev, gk.position_size(dq, q1, q_abs, tol), tol)
        if rules.converged(eta, size, noise):
            system_consistent(ctx, q1, qd1, qdd1, lam1, fi, ff, true)
            am, af = params[3], params[4]
            for j in range(nq):
                true[2 * nq + m + j] = ((1.0 - af) * qdd1[j] + af * qdd[j] - am * a[j]) / (1.0 - am)
            return CONVERGED, it, size, eta, done
        if rules.stalled(size, prev, it):
            return STALLED, it, size, eta, done
        prev = size


@njit(**KERNEL)
def level_fix(fi, ff, rhs, a, b, nq):
    """The iteration matrix's (fi, ff) correction of one constraint level: rhs's constraint
    rows set to a - b (the level's target less its product with phi_q), solved."""
    for i in range(a.shape[0]):
        rhs[nq + i] = a[i] - b[i]
    return lu_solve(fi, ff, rhs)


@njit(**KERNEL)
def stack_levels(qd, qdd1, lam1, fix, out):
    """(qd, qdd1 - fix's coordinates, lam1 - fix's multipliers) stacked into `out`."""
    nq, m = qd.shape[0], lam1.shape[0]
    out[:nq] = qd
    out[nq : 2 * nq] = qdd1 - fix[:nq]
    out[2 * nq : 2 * nq + m] = lam1 - fix[nq:]


@njit(**KERNEL)
def _true_acceleration(
    q1, qd1, qdd1, lam1, rows, active, row_bodies, packed, functions, refs, body, z, elements,
    work, fi, ff, out, full, x, xd,
):  # fmt: skip
    """(qd, qdd, lam) on all three constraint levels, stacked into `out`, by two
    corrections with the iteration matrix
    (mechlib.solvers.genalpha.integrator.Integrator._true_acceleration;
    `rows`: phi_q of the last iterate, as `constraint_rows` left them; `packed`: the
    constraints unpacked, mechlib.kinematics.constraint_arrays.unpack; work: `_residual_work`'s;
    full (the pack's rows), x, xd (nb+1, 7): work arrays, overwritten). The velocity level's
    nu reads no state; gamma is evaluated at the corrected velocity only (what
    `level_fix` and `stack_levels` do, in four arrays made here)."""
    nq, m = q1.shape[0], lam1.shape[0]
    levels = np.empty((3, m))
    nu, gamma, product = levels[0], levels[1], levels[2]
    rhs, fix, qd = np.zeros(nq + m), np.empty(nq + m), np.empty(nq)
    ca.unpacked_nu_values(packed, functions, nu)
    ca.times(rows, active, row_bodies, qd1, product)
    for i in range(m):
        rhs[nq + i] = nu[i] - product[i]
    lu_solve_into(fi, ff, rhs, fix)
    for j in range(nq):
        qd[j] = qd1[j] + fix[j]
    ca.state_into(q1, qd, x, xd)
    ca.unpacked_gamma(x, xd, packed, functions, refs, gamma, full)
    _dynamic_residual(x, xd, qdd1, lam1, rows, active, row_bodies, body, z, elements, work, rhs)
    ca.times(rows, active, row_bodies, qdd1, product)
    for i in range(m):
        rhs[nq + i] = product[i] - gamma[i]
    lu_solve_into(fi, ff, rhs, fix)
    for j in range(nq):
        out[j] = qd[j]
        out[nq + j] = qdd1[j] - fix[j]
    for i in range(m):
        out[2 * nq + i] = lam1[i] - fix[nq + i]


newton_parts(14, _rigid_residual, _rigid_consistent)  # loaded_newton's ctx
