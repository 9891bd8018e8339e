"""Where a step of Kane's spin-up beam goes (issue 40): the compiled kernels of a modal run
(mechlib.solvers.genalpha.modal_run) timed one by one in compiled loops, on the arrays of a
run of `benchmarks.flexible`'s unstiffened beam at tolerance 1e-6 (taken from its third
compiled call, about 0.1 s into the run), with the run's counts beside them.

Per call, microseconds of process CPU, best of 3 loops of `--calls` calls: a Newton
iteration's residual (with its parts: the constraint rows and welds, the modal body's
M_q qdd and Q_q), the LU solve, the consistent state's two corrections, the factorisation
with its tangent kept (M and phi_q, then LAPACK's LU and condition estimate), the motion's
callback into Python (numba's object mode and the filler). The loops compile on their first
call (about a minute). Run: `.venv/bin/python -m benchmarks.modal_kernels [--calls N]`.
"""

from __future__ import annotations

import argparse
import copy
import time
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["main"]


def _captured() -> tuple[tuple, Any]:
    """The arguments of the third `run_modal` call of Kane's beam at 1e-6 and the run's stats."""
    from benchmarks.flexible import _run
    from mechlib.solvers.genalpha import modal_run

    calls: list[tuple] = []
    kernel = modal_run.run_modal

    def kept(*args):
        if len(calls) < 3:
            calls.append(copy.deepcopy(args[:9]) + (None,) + copy.deepcopy(args[10:]))
        return kernel(*args)

    modal_run.run_modal = kept
    try:
        sol, _, _ = _run("kane_plain", 1e-6)
    finally:
        modal_run.run_modal = kernel
    return calls[-1], sol.stats


def _loops() -> dict[str, Callable[..., Any]]:
    """The timing loops, compiled with numba (after mechlib's kernels are)."""
    import numba

    from mechlib.core.jit import compile_all

    compile_all()
    from mechlib.kinematics import constraint_arrays as ca

    @numba.njit
    def newton_ctx(q1, ints, floats, functions, refs, body, bodies, welds, active):
        nq, nb = q1.shape[0], ints[0]
        packed = ca.unpack(ints, floats)
        nall = packed[25].shape[0] + welds[1]
        work = (np.empty((3, nq)), np.empty(nall), np.zeros((nb + 1, 3)), np.zeros(1))
        x, xd = np.empty((nb + 1, 7)), np.empty((nb + 1, 7))
        return (packed, functions, refs, body, bodies, welds, active, np.empty(nall),
                np.empty((nall, nq + 7)), work, x, xd)  # fmt: skip

    return {**_iteration_loops(newton_ctx), **_step_loops(newton_ctx)}


def _iteration_loops(newton_ctx) -> dict[str, Callable[..., Any]]:
    """The loops of a Newton iteration's kernels."""
    import numba

    from mechlib.kinematics import constraint_arrays as ca
    from mechlib.linalg.flat_lu import lu_solve_into
    from mechlib.solvers.genalpha import modal_newton as mn

    @numba.njit
    def residual(n, state, system, factors):
        q1, qd1, qdd1, lam1 = state
        ctx = newton_ctx(q1, *system)
        res = np.empty(q1.shape[0] + lam1.shape[0])
        for _ in range(n):
            mn._modal_residual(ctx, q1, qd1, qdd1, lam1, res)
        return res[0]

    @numba.njit
    def rows(n, state, system, factors):
        q1, qd1 = state[0], state[1]
        packed, functions, refs, _, bodies, welds, _, full, work_rows, _, x, xd = newton_ctx(
            q1, *system
        )
        nb = x.shape[0] - 1
        for _ in range(n):
            ca.state_into(q1, qd1, x, xd)
            mn.modal_rows(x, q1[7 * nb :], packed, functions, refs, bodies, welds, full, work_rows)
        return full[0]

    @numba.njit
    def modal_terms(n, state, system, factors):
        q1, qd1, qdd1, lam1 = state
        ctx = newton_ctx(q1, *system)
        x, xd, bodies, active = ctx[10], ctx[11], ctx[4], ctx[6]
        ca.state_into(q1, qd1, x, xd)
        lam_full = np.zeros(ctx[7].shape[0])
        for i in range(active.shape[0]):
            lam_full[active[i]] = lam1[i]
        gravity, m_qdd, forces = np.zeros(3), np.zeros(q1.shape[0]), np.zeros(q1.shape[0])
        for _ in range(n):
            mn._modal_terms(x, xd, q1, qd1, qdd1, lam_full, bodies, gravity, m_qdd, forces)
        return forces[0]

    @numba.njit
    def solve(n, state, system, factors):
        b = np.ones(state[0].shape[0] + state[3].shape[0])
        x = np.empty_like(b)
        for _ in range(n):
            lu_solve_into(factors[0], factors[1], b, x)
        return x[0]

    return {
        "residual (a Newton iteration)": residual,
        "  constraint rows and welds": rows,
        "  modal body's M_q qdd and Q_q": modal_terms,
        "LU solve": solve,
    }


def _step_loops(newton_ctx) -> dict[str, Callable[..., Any]]:
    """The loops of a step's kernels: the consistent state, the factorisation."""
    import numba

    from mechlib.solvers.genalpha import modal_matrix as mm
    from mechlib.solvers.genalpha import modal_newton as mn

    @numba.njit
    def consistent(n, state, system, factors):
        q1, qd1, qdd1, lam1 = state
        ctx = newton_ctx(q1, *system)
        res = np.empty(q1.shape[0] + lam1.shape[0])
        mn._modal_residual(ctx, q1, qd1, qdd1, lam1, res)  # the rows of the last iterate
        out = np.empty(3 * q1.shape[0] + lam1.shape[0])
        for _ in range(n):
            mn._modal_consistent(ctx, q1, qd1, qdd1, lam1, factors[0], factors[1], out)
        return out[0]

    @numba.njit
    def factorisation(n, state, system, factors):
        fi, ff, tangent = factors[0].copy(), factors[1].copy(), factors[2]
        lent = mn.row_arrays(state[0].shape[0], system[0], system[1], system[6])
        for _ in range(n):
            mm.factored(state[0], 1e4, 1e2, system, tangent, fi, ff, lent)
        return ff[0]

    @numba.njit
    def mass_and_phi_q(n, state, system, factors):
        q1, m = state[0], system[7].shape[0]
        ints, floats, functions, refs, body, bodies, welds, active = system
        mass, jac = np.empty((q1.shape[0], q1.shape[0])), np.empty((m, q1.shape[0]))
        for _ in range(n):
            mn.modal_matrices(
                q1, ints, floats, functions, refs, body, bodies, welds, active, mass, jac
            )
        return mass[0, 0]

    return {
        "consistent state (per step)": consistent,
        "factorisation, tangent kept": factorisation,
        "  M and phi_q": mass_and_phi_q,
    }


def _callback(calls: int, arrays_functions: Callable[[float], np.ndarray], out) -> float:
    """us per call of the motion's callback (objmode and the run's filler)."""
    import numba

    from mechlib.kinematics.time_functions import calling, functions_at

    @numba.njit
    def loop(n, handle, out):
        for i in range(n):
            functions_at(handle, 1e-3 * i, out)
        return out[0, 0]

    def fill(t: float, into: np.ndarray) -> None:
        into[:] = arrays_functions(t)

    with calling(fill) as handle:
        return _best(lambda n: loop(n, handle, out), calls)


def _bound(loop: Callable[..., Any], *args: Any) -> Callable[[int], Any]:
    """loop(n, *args) as a function of n."""
    return lambda n: loop(n, *args)


def _best(run: Callable[[int], Any], calls: int) -> float:
    run(2)
    best = np.inf
    for _ in range(3):
        start = time.process_time()
        run(calls)
        best = min(best, time.process_time() - start)
    return best / calls * 1e6


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=20000)
    args = parser.parse_args(argv)
    captured, stats = _captured()
    own, own_lam, factors, tangent = captured[0], captured[1], captured[11], captured[10]
    system = captured[8]
    state = (own[0].copy(), own[1].copy(), own[2].copy(), own_lam.copy())
    packed = (factors[0], factors[1], tangent)
    print(f"Kane's beam at 1e-6: {stats}")
    print(f"nq {own.shape[1]}, multipliers {own_lam.size}; us per call:")
    for label, loop in _loops().items():
        us = _best(_bound(loop, state, system, packed), args.calls)
        print(f"  {label:34} {us:7.2f}")
    from benchmarks.flexible import spin_up_beam
    from mechlib.flexible.packed import modal_arrays
    from mechlib.system.system import System

    arrays = modal_arrays(System(spin_up_beam(False)))
    assert arrays is not None
    us = _callback(args.calls // 4, arrays.functions, system[2].copy())
    print(f"  {'the motion callback (per attempt)':34} {us:7.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
