"""Throughput of a large sweep (issue 17 item 4: a campaign of N variants of one mechanism).

Builds a set of N variants of the bench slider-crank (`models/slider_crank.case.yaml`, its
initial crank rate swept evenly from 1/2 to 3/2 of 2*pi rad/s), runs it with
`loads run SET --jobs J --force` in a fresh output folder (every run's CSV and summary, the
envelope, the workbook and plots, as a user gets them), and the same N runs in Exudyn with a
pool of J processes (each run solved at Exudyn's 1e-4 setting of the suite, h = 1 ms, its
channels sent back to the parent, which takes each column's max and min: no files). Prints
runs per second of both and their ratio, the CPU of each side per run (getrusage: the
`loads` command with its worker processes; the Exudyn pool with this process's share),
with the machine, the date and the load average before and after (the machine may be
shared: compare the ratio, measured side by side).

`--breakdown` (default on) times the stages of a few runs in this process: load and
validate, build, solve, accuracy companion, whole `run_case`, write; and the set's report
(a second `run_set` in this process, every run reused). `--dask` also times the same set on
a local Dask cluster of J workers (`loads run SET --scheduler local --jobs J`).
`--accuracy-off` runs the case without its error estimate (`analysis.accuracy: off`: no
companion run), as Exudyn runs. `--equal-accuracy` runs it as the suite's calibration
found it meets Exudyn's 1e-4 of range (`tolerance: 1e-4`, `output: steps`, accuracy off:
errors 9.7e-5 and 9.4e-5 in benchmarks/results/suite.json): the solvers compared
at equal accuracy, each run still written as a user gets it.

`--rounds N` runs both codes N times, the first to go alternating, and prints the median
of the rounds' ratios (the machine's phases last minutes: one pair can favour either).

    python -m benchmarks.campaign [--runs 200] [--jobs 2] [--dask] [--accuracy-off]
                                  [--equal-accuracy] [--rounds N] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "benchmarks" / "models" / "slider_crank.case.yaml"
PARAMETER = "crank_rate"
NOMINAL_RATE = 2.0 * math.pi  # rad/s, the bench model's initial crank rate
EXUDYN_STEP = 1e-3  # s: Exudyn's step at the suite's 1e-4 accuracy target (benchmarks/README.md)
SAMPLE_RUNS = 3  # runs timed stage by stage in this process
# the loads setting the suite's calibration found at Exudyn's 1e-4 of range (results/suite.json)
EQUAL_SETTING = "tolerance: 1.0e-04\n  output: steps\n"


def sweep_rates(runs: int) -> list[float]:
    """`runs` initial crank rates (rad/s), evenly from 0.5 to 1.5 times the nominal one."""
    return [float(r) for r in np.linspace(0.5 * NOMINAL_RATE, 1.5 * NOMINAL_RATE, runs)]


def write_sweep(
    folder: Path, rates: list[float], *, accuracy_off: bool = False, equal: bool = False
) -> Path:
    """The case (the bench slider-crank, its initial rate a parameter; `accuracy_off`: no
    error estimate, `analysis.accuracy: off`; `equal`: that and the suite's setting at
    Exudyn's accuracy, EQUAL_SETTING) and the set sweeping it over `rates`, written into
    `folder`; returns the set file."""
    text = CASE.read_text(encoding="utf-8")
    if equal:
        if "tolerance: 1.0e-06\n" not in text:
            raise RuntimeError(f"{CASE}: no `tolerance: 1.0e-06` to replace")
        text = text.replace("tolerance: 1.0e-06\n", EQUAL_SETTING, 1)
    if accuracy_off or equal:
        text = text.replace("analysis:\n", 'analysis:\n  accuracy: "off"\n', 1)
    given = f"pivot: {{value: 0, rate: {NOMINAL_RATE!r}}}"
    if given not in text:
        raise RuntimeError(f"{CASE}: no `{given}` to sweep (regenerated differently?)")
    text = text.replace(given, f"pivot: {{value: 0, rate: {PARAMETER}}}")
    text = text.replace("initial:", f"parameters: {{{PARAMETER}: {NOMINAL_RATE!r}}}\ninitial:", 1)
    (folder / "crank.case.yaml").write_text(text, encoding="utf-8")
    values = ", ".join(repr(rate) for rate in rates)
    set_file = folder / "campaign.set.yaml"
    set_file.write_text(
        f"set: campaign\ncases: [crank.case.yaml]\nsweep:\n  {PARAMETER}: [{values}]\n",
        encoding="utf-8",
    )
    return set_file


def _cpu_s() -> tuple[float, float]:
    """(this process's, its waited-for descendants') user + system CPU seconds so far."""
    own, children = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )
    return own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime


def _cpu_per_run(
    before: tuple[float, float], runs: int, after: tuple[float, float] | None = None
) -> dict[str, float]:
    """CPU s of this process and of its descendants from `before` to `after` (`_cpu_s`;
    default: now), and ms a run."""
    after = after or _cpu_s()
    total = (after[0] - before[0]) + (after[1] - before[1])
    return {"cpu_s": round(total, 2), "cpu_ms_per_run": round(1e3 * total / max(runs, 1), 1)}


def run_loads(set_file: Path, jobs: int, extra: list[str]) -> dict[str, Any]:
    """`loads run SET --jobs J --force` in a fresh folder: wall s, exit, runs written, solver
    CPU s summed over the summaries, CPU s of the command and its workers."""
    loads = Path(sys.executable).with_name("loads")
    out = set_file.parent / f"out-{len(extra)}-{time.monotonic_ns()}"
    command = [str(loads), "run", str(set_file), "--jobs", str(jobs), "--force", "-o", str(out)]
    cpu = _cpu_s()
    start = time.perf_counter()
    done = subprocess.run([*command, *extra], capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = _cpu_s()  # before the summaries are read: the command's CPU only
    summaries = list(out.rglob("*.summary.json"))
    solver = [json.loads(p.read_text(encoding="utf-8"))["stats"]["cpu_seconds"] for p in summaries]
    return {
        "wall_s": round(wall, 2),
        "exit": done.returncode,
        "runs": len(summaries),
        "solver_cpu_s": round(float(sum(solver)), 2),
        **_cpu_per_run(cpu, len(summaries), after),
        "output": str(out),
        "stderr_tail": done.stderr.strip().splitlines()[-3:],
    }


def _exudyn_run(rate: float) -> dict[str, tuple[float, float]]:
    """One Exudyn run of the slider-crank at initial crank rate `rate` (rad/s): each output
    column's (max, min)."""
    import dataclasses

    from benchmarks.exudyn_models import ExudynOptions, run_exudyn
    from benchmarks.models import slider_crank

    model = slider_crank()
    model = dataclasses.replace(model, initial_rate=(model.initial_rate[0], rate))
    options = ExudynOptions(step=EXUDYN_STEP, end=model.end, output_step=model.output_step)
    run = run_exudyn(model, options)
    return {c: (float(v.max()), float(v.min())) for c, v in run.channels.items()}


def run_exudyn_pool(rates: list[float], jobs: int) -> dict[str, Any]:
    """The runs in Exudyn on a pool of `jobs` processes (started inside the timing, as
    `loads` starts its workers): wall s, CPU s of this process and the pool's, and the
    envelope of the main column."""
    cpu = _cpu_s()
    start = time.perf_counter()
    with multiprocessing.get_context("spawn").Pool(jobs) as pool:
        peaks = pool.map(_exudyn_run, rates, chunksize=max(1, len(rates) // (4 * jobs)))
    wall = time.perf_counter() - start
    column = "slider_pos.x"
    return {
        "wall_s": round(wall, 2),
        "runs": len(peaks),
        **_cpu_per_run(cpu, len(peaks)),
        "envelope": {column: [max(p[column][0] for p in peaks), min(p[column][1] for p in peaks)]},
    }


def _timed(fn: Any, *args: Any, **kwargs: Any) -> tuple[Any, float]:
    start = time.perf_counter()
    result = fn(*args, **kwargs)
    return result, time.perf_counter() - start


def stage_breakdown(set_file: Path, rates: list[float], out: Path) -> dict[str, float]:
    """Wall s per stage of `SAMPLE_RUNS` runs in this process (after one unmeasured run:
    imports, compiled kernels), mean per run; and the set's report with every run reused
    (`out`: where `loads run` wrote the set)."""
    from loadcases.build.model import build_run
    from loadcases.inputs.loader import load_case
    from loadcases.results.files import write_results
    from loadcases.run import run_case
    from loadcases.run.companion import coarser, sparser
    from loadcases.sets.campaign import run_set

    case = set_file.with_name("crank.case.yaml")
    run_case(load_case(case, overrides={PARAMETER: rates[0]}))
    totals: dict[str, float] = {}
    sample = rates[:: max(1, len(rates) // SAMPLE_RUNS)][:SAMPLE_RUNS]
    for rate in sample:
        cf, t_load = _timed(load_case, case, overrides={PARAMETER: rate})
        built, t_build = _timed(build_run, cf, abscissa=True)
        solved, t_solve = _timed(built.solve)
        companion = sparser(coarser(built.analysis), solved)  # as run_case makes it
        _, t_companion = _timed(built.solve, companion, checks=False)
        outcome, t_run = _timed(run_case, cf, abscissa=True)
        _, t_write = _timed(write_results, outcome, case.parent / "stages", version="bench")
        for key, value in (
            ("load_validate", t_load),
            ("build", t_build),
            ("solve", t_solve),
            ("companion", t_companion),
            ("run_case", t_run),
            ("write", t_write),
        ):
            totals[key] = totals.get(key, 0.0) + value / len(sample)
    _, totals["set_report_all_reused"] = _timed(run_set, set_file, output_dir=out)
    return {key: round(value, 4) for key, value in totals.items()}


def _faster(ratio: float) -> str:
    """Which code ran the campaign faster, and by how much."""
    if ratio >= 1.0:
        return f"loads {ratio:.2f}x as fast"
    return f"Exudyn {1 / ratio:.2f}x as fast"


def _rate_line(label: str, result: dict[str, Any]) -> str:
    rate = result["runs"] / result["wall_s"] if result["wall_s"] else float("nan")
    return (
        f"{label}: {result['runs']} runs in {result['wall_s']:.1f} s wall = {rate:.2f} runs/s, "
        f"{result['cpu_ms_per_run']:.0f} ms of CPU a run"
    )


CODES = ("loads", "exudyn")


def _round(set_file: Path, rates: list[float], jobs: int, *, exudyn_first: bool) -> dict:
    """One round: the sweep in `loads run -j jobs` and in Exudyn's pool, one after the
    other (`exudyn_first`: Exudyn's first, so that a machine's phase does not always favour
    the same code), with their throughput ratio."""
    done: dict[str, Any] = {}
    for code in reversed(CODES) if exudyn_first else CODES:
        if code == "loads":
            done[code] = run_loads(set_file, jobs, [])
            print(_rate_line(f"loads run -j {jobs}", done[code]), flush=True)
        else:
            done[code] = run_exudyn_pool(rates, jobs)
            print(_rate_line(f"Exudyn, pool of {jobs}", done[code]), flush=True)
    loads, exudyn = done["loads"], done["exudyn"]
    ratio = exudyn["wall_s"] / loads["wall_s"] * (loads["runs"] / max(exudyn["runs"], 1))
    return {**done, "exudyn_first": exudyn_first, "throughput_ratio_loads_over_exudyn": ratio}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--dask", action="store_true", help="also on a local Dask cluster")
    parser.add_argument("--no-breakdown", action="store_true")
    parser.add_argument(
        "--accuracy-off",
        action="store_true",
        help="runs without their error estimate (analysis.accuracy: off), as Exudyn's",
    )
    parser.add_argument(
        "--equal-accuracy",
        action="store_true",
        help="loads at the suite's setting for Exudyn's accuracy (tolerance 1e-4, output "
        "steps, accuracy off)",
    )
    parser.add_argument(
        "--rounds",
        type=int,
        default=1,
        help="rounds of both codes, the first to go alternating (loads first in round 1): "
        "the ratio printed is the median of the rounds'",
    )
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    from benchmarks.suite import machine_info

    rates = sweep_rates(args.runs)
    result: dict[str, Any] = {"machine": machine_info(), "runs": args.runs, "jobs": args.jobs}
    result["accuracy_off"] = args.accuracy_off or args.equal_accuracy
    result["equal_accuracy"] = args.equal_accuracy
    result["load_before"] = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        set_file = write_sweep(
            Path(tmp), rates, accuracy_off=args.accuracy_off, equal=args.equal_accuracy
        )
        result["rounds"] = [
            _round(set_file, rates, args.jobs, exudyn_first=k % 2 == 1)
            for k in range(max(1, args.rounds))
        ]
        result["loads"], result["exudyn"] = (result["rounds"][0][key] for key in CODES)
        if args.dask:
            result["dask"] = run_loads(set_file, args.jobs, ["--scheduler", "local"])
            print(_rate_line("loads run --scheduler local", result["dask"]), flush=True)
        if not args.no_breakdown:
            result["stages_s"] = stage_breakdown(set_file, rates, Path(result["loads"]["output"]))
            print("per run, in this process (s):", result["stages_s"], flush=True)
    result["load_after"] = os.getloadavg()
    ratios = [r["throughput_ratio_loads_over_exudyn"] for r in result["rounds"]]
    ratio = float(np.median(ratios))
    result["throughput_ratio_loads_over_exudyn"] = round(ratio, 4)
    of = (
        f"median of {len(ratios)} rounds {[round(r, 3) for r in ratios]}, "
        if len(ratios) > 1
        else ""
    )
    print(
        f"throughput loads / Exudyn: {ratio:.3f} ({of}{_faster(ratio)}); load average "
        f"{result['load_before'][0]:.1f} before, {result['load_after'][0]:.1f} after (1 min)"
    )
    if args.json:
        args.json.write_text(json.dumps(result, indent=2), encoding="utf-8")
    return 0 if result["loads"]["exit"] == 0 and ratio >= 1.0 else 1


if __name__ == "__main__":
    raise SystemExit(main())
