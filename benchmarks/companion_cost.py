"""What the accuracy estimate costs (issue 35 item 2: at most 25 % of a run): per case, the
CPU of the run as `run_case` solves it and of its accuracy companions
(loadcases.run.companion: steps twice as long, rows thinned; `grid` on the run's own steps
two at a time, `adaptive` error-controlled), best of `--repeat`, all alternating in one
process, with each companion's cost split: the setup (the system built,
the model checked, the initial state assembled, as `mechlib.solve` does them), the same
companion with the end's row only (its steps alone: the difference is its rows), and its
steps' work (accepted and rejected steps, Newton iterations, factorisations) beside the
run's. `--profile` adds cProfile's cumulative CPU of one companion by phase.

    python -m benchmarks.companion_cost [--repeat 5] [--profile] [--case NAME ...] [-o FILE]
"""

from __future__ import annotations

import argparse
import cProfile
import dataclasses
import pstats
import time
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.rows import stream_rows
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case
from loadcases.run.companion import coarser, on_grid, sparser
from mechlib.checks.model_check import check_model
from mechlib.solvers.assembly import assemble
from mechlib.solvers.solve_copy import solve_copy
from mechlib.solvers.static_start import settle_modes
from mechlib.system.planar import make_system

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = ROOT / "loadcases" / "library" / "verification"

#: name -> (case file, analysis keys changed): the cost table of docs/performance.md
CASES: dict[str, tuple[Path, dict[str, Any]]] = {
    "bench slider-crank": (ROOT / "benchmarks" / "models" / "slider_crank.case.yaml", {}),
    "pendulum 2 s": (LIBRARY / "pendulum.case.yaml", {"end": 2.0, "step": 0.01}),
    "servo closed valve": (LIBRARY / "elements" / "servo_closed_valve.case.yaml", {}),
    "A01 10 s": (LIBRARY / "hard" / "iftomm_a01_pendulum.case.yaml", {}),
    "Andrews": (LIBRARY / "hard" / "andrews_squeezer.case.yaml", {}),
    "A04": (LIBRARY / "hard" / "iftomm_a04_bricard.case.yaml", {}),
    "A05": (LIBRARY / "hard" / "iftomm_a05_flyball.case.yaml", {}),
}

#: the companion's phases in a profile: function name -> phase
PHASES = {
    "make_system": "setup",
    "check_model": "setup",
    "_analyse": "assembly, steps and rows",
    "run_steps": "compiled runs (steps and rows)",
    "step": "Python steps",
    "upto": "Python-served rows",
    "_channels": "requests",
}


def built(name: str):
    """The case `name` built as `run_case` builds it."""
    file, keys = CASES[name]
    case_file = load_case(file)
    if keys:
        changed = case_file.case.analysis.model_copy(update=keys)
        case = case_file.case.model_copy(update={"analysis": changed})
        case_file = dataclasses.replace(case_file, case=case)
    return build_run(case_file)


def _cpu(fn: Any, *args: Any, **kwargs: Any) -> tuple[Any, float]:
    started = time.process_time()
    out = fn(*args, **kwargs)
    return out, time.process_time() - started


def _setup(run_built: Any, analysis: Any) -> None:
    """What `mechlib.solve` does before its first step: the system, its checks, the
    assembled initial state."""
    system = make_system(solve_copy(run_built.mechanism))
    check_model(system, analysis, redundant=run_built.redundant)
    assembled = assemble(system, analysis.start, run_built.initial, run_built.branches)
    settle_modes(system, assembled, analysis.start, run_built.initial)


def profile(run_built: Any, analysis: Any) -> dict[str, float]:
    """CPU s of one companion solve by phase (cumulative time of the functions in PHASES)."""
    profiler = cProfile.Profile(time.process_time)
    profiler.enable()
    run_built.solve(analysis, checks=False)
    profiler.disable()
    stats = pstats.Stats(profiler).stats  # type: ignore[attr-defined]
    out: dict[str, float] = {}
    for (file, _, function), (_, _, _, cumulative, _) in stats.items():
        phase = PHASES.get(function)
        if phase is not None and "mechlib" in file:
            out[phase] = out.get(phase, 0.0) + cumulative
    return {k: round(v, 5) for k, v in out.items()}


def work(solution: Any) -> dict[str, int]:
    """A solve's work: steps, rejected steps, Newton iterations, factorisations, rows."""
    s = solution.stats
    return {
        "steps": s.steps,
        "rejected": s.rejected_steps,
        "newton": s.newton_iterations,
        "factorizations": s.factorizations,
        "rows": len(solution.time),
    }


def companions(analysis: Any, run: Any) -> dict[str, Any]:
    """The two companions of `run` (loadcases.run.companion): on its own steps (`grid`,
    where they are known) and error-controlled (`adaptive`)."""
    out = {"adaptive": sparser(coarser(analysis), run)}
    grid = on_grid(analysis, run)
    if grid is not None:
        out["grid"] = grid
    return out


def _engine(b: Any, kinds: dict[str, Any]) -> tuple[Any, str]:
    """The companion as loadcases.run.global_error solves it, and its kind: on the run's
    steps where they are known, the adaptive one where that is not or fails."""
    if "grid" in kinds:
        solution = b.solve(kinds["grid"], checks=False)
        if solution.ok:
            return solution, "grid"
    return b.solve(kinds["adaptive"], checks=False), "adaptive"


def case_row(name: str, repeat: int, with_profile: bool) -> dict[str, Any]:
    """The run's and its companions' CPU (best of `repeat`, all alternating), each
    companion's steps alone, the setup, and the work of each."""
    b = built(name)
    run = b.solve()  # imports and compiled kernels loaded
    kinds = companions(b.analysis, run)
    alone = {k: dataclasses.replace(c, step=c.end - c.start) for k, c in kinds.items()}
    for companion in kinds.values():
        b.solve(companion, checks=False)
    best: dict[str, float] = {}
    solved: dict[str, Any] = {}

    def timed(key: str, fn: Any, *args: Any, **kwargs: Any) -> Any:
        out, cpu = _cpu(fn, *args, **kwargs)
        best[key] = min(best.get(key, np.inf), cpu)
        return out

    for _ in range(repeat):
        solved["run"] = timed("run", b.solve)
        for kind, companion in kinds.items():
            solved[kind] = timed(kind, b.solve, companion, checks=False)
            # the same steps, the end's row only
            timed(f"{kind} steps", b.solve, alone[kind], checks=False)
        timed("setup", _setup, b, kinds["adaptive"])
        # as the engine estimates: the grid companion, the adaptive one where that failed
        solved["engine"], engine = timed("engine", _engine, b, kinds)
    row: dict[str, Any] = {"case": name, **{f"{k}_ms": round(1e3 * v, 2) for k, v in best.items()}}
    for kind in (*kinds, "engine"):
        row[f"{kind} ratio"] = round(best[kind] / best["run"], 3)
    row["engine's companion"] = engine
    row.update({key: work(solution) for key, solution in solved.items()})
    if with_profile:
        row["companion_profile_s"] = {k: profile(b, c) for k, c in kinds.items()}
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--profile", action="store_true")
    parser.add_argument("--case", action="append", choices=list(CASES))
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    names = args.case or list(CASES)
    stream_rows((case_row(n, args.repeat, args.profile) for n in names), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
