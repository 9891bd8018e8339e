"""The dense rows' one exact Newton step against the full position Newton (issue 35's
campaign; mechlib.solvers.dense_compiled._positions' `once`, `dense.ONE_STEP`): per case,
each requested column's largest difference between the run as it is and the same run
with `once` 0 (every row's Newton until a step is below the position tolerance, 1e-10),
of the request's peak |value| and of its accuracy estimate (`accuracy.estimate`,
history), the solves' Jacobian evaluations and the CPU of both `run_case`s (best of
`--repeat`, alternating, in this process).

    python -m benchmarks.row_newton [--repeat 3] [--once 1e-8] [--cases NAME ...]
                                    [-o benchmarks/results/row-newton.json]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.error_table import CHEAP, LIBRARY, LONG, _with
from benchmarks.rows import stream_rows
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from loadcases.run.global_error import request_of
from mechlib.solvers import dense

CAMPAIGN = Path(__file__).resolve().parent / "models" / "slider_crank.case.yaml"
#: name -> (case file, analysis keys changed)
CASES: dict[str, tuple[Path, dict[str, Any]]] = {
    "campaign slider-crank": (CAMPAIGN, {}),
    "pendulum 2 s": (LIBRARY / CHEAP["pendulum 2 s"][0], CHEAP["pendulum 2 s"][1]),
    "A01 10 s": (LIBRARY / CHEAP["A01 10 s"][0], {}),
    "A04": (LIBRARY / LONG["A04"][0], {}),
    "A05": (LIBRARY / CHEAP["A05"][0], {}),
    "servo closed valve": (LIBRARY / CHEAP["servo closed valve"][0], {}),
}


def _timed(case: Any, once: float) -> tuple[Any, float]:
    """The case run with the rows' `once` (0: the full Newton), its CPU (s)."""
    kept = float(dense.PROJECTION[3])
    dense.PROJECTION[3] = once  # the array the compiled runs and rows read
    try:
        started = time.process_time()
        run = run_case(case)
        return run, time.process_time() - started
    finally:
        dense.PROJECTION[3] = kept


def compare(name: str, file: Path, keys: dict[str, Any], once: float, repeat: int):
    """The rows of one case: per request, the largest difference of its columns."""
    case = load_case(file)
    case = _with(case, **keys) if keys else case
    cpu = {0.0: np.inf, once: np.inf}
    runs: dict[float, Any] = {}
    for _ in range(repeat):
        for b in (0.0, once):
            runs[b], spent = _timed(case, b)
            cpu[b] = min(cpu[b], spent)
    base, other = runs[0.0].solution, runs[once].solution
    estimate = (runs[0.0].checks.get("accuracy") or {}).get("estimate", {})
    worst: dict[str, float] = {}
    peaks: dict[str, float] = {}
    for column, values in base.channels.items():
        request = request_of(column)
        peaks[request] = max(peaks.get(request, 0.0), float(np.nanmax(np.abs(values))))
    for column, values in base.channels.items():
        request = request_of(column)
        diff = float(np.nanmax(np.abs(other.channels[column] - values)))
        worst[request] = max(worst.get(request, 0.0), diff)
    for request, diff in worst.items():
        peak = peaks[request] or 1.0
        guess = (estimate.get(request) or {}).get("history")
        yield {
            "case": name,
            "request": request,
            "once": once,
            "of_peak": diff / peak,
            "of_estimate": diff / peak / guess if guess else None,
            "estimate_history": guess,
            "rows": len(base.time),
            "cpu_full_s": cpu[0.0],
            "cpu_once_s": cpu[once],
            "jacobians_full": runs[0.0].solution.stats.jacobian_evaluations,
            "jacobians_once": runs[once].solution.stats.jacobian_evaluations,
        }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--once", type=float, default=dense.ONE_STEP)
    parser.add_argument("--cases", nargs="*", default=list(CASES))
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    rows = (
        row for name in args.cases for row in compare(name, *CASES[name], args.once, args.repeat)
    )
    stream_rows(rows, args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
