"""What a run's error estimate costs, solve by solve (issue 35): the run, its companion
(loadcases.run.companion.coarser, thinned as solve_to_accuracy thins it) and, where the run
passed a near-singular position, the finer run, each solved alone with its work counters
(accepted and rejected steps, Newton iterations, factorisations, Jacobians) and its
processor time (s). The counters are exact and repeatable; the processor time on the shared
2-core VM is not (it grows with the load: compare counters between commits, and times only
from runs measured side by side).

    python -m benchmarks.estimate_cost [CASE.yaml ...] [--end S] [-o FILE]

Default case: IFToMM A02 with N = 40, planar (benchmarks/hard), at the default tolerance.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import time
from pathlib import Path
from typing import Any

import mechlib as ml
from benchmarks.error_table import _with
from benchmarks.rows import stream_rows
from loadcases.build.model import BuiltRun, build_run
from loadcases.inputs.loader import load_case
from loadcases.run.companion import coarser, finer, passed_singular, sparser

HARD = Path(__file__).resolve().parent / "hard"
DEFAULT_CASE = HARD / "a02_n_four_bar_planar.case.yaml"


def _commit() -> str:
    """The checkout's commit (short), or '' outside a git tree."""
    root = Path(__file__).resolve().parents[1]
    done = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True
    )
    return done.stdout.strip()


def _row(case: str, which: str, built: BuiltRun, analysis: ml.Dynamic) -> tuple[dict, Any]:
    """One solve's row (its counters and processor time, s) and its solution."""
    started = time.process_time()
    solution = built.solve(analysis, checks=which != "companion")
    cpu = time.process_time() - started
    row = {
        "case": case,
        "solve": which,
        "status": solution.status,
        **solution.stats.as_dict(),
        "cpu_s": cpu,
        "commit": _commit(),
        "load_average": os.getloadavg()[0],
    }
    return row, solution


def case_rows(file: Path, end: float | None = None) -> list[dict[str, Any]]:
    """The run, its companion and (after a near-singular position) its finer run."""
    changes: dict[str, Any] = {"tolerance": None}
    if end is not None:
        changes["end"] = end
    built = build_run(_with(load_case(file), **changes))
    analysis = built.analysis
    assert isinstance(analysis, ml.Dynamic), "a dynamic case"
    row, run = _row(file.name, "run", built, analysis)
    rows = [row]
    rows.append(_row(file.name, "companion", built, sparser(coarser(analysis), run))[0])
    if passed_singular(run):
        rows.append(_row(file.name, "finer", built, finer(analysis, run.stats.steps))[0])
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", type=Path, default=[DEFAULT_CASE])
    parser.add_argument("--end", type=float, default=None, help="end time (s)")
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    stream_rows((row for file in args.cases for row in case_rows(file, args.end)), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
