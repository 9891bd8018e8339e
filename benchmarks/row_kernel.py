"""The compiled dense rows alone (issue 35's campaign; mechlib.solvers.dense_compiled): the
campaign's slider-crank run with every step from Python (`StepRun` off), each step's rows
call `project_loaded_rows` (mechlib.solvers.dense.DenseRows.block); those calls are kept
and replayed, all of them `--repeat` times, the best per-row time (us, CPU of this
process) printed with the rows' count. `--save FILE` writes the rows (npz), `--compare
FILE` reads them back and prints the largest difference of each part of the rows (q, qd,
qdd, lam) against them: 0 where the kernel's results are bit-identical. `--parts`: where a
row's time goes (each part's added time, us a row, in a compiled loop over the kept rows
stopped after that part: interpolation, the constraints at the interpolated q, the position
Newton, the Schur complement's factor, the velocity, acceleration and reaction solves) and
the position Newton's steps per row with its first step's sizes (the kernel's iteration run
as Python, its inner kernels compiled).

    python -m benchmarks.row_kernel [--repeat 20] [--save rows.npz | --compare rows.npz]
                                    [--parts]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks import row_parts
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.solvers import dense
from mechlib.solvers.genalpha import run as genalpha_run

CAMPAIGN = Path(__file__).resolve().parent / "models" / "slider_crank.case.yaml"
_OUT_STATE, _OUT_Z = 12, 13  # project_loaded_rows' output arguments


def captured_calls(case_file: Path = CAMPAIGN) -> list[tuple[Any, ...]]:
    """The arguments of every `project_loaded_rows` call of the case's run with its steps
    from Python (its outputs copied: the replay writes them)."""
    calls: list[tuple[Any, ...]] = []
    kernel = dense.project_loaded_rows

    def record(*args: Any) -> Any:
        calls.append(tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args))
        return kernel(*args)

    step_run: Any = genalpha_run.StepRun
    eligible = step_run.eligible
    setattr(dense, "project_loaded_rows", record)  # noqa: B010 -- the module's name, patched
    step_run.eligible = staticmethod(lambda stepper: False)
    try:
        run_case(load_case(case_file))
    finally:
        setattr(dense, "project_loaded_rows", kernel)  # noqa: B010
        step_run.eligible = eligible
    return calls


def replay(calls: list[tuple[Any, ...]]) -> tuple[float, list[np.ndarray], int]:
    """(CPU s of this process, the rows written, the rows done) of all `calls` once."""
    kernel: Any = dense.project_loaded_rows
    outs = [(c[_OUT_STATE].copy(), c[_OUT_Z].copy()) for c in calls]
    done = 0
    started = time.process_time()
    for c, (state, z) in zip(calls, outs, strict=True):
        done += kernel(*c[:_OUT_STATE], state, z)[0]
    spent = time.process_time() - started
    return spent, [state for state, _ in outs], done


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--save", type=Path)
    parser.add_argument("--compare", type=Path)
    parser.add_argument("--parts", action="store_true")
    args = parser.parse_args(argv)
    calls = captured_calls()
    if args.parts:
        row_parts.report(calls)
    best, rows, done = min((replay(calls) for _ in range(args.repeat)), key=lambda r: r[0])
    print(f"{done} rows in {len(calls)} calls: {1e6 * best / max(done, 1):.2f} us a row (best)")
    stacked = np.concatenate(rows)
    if args.save:
        np.savez(args.save, rows=stacked)
    if args.compare:
        kept = np.load(args.compare)["rows"]
        nq = calls[0][0].shape[1]
        parts = {"q": (0, nq), "qd": (nq, 2 * nq), "qdd": (2 * nq, 3 * nq), "lam": (3 * nq, None)}
        for name, (a, b) in parts.items():
            diff = np.abs(stacked[:, a:b] - kept[:, a:b]).max()
            peak = np.abs(kept[:, a:b]).max()
            print(f"{name}: largest difference {diff:.3g} ({diff / peak:.3g} of its peak)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
