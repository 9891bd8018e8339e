"""What a dynamic run's error estimate adds to the run as written (issue 35 item 2: at most
25 % of a run): the same work with `analysis.accuracy` as written and with `accuracy: off`,
alternated.

- The campaign (`benchmarks.campaign`'s set of N variants of the bench slider-crank, every
  file written as a user gets them): `loads run SET -j J --force` as written and without
  the estimate, `--rounds` times each, the first to go alternating; CPU a run of the
  command and its workers (getrusage), and the estimate's share, (as written - off) / off,
  per round and their median (`--rounds 0`: not run).
- `--cases`: per case of the companion cost table (benchmarks.companion_cost.CASES),
  `run_case` in this process as written and with accuracy off, alternated `--repeat`
  times, best CPU of each: the whole run (validation aside) with its rows, requests and
  checks, which `companion_cost` leaves out of its companion / solve ratio; and as
  written without the companion's rows about the run's crests (what they cost).
- `--command`: per case of the cost table, `loads run CASE` as a user runs one case (a
  fresh process: start-up, validation, the solve, its files), as written and with
  accuracy off, alternated `--repeat` times, the median CPU (the command's) and wall time;
  `--long` adds IFToMM A01 over 2000 s (200 001 rows) and A05 over 50 s;
  `--command-beside 1` (or 0) has the command solve the companion beside the run (after
  it) whatever the machine's load (LOADS_COMPANION_BESIDE).
- `--beside`: per case of the cost table and the long ones, `run_case` in this process
  with the companion after the run, beside it (loads run's default on two cores:
  loadcases.run.beside) and with accuracy off, alternated `--repeat` times: the best wall
  time and process CPU of each, whether the companion followed the run, and whether the
  two estimates are the same to the last bit.

CPU times on a shared machine move with its load: compare the two columns of one run.

    python -m benchmarks.estimate_overhead [--runs 200] [--jobs 2] [--rounds 3] [--cases]
                                           [--command [--long] [--command-beside 0|1]]
                                           [--beside] [--repeat 5] [--json FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml

from benchmarks.campaign import run_loads, sweep_rates, write_sweep
from benchmarks.companion_cost import CASES, LIBRARY
from loadcases.run.beside import ENVIRONMENT

#: `--long`: a long run for `--command` (the error table's A01: benchmarks.error_table_long)
LONG = {
    "A01 2000 s": (LIBRARY / "hard" / "iftomm_a01_pendulum.case.yaml", {"end": 2000.0}),
    "A05 50 s": (LIBRARY / "hard" / "iftomm_a05_flyball.case.yaml", {"end": 50.0}),
}

__all__ = [
    "beside_overhead",
    "campaign_overhead",
    "case_overhead",
    "command_overhead",
    "main",
    "variants",
]


def campaign_overhead(runs: int, jobs: int, rounds: int) -> dict[str, Any]:
    """The campaign set as written and with accuracy off, `rounds` pairs alternating which
    goes first: CPU ms a run of each and the estimate's share of the run, per round."""
    rates = sweep_rates(runs)
    out: list[dict[str, float]] = []
    with tempfile.TemporaryDirectory() as tmp:
        sets = {}
        for kind, off in (("as_written", False), ("off", True)):
            folder = Path(tmp) / kind
            folder.mkdir()
            sets[kind] = write_sweep(folder, rates, accuracy_off=off)
        for k in range(max(1, rounds)):
            order = ("as_written", "off") if k % 2 == 0 else ("off", "as_written")
            done = {kind: run_loads(sets[kind], jobs, []) for kind in order}
            for kind, result in done.items():
                if result["exit"] != 0 or result["runs"] != runs:
                    raise RuntimeError(f"{kind}: {result['stderr_tail']}")
            on, off = (done[kind]["cpu_s"] * 1e3 / runs for kind in ("as_written", "off"))
            row = {"as_written_ms": round(on, 2), "off_ms": round(off, 2)}
            row["overhead"] = round(on / off - 1.0, 4)
            out.append(row)
            print(
                f"round {k + 1}: {on:.1f} ms of CPU a run as written, {off:.1f} off: "
                f"the estimate {row['overhead']:.1%} of a run",
                flush=True,
            )
    return {"rounds": out, "overhead": statistics.median(r["overhead"] for r in out)}


def variants(name: str) -> dict[str, Any]:
    """A cost-table case loaded with its analysis keys (benchmarks.companion_cost.CASES):
    `as_written` and `off` (`analysis.accuracy: off`)."""
    from loadcases.inputs.loader import load_case

    file, keys = {**CASES, **LONG}[name]
    written = load_case(file)
    analyses = {
        "as_written": written.case.analysis.model_copy(update=keys),
        "off": written.case.analysis.model_copy(update={**keys, "accuracy": "off"}),
    }
    return {
        kind: dataclasses.replace(
            written, case=written.case.model_copy(update={"analysis": analysis})
        )
        for kind, analysis in analyses.items()
    }


def case_overhead(name: str, repeat: int) -> dict[str, Any]:
    """`run_case` of a cost-table case as written, as written without the companion's rows
    about the run's crests (loadcases.run.companion.crest_rows: none kept) and with
    accuracy off (`variants`), alternating, best CPU ms of `repeat` each, and the
    estimate's share of each."""
    from loadcases.run import companion, run_case

    files = variants(name)
    kinds = {"as_written": files["as_written"], "no_crest_rows": files["as_written"]}
    kinds["off"] = files["off"]
    best = {kind: float("inf") for kind in kinds}
    kept = companion.crest_rows
    for case_file in files.values():
        run_case(case_file)  # its kernels loaded
    try:
        for _ in range(max(1, repeat)):
            for kind, case_file in kinds.items():
                companion.crest_rows = kept if kind != "no_crest_rows" else _no_rows
                started = time.process_time()
                run_case(case_file)
                best[kind] = min(best[kind], time.process_time() - started)
    finally:
        companion.crest_rows = kept
    on, without, off = (best[kind] * 1e3 for kind in ("as_written", "no_crest_rows", "off"))
    return {
        "case": name,
        "as_written_ms": round(on, 2),
        "no_crest_rows_ms": round(without, 2),
        "off_ms": round(off, 2),
        "overhead": round(on / off - 1.0, 4),
        "overhead_no_crest_rows": round(without / off - 1.0, 4),
    }


def beside_overhead(name: str, repeat: int) -> dict[str, Any]:
    """`run_case` of a case with its companion after the run, beside it and with accuracy
    off, alternating, `repeat` times each: the best wall s and process CPU s of each, the
    estimate's share of each (of the wall time), whether the companion followed the run,
    and whether the two estimates are the same to the last bit."""
    from loadcases.run import run_case

    files = variants(name)
    kinds = {"after": (files["as_written"], False), "beside": (files["as_written"], True)}
    kinds["off"] = (files["off"], False)
    wall = {kind: float("inf") for kind in kinds}
    cpu = dict(wall)
    estimates: dict[str, Any] = {}
    run_case(files["as_written"])  # its kernels loaded
    for _ in range(max(1, repeat)):
        for kind, (case_file, beside) in kinds.items():
            started, used = (time.perf_counter(), time.process_time())
            outcome = run_case(case_file, beside=beside)
            wall[kind] = min(wall[kind], time.perf_counter() - started)
            cpu[kind] = min(cpu[kind], time.process_time() - used)
            estimates[kind] = outcome.checks.get("accuracy")
    followed = bool(estimates["beside"]["beside"])
    same = estimates["after"]["estimate"] == estimates["beside"]["estimate"]
    return {
        "case": name,
        "off_wall_s": round(wall["off"], 4),
        "after_wall_s": round(wall["after"], 4),
        "beside_wall_s": round(wall["beside"], 4),
        "off_cpu_s": round(cpu["off"], 4),
        "after_cpu_s": round(cpu["after"], 4),
        "beside_cpu_s": round(cpu["beside"], 4),
        "after_overhead": round(wall["after"] / wall["off"] - 1.0, 4),
        "beside_overhead": round(wall["beside"] / wall["off"] - 1.0, 4),
        "followed": followed,
        "same_estimate": same,
    }


def _no_rows(run: Any, found: Any = None) -> list[float]:
    """`crest_rows` keeping none (the companion's rows as before them)."""
    return []


def command_files(name: str, folder: Path) -> dict[str, Path]:
    """A cost-table case as two case files (`as_written`, `off`: `analysis.accuracy: off`),
    each with its analysis keys (benchmarks.companion_cost.CASES, or `LONG`), beside a copy of the
    case's folder in `folder` (its mechanism files found as the original finds them)."""
    file, keys = {**CASES, **LONG}[name]
    copy = folder / file.stem
    shutil.copytree(file.parent, copy)
    case = yaml.safe_load(file.read_text(encoding="utf-8"))
    out = {}
    for kind, extra in (("as_written", {}), ("off", {"accuracy": "off"})):
        changed = {**case, "analysis": {**case["analysis"], **keys, **extra}}
        out[kind] = copy / f"{file.name.removesuffix('.case.yaml')}-{kind}.case.yaml"
        out[kind].write_text(yaml.safe_dump(changed, sort_keys=False), encoding="utf-8")
    return out


def command_overhead(name: str, repeat: int, beside: str = "") -> dict[str, Any]:
    """`loads run CASE` of a cost-table case as written and with accuracy off, alternating
    which goes first, `repeat` times each: the median CPU ms (the command's) and wall s of
    each and the estimate's share of the command; `beside`: the companion beside the run
    ("1") or after it ("0") whatever the machine's load (LOADS_COMPANION_BESIDE), "": as
    the command chooses."""
    spent: dict[str, list[tuple[float, float]]] = {"as_written": [], "off": []}
    said = os.environ.get(ENVIRONMENT)
    with tempfile.TemporaryDirectory() as tmp:
        files = command_files(name, Path(tmp))
        for k in range(max(1, repeat)):
            order = ("as_written", "off") if k % 2 == 0 else ("off", "as_written")
            for kind in order:
                os.environ[ENVIRONMENT] = beside
                try:
                    done = run_loads(files[kind], 1, [])
                finally:
                    os.environ.pop(ENVIRONMENT)
                    if said is not None:
                        os.environ[ENVIRONMENT] = said
                if done["exit"] != 0 or done["runs"] != 1:
                    raise RuntimeError(f"{name} {kind}: {done['stderr_tail']}")
                spent[kind].append((done["cpu_ms_per_run"], done["wall_s"]))
    cpu = {kind: statistics.median(c for c, _ in rows) for kind, rows in spent.items()}
    wall = {kind: statistics.median(w for _, w in rows) for kind, rows in spent.items()}
    return {
        "case": name,
        "beside": {"1": "forced", "0": "never"}.get(beside, "as the command chooses"),
        "as_written_cpu_ms": cpu["as_written"],
        "off_cpu_ms": cpu["off"],
        "as_written_wall_s": wall["as_written"],
        "off_wall_s": wall["off"],
        "overhead": round(cpu["as_written"] / cpu["off"] - 1.0, 4),
    }


def _measured(names: Any, measure: Any) -> list[dict[str, Any]]:
    """`measure(name)` of each case, each row printed as it comes."""
    rows = []
    for name in names:
        rows.append(measure(name))
        print(_line(rows[-1]), flush=True)
    return rows


def _line(row: dict[str, Any]) -> str:
    """A `case_overhead` or `command_overhead` row as a line."""
    if "beside_wall_s" in row:
        return (
            f"{row['case']}: run_case wall {row['off_wall_s']:.3f} s off, "
            f"{row['after_wall_s']:.3f} companion after (+{row['after_overhead']:.0%}), "
            f"{row['beside_wall_s']:.3f} beside (+{row['beside_overhead']:.0%}; followed "
            f"{row['followed']}, same estimate {row['same_estimate']}); CPU "
            f"{row['off_cpu_s']:.3f} / {row['after_cpu_s']:.3f} / {row['beside_cpu_s']:.3f} s"
        )
    if "as_written_ms" in row:
        return (
            f"{row['case']}: run_case {row['as_written_ms']:.1f} ms as written, "
            f"{row['off_ms']:.1f} off: the estimate {row['overhead']:.1%} "
            f"({row['overhead_no_crest_rows']:.1%} without the crest rows)"
        )
    return (
        f"{row['case']} (companion beside: {row['beside']}): loads run "
        f"{row['as_written_cpu_ms']:.0f} ms of CPU as written, "
        f"{row['off_cpu_ms']:.0f} off ({row['as_written_wall_s']:.2f} / "
        f"{row['off_wall_s']:.2f} s): the estimate {row['overhead']:.1%}"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cases", action="store_true", help="also the cost table's cases")
    parser.add_argument(
        "--command", action="store_true", help="also `loads run CASE` of each of them"
    )
    parser.add_argument(
        "--long", action="store_true", help="--command on A01 over 2000 s and A05 over 50 s too"
    )
    parser.add_argument(
        "--beside", action="store_true", help="the companion after and beside the run, wall time"
    )
    parser.add_argument(
        "--command-beside",
        choices=("", "0", "1"),
        default="",
        help="--command's companion: 1 beside the run, 0 after it ('': as loads run chooses)",
    )
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    from benchmarks.suite import machine_info

    result: dict[str, Any] = {"machine": machine_info(), "load_before": os.getloadavg()}
    if args.rounds > 0:  # --rounds 0: the cases alone
        result["campaign"] = campaign_overhead(args.runs, args.jobs, args.rounds)
        print(f"campaign: the estimate {result['campaign']['overhead']:.1%} of a run (median)")
    if args.cases:
        result["cases"] = _measured(CASES, lambda name: case_overhead(name, args.repeat))
    if args.command:
        names = [*CASES, *(LONG if args.long else ())]
        result["command"] = _measured(
            names, lambda name: command_overhead(name, args.repeat, args.command_beside)
        )
    if args.beside:
        names = [*CASES, *LONG]
        result["beside"] = _measured(names, lambda name: beside_overhead(name, args.repeat))
    result["load_after"] = os.getloadavg()
    if args.json:
        args.json.write_text(json.dumps(result, indent=2), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
