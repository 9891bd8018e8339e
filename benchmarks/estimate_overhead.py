"""What a dynamic run's error estimate adds to the run as written (issue 35 item 2: at most
25 % of a run): the same work with `analysis.accuracy` as written and with `accuracy: off`,
alternated.

- The campaign (`benchmarks.campaign`'s set of N variants of the bench slider-crank, every
  file written as a user gets them): `loads run SET -j J --force` as written and without
  the estimate, `--rounds` times each, the first to go alternating; CPU a run of the
  command and its workers (getrusage), and the estimate's share, (as written - off) / off,
  per round and their median.
- `--cases`: per case of the companion cost table (benchmarks.companion_cost.CASES),
  `run_case` in this process as written and with accuracy off, alternated `--repeat`
  times, best CPU of each: the whole run (validation aside) with its rows, requests and
  checks, which `companion_cost` leaves out of its companion / solve ratio.

CPU times on a shared machine move with its load: compare the two columns of one run.

    python -m benchmarks.estimate_overhead [--runs 200] [--jobs 2] [--rounds 3] [--cases]
                                           [--repeat 5] [--json FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from benchmarks.campaign import run_loads, sweep_rates, write_sweep
from benchmarks.companion_cost import CASES

__all__ = ["campaign_overhead", "case_overhead", "main", "variants"]


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

    file, keys = CASES[name]
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
    """`run_case` of a cost-table case as written and with accuracy off (`variants`),
    alternating, best CPU ms of `repeat` each, and the estimate's share."""
    from loadcases.run import run_case

    files = variants(name)
    best = {kind: float("inf") for kind in files}
    for case_file in files.values():
        run_case(case_file)  # its kernels loaded
    for _ in range(max(1, repeat)):
        for kind, case_file in files.items():
            started = time.process_time()
            run_case(case_file)
            best[kind] = min(best[kind], time.process_time() - started)
    on, off = best["as_written"] * 1e3, best["off"] * 1e3
    return {
        "case": name,
        "as_written_ms": round(on, 2),
        "off_ms": round(off, 2),
        "overhead": round(on / off - 1.0, 4),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cases", action="store_true", help="also the cost table's cases")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    from benchmarks.suite import machine_info

    result: dict[str, Any] = {"machine": machine_info(), "load_before": os.getloadavg()}
    result["campaign"] = campaign_overhead(args.runs, args.jobs, args.rounds)
    print(f"campaign: the estimate {result['campaign']['overhead']:.1%} of a run (median)")
    if args.cases:
        result["cases"] = []
        for name in CASES:
            row = case_overhead(name, args.repeat)
            result["cases"].append(row)
            print(
                f"{name}: run_case {row['as_written_ms']:.1f} ms as written, "
                f"{row['off_ms']:.1f} off: the estimate {row['overhead']:.1%}",
                flush=True,
            )
    result["load_after"] = os.getloadavg()
    if args.json:
        args.json.write_text(json.dumps(result, indent=2), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
