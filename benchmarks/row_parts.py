"""Where a dense row's time goes (issue 35; `python -m benchmarks.row_kernel --parts`): the
kept `project_loaded_rows` calls (benchmarks.row_kernel.captured_calls) replayed in a
compiled loop stopped after each part of a row (mechlib.solvers.dense_compiled.
project_worked_row's own parts, in one `row_work` for all rows as the run kernel makes it),
each part's added time in us a row (best of 5); and the position Newton's steps per row
with its first step's size (the kernel's `_positions` run as Python, its inner kernels
compiled, each step counted by the solve that makes it)."""

from __future__ import annotations

import collections
import itertools
import time
from typing import Any

import numpy as np
from numba import njit

from mechlib.kinematics import constraint_arrays as ca
from mechlib.solvers import dense_compiled as dc
from mechlib.solvers import dense_states as ds

PARTS = (
    "interpolation (q, qd and element states)",
    "phi and phi_q at the interpolated q",
    "position Newton (its factor, steps, later Jacobians)",
    "Schur complement phi_q M^-1 phi_q^T and its factor",
    "velocity projection, qdd and lam (gamma, Q, two solves)",
)


def _stage_rows(reps, stage, ends, t0, t1, times, work, functions, refs, body, params, ends_z,
                elements, rows_state, rows_z):  # fmt: skip
    """`project_loaded_rows`' rows `reps` times, each stopped after part `stage` (0-4)."""
    h = t1 - t0
    packed, _, state, vectors, xs, mats, _, _, _, full, rows, _, weights = work
    q, qd, x, xd = state[0], state[1], xs[0], xs[1]
    tol, reuse, most, once = params[0], params[1], int(params[2]), params[3]
    for _ in range(reps):
        for k in range(times.shape[0]):
            t = times[k]
            w = (t - t0) / h
            s = 1.0 if abs(t - t1) <= 1e-12 * max(1.0, abs(t)) else w
            ds.hermite_states(ends_z[0], ends_z[1], ends_z[2], ends_z[3], h, w, rows_z[k])
            dc._interpolate(ends, h, s, q, qd, weights)
            if stage == 0:
                continue
            ca.state_into(q, qd, x, xd)
            ca.phi_and_jacobian_in(x, packed, functions, refs, vectors[0], mats[1], full, rows)
            if stage == 1:
                continue
            dc._positions(work, functions, refs, tol, reuse, most, once)
            if stage == 2:
                continue
            ca.state_into(q, qd, x, xd)
            dc._schur(work, body)
            if stage == 3:
                continue
            dc._dynamics(work, functions, refs, body, rows_z[k], elements, rows_state[k])


def part_times(calls: list[tuple[Any, ...]], reps: int = 20) -> list[float]:
    """Each part's added time (s a row) over the kept calls, best of 5."""
    stage_rows: Any = njit(_stage_rows)  # compiled here: the kernels it calls are by now
    first = calls[0]
    nq = first[0].shape[1]
    work = dc.row_work(first[4], first[5], first[8], nq, first[12].shape[1] - 3 * nq)
    rows = sum(c[3].shape[0] for c in calls)
    totals = []
    for stage in range(len(PARTS)):
        best = np.inf
        for _ in range(5):
            started = time.process_time()
            for c in calls:
                stage_rows(reps, stage, *c[:4], work, *c[6:12], c[12].copy(), c[13].copy())
            best = min(best, (time.process_time() - started) / (rows * reps))
        totals.append(best)
    return [totals[0]] + [b - a for a, b in itertools.pairwise(totals)]


def newton_steps(calls: list[tuple[Any, ...]]) -> tuple[collections.Counter, np.ndarray]:
    """(rows by their position Newton's steps, each row's first step's size: the largest
    coordinate change, m or Euler parameter)."""
    positions, transpose_times = dc._positions, dc._transpose_times
    row: Any = dc.project_worked_row
    as_python: Any = positions
    sizes: list[float] = []

    def counted(a, y, touched, out):  # each Newton step's q change, after its solve
        transpose_times(a, y, touched, out)
        sizes.append(float(np.abs(out).max()))

    steps: collections.Counter = collections.Counter()
    first: list[float] = []
    dc._positions = lambda *args: as_python.py_func(*args)
    dc._transpose_times = counted
    try:
        for c in calls:
            ends, t0, t1, times = c[:4]
            nq, h = ends.shape[1], t1 - t0
            work = dc.row_work(c[4], c[5], c[8], nq, c[12].shape[1] - 3 * nq)
            out, z = np.empty(c[12].shape[1]), np.empty(c[10].shape[1])
            for t in times:
                s = 1.0 if abs(t - t1) <= 1e-12 * max(1.0, abs(t)) else (t - t0) / h
                sizes.clear()
                row.py_func(ends, h, s, work, *c[6:10], z, c[11], out)
                steps[len(sizes)] += 1
                first.append(sizes[0] if sizes else np.nan)
    finally:
        dc._positions, dc._transpose_times = positions, transpose_times
    return steps, np.array(first)


def report(calls: list[tuple[Any, ...]]) -> None:
    """Print the parts' times and the Newton steps per row."""
    times = part_times(calls)
    for name, spent in zip(PARTS, times, strict=True):
        print(f"  {1e6 * spent:5.2f} us  {name}")
    print(f"  {1e6 * sum(times):5.2f} us  a row in all (no call dispatch)")
    steps, first = newton_steps(calls)
    shares = ", ".join(f"{n} step(s): {k}" for n, k in sorted(steps.items()))
    q10, q50, q90 = np.nanquantile(first, [0.1, 0.5, 0.9])
    print(f"  position Newton per row: {shares}; first step {q10:.2g} / {q50:.2g} / {q90:.2g}"
          f" (10 / 50 / 90 %), largest {np.nanmax(first):.2g}")  # fmt: skip
