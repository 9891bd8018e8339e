"""`analysis.accuracy` on the long cases (issue 35 item 3): IFToMM A01 over 2000 s and A02
N = 40 with `{target: 1e-2, measure: histories}` (the benchmark's 0.1 m on a 1 m pendulum
is 0.1 of the peak), at the default budget unless given; the run's outcome, tightenings,
CPU, and its true error against the closed form (benchmarks/error_table_long.py).

    python -m benchmarks.accuracy_target_long [A01|A02|A02-planar ...] [--target 1e-2] [-o FILE]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from benchmarks.error_table import _with
from benchmarks.error_table_long import CASES
from benchmarks.rows import stream_rows
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from loadcases.schema.case import AccuracyTarget


def measured(name: str, target: float) -> dict:
    """One case solved to `target` (time histories), with its true errors."""
    file, analysis, exact = CASES[name]
    goal = AccuracyTarget(target=target, budget=None, measure="histories")
    started = time.process_time()
    outcome = run_case(_with(load_case(file), **analysis, accuracy=goal))
    cpu = time.process_time() - started
    run, block = outcome.solution, outcome.checks["accuracy"]
    truth = exact(run.time)
    true = {
        column: float(np.abs(run.channels[column] - values).max()) / float(np.abs(values).max())
        for column, values in truth.items()
    }
    return {
        "case": name,
        "target": target,
        "status": run.status,
        "outcome": block["outcome"],
        "tightenings": block["tightenings"],
        "tolerance": block["tolerance"],
        "steps": run.stats.steps,
        "cpu_s": cpu,
        "estimate_history": {n: e["history"] for n, e in block["estimate"].items()},
        "true_history": true,
        "load_average": os.getloadavg()[0],
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=list(CASES))
    parser.add_argument("--target", type=float, default=1e-2)
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    stream_rows((measured(name, args.target) for name in args.cases), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
