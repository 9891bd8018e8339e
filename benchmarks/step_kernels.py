"""Where a compiled step of the campaign goes (issue 35; mechlib.solvers.genalpha.run): the
campaign's slider-crank solved as written (run and grid companion), each `run_steps` call
kept and replayed (`--repeat` times, the best CPU in ms), then each part of a step timed
alone in a compiled loop at the first call's state (module attributes: the kernels
compiled by the run, mechlib.core.jit) (us per call: a Newton iteration's
residual and solve, the converged step's consistent state, a refactorisation), and the
Newton iterations per attempt of the Python steps (the same iterations as the compiled
ones), split by whether the attempt factored its own iteration matrix.

    python -m benchmarks.step_kernels [--repeat 10]
"""

from __future__ import annotations

import argparse
import collections
import time
from pathlib import Path
from typing import Any

import numpy as np
from numba import njit

from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.kinematics import constraint_arrays as ca
from mechlib.linalg import flat_lu
from mechlib.solvers.genalpha import compiled as gc
from mechlib.solvers.genalpha import run as genalpha_run
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.system import saddle

CAMPAIGN = Path(__file__).resolve().parent / "models" / "slider_crank.case.yaml"
_COUNTS, _CTRL = 5, 4  # run_steps' counters and control array


def _copied(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.copy()
    if isinstance(value, tuple):
        return tuple(_copied(v) for v in value)
    return value


def captured_calls(case_file: Path = CAMPAIGN) -> list[tuple[Any, ...]]:
    """The arguments of every `run_steps` call of the case's run and companion (copies)."""
    calls: list[tuple[Any, ...]] = []
    kernel = genalpha_run.run_steps

    def record(*args: Any) -> Any:
        calls.append(_copied(args))
        return kernel(*args)

    setattr(genalpha_run, "run_steps", record)  # noqa: B010 -- the module's name, patched
    try:
        run_case(load_case(case_file))
    finally:
        setattr(genalpha_run, "run_steps", kernel)  # noqa: B010
    return calls


def replay(calls: list[tuple[Any, ...]]) -> tuple[float, int, int, int]:
    """(CPU s, step attempts, Newton iterations, refactorisations) of all calls once."""
    kernel: Any = genalpha_run.run_steps
    spent, attempts, iterations, refactored = 0.0, 0, 0, 0
    for call in calls:
        args = [_copied(a) for a in call]
        started = time.process_time()
        kernel(*args)
        spent += time.process_time() - started
        counts, before = args[_COUNTS], call[_COUNTS]
        attempts += int(counts[0] - before[0] + counts[1] - before[1])
        iterations += int(counts[2])
        refactored += int(args[_CTRL][genalpha_run.REFACTORED])
    return spent, attempts, iterations, refactored


@njit
def _residuals(n, q, qd, qdd, lam, x, xd, packed, functions, refs, full, rows, body, el, work, res):
    for _ in range(n):
        ca.state_into(q, qd, x, xd)
        active, row_bodies = ca.unpacked_rows(x, packed, functions, refs, full, rows)
        gc._dynamic_residual(
            x, xd, qdd, lam, rows, active, row_bodies, body, np.zeros(0), el, work, res
        )


@njit
def _solves(n, fi, ff, res, dx):
    for _ in range(n):
        flat_lu.lu_solve_into(fi, ff, res, dx)


@njit
def _consistent(
    n, q, qd, qdd, lam, x, xd, packed, functions, refs, full, rows, body, el, work, fi, ff, out
):  # fmt: skip
    active, row_bodies = ca.unpacked_rows(x, packed, functions, refs, full, rows)
    for _ in range(n):
        gc._true_acceleration(
            q, qd, qdd, lam, rows, active, row_bodies, packed, functions, refs, body,
            np.zeros(0), el, work, fi, ff, out, full, x, xd,
        )  # fmt: skip


@njit
def _refactors(n, x, ints, floats, functions, refs, body, prow, pcol, values, place, brow, bcol,
               fi, ff):  # fmt: skip
    for _ in range(n):
        saddle.saddle_values(x, ints, floats, functions, refs, body, prow, pcol, values)
        flat_lu.refactor(values, place, brow, bcol, fi, ff)


def _us(loop: Any, *args: Any, n: int = 20000) -> float:
    """Best of three of `loop`(n, *args), us per call."""
    loop(1, *args)
    best = float("inf")
    for _ in range(3):
        started = time.process_time()
        loop(n, *args)
        best = min(best, time.process_time() - started)
    return 1e6 * best / n


def parts(call: tuple[Any, ...]) -> dict[str, float]:
    """Each part of a step, us per call, at the state of `call` (run_steps' arguments)."""
    own, own_lam, cons, cons_lam = call[:4]
    ints, floats, functions, body, fi, ff, layout = call[8:15]
    refs, elements = call[18][call[19]], call[25]
    nq, m = own.shape[1], own_lam.shape[0]
    packed, full, rows, work, x, xd = gc.rigid_work(ints, floats, nq)
    q, qd, qdd, lam = own[0].copy(), cons[0].copy(), cons[1].copy(), cons_lam.copy()
    res, dx, out = np.full(nq + m, 1e-3), np.empty(nq + m), np.empty(3 * nq + m)
    state = (q, qd, qdd, lam, x, xd, packed, functions, refs, full, rows, body, elements, work)
    _, prow, pcol, place, brow, bcol = layout
    values = np.empty(prow.shape[0])
    refactor_args = (ints, floats, functions, refs, body, prow, pcol, values, place, brow, bcol,
                     fi.copy(), ff.copy())  # fmt: skip
    return {
        "residual (constraint rows, M qdd + phi_q^T lam - Q)": _us(_residuals, *state, res),
        "LU solve": _us(_solves, fi, ff, res, dx),
        "consistent state (two solves)": _us(_consistent, *state, fi, ff, out),
        "refactorisation (saddle values, LU)": _us(_refactors, x, *refactor_args),
    }


def newton_histogram(case_file: Path = CAMPAIGN) -> dict[str, dict[int, collections.Counter]]:
    """Newton iterations per attempt of each integrator (run, companion) of the case's
    Python steps, by the iteration matrices the attempt factored (0: the kept one)."""
    log: list[tuple[int, int, int]] = []
    made = [0]
    step, matrix = Integrator.step, Integrator._iteration_matrix

    def counted_matrix(self: Any, *args: Any, **kwargs: Any) -> Any:
        made[0] += 1
        return matrix(self, *args, **kwargs)

    def counted_step(self: Any, *args: Any, **kwargs: Any) -> Any:
        iterations, factored = self.stats.newton_iterations, made[0]
        out = step(self, *args, **kwargs)
        log.append((id(self), self.stats.newton_iterations - iterations, made[0] - factored))
        return out

    step_run: Any = genalpha_run.StepRun
    eligible = step_run.eligible
    patched: Any = Integrator
    patched.step, patched._iteration_matrix = counted_step, counted_matrix
    step_run.eligible = staticmethod(lambda stepper: False)
    try:
        run_case(load_case(case_file))
    finally:
        patched.step, patched._iteration_matrix = step, matrix
        step_run.eligible = eligible
    found: dict[str, dict[int, collections.Counter]] = {}
    for n, owner in enumerate(dict.fromkeys(e[0] for e in log)):
        name = "run" if n == 0 else f"companion {n}"
        found[name] = collections.defaultdict(collections.Counter)
        for who, iterations, factored in log:
            if who == owner:
                found[name][factored][iterations] += 1
    return found


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10)
    args = parser.parse_args(argv)
    calls = captured_calls()
    spent, attempts, iterations, refactored = min(replay(calls) for _ in range(args.repeat))
    print(
        f"run_steps: {len(calls)} calls, {1e3 * spent:.2f} ms (best of {args.repeat}), "
        f"{attempts} step attempts, {iterations} Newton iterations, {refactored} refactored"
    )
    for name, us in parts(calls[0]).items():
        print(f"  {name}: {us:.2f} us")
    for name, by_matrix in newton_histogram().items():
        for factored, counter in sorted(by_matrix.items()):
            total = sum(counter.values())
            mean = sum(k * v for k, v in counter.items()) / total
            print(
                f"{name}, {factored} matrices factored in the attempt: {total} attempts, "
                f"{mean:.2f} iterations each, {dict(sorted(counter.items()))}"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
