"""The global error estimate against the true error on runs with events (issue 35): per case
and request, the estimate of the grid companion (the run's own steps two at a time, the
events' times kept as step ends) and of the adaptive one (error-controlled, steps twice as
long) beside the true error of the run at the case's settings, measured against a reference
run of the same case, the same events, at 1e-3 of the case's tolerance with `output: steps`
at a tenth of the output interval; a second reference at 1e-4 of it says how far the first
has converged (`reference_error`, of the request's peak: it must be well below the true
errors it measures).

    python -m benchmarks.error_table_events [-o benchmarks/results/error-table-events.json]
                                            [--gear FILE]

The cases: the door jettison (a time event, then a stop at the hinge angle), the door
lifted by the inner handle until let go (the handle's motion switched off, then a stop),
the bench model's three flaps falling onto their latches (three springs switched on, their
forces requested here) and the user's landing gear free fall onto its down-stop.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml

from benchmarks.companion_choice import companion_kind
from benchmarks.error_table import _with, at_target, true_errors
from benchmarks.rows import write_rows
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

ROOT = Path(__file__).resolve().parents[1]
REFERENCE_FACTORS = (1e-3, 1e-4)  # of the case's tolerance: the reference, its check
REFERENCE_ROWS = 10  # reference rows per output interval: its envelope is the continuous one
DEFAULT_TOLERANCE = 1e-6  # generalized-alpha's, where the case sets none

#: the flaps' latch springs and hinges requested besides their angles
FLAP_REQUESTS = {
    **{f"latch{k}": {"force": f"latch{k}"} for k in range(3)},
    **{f"hinge{k}_force": {"joint": f"hinge{k}", "quantity": "force"} for k in range(3)},
}

#: name -> (case file, requests added to it)
CASES: dict[str, tuple[Path, dict[str, Any]]] = {
    "door jettison": (ROOT / "loadcases/library/door/jettison.case.yaml", {}),
    "door let go": (ROOT / "loadcases/library/door/lifting_inner_let_go.case.yaml", {}),
    "flap latches": (ROOT / "benchmarks/models/flap_latches.case.yaml", FLAP_REQUESTS),
}
#: the user's landing gear free fall (its case file is not in the project: `--gear FILE`)
GEAR = "gear free fall"


def _loaded(path: Path, requests: dict[str, Any], directory: Path) -> Any:
    """The case at `path` with `requests` added (its copy in `directory`: a case whose
    mechanism is inline, as the bench models')."""
    if not requests:
        return load_case(path)
    data = yaml.safe_load(path.read_text())
    data["requests"] = {**data["requests"], **requests}
    copy = directory / path.name
    copy.write_text(yaml.safe_dump(data, sort_keys=False))
    return load_case(copy)


def reference(case_file: Any, factor: float) -> Any:
    """The case at `factor` of its tolerance, `output: steps` at a tenth of its interval."""
    analysis = case_file.case.analysis
    tolerance = (analysis.tolerance or DEFAULT_TOLERANCE) * factor
    return run_case(
        _with(
            case_file,
            step=analysis.step / REFERENCE_ROWS,
            tolerance=tolerance,
            output="steps",
            accuracy="off",
        )
    ).solution


def estimates(case_file: Any, kind: str) -> tuple[Any, dict[str, Any], float]:
    """The run at the case's settings, its accuracy block with the `kind` companion, its
    CPU time (s)."""
    with companion_kind(kind):
        started = time.process_time()
        outcome = run_case(case_file)
        cpu = time.process_time() - started
    return outcome.solution, outcome.checks.get("accuracy") or {}, cpu


def case_rows(name: str, path: Path, requests: dict[str, Any]) -> list[dict[str, Any]]:
    """One case's rows: per request the two companions' estimates and the true error."""
    with tempfile.TemporaryDirectory() as directory:
        case_file = _loaded(path, requests, Path(directory))
        run, grid, cpu_grid = estimates(case_file, "grid")
        _, adaptive, cpu_adaptive = estimates(case_file, "adaptive")
        tight, tighter = (reference(case_file, factor) for factor in REFERENCE_FACTORS)
    truth = true_errors(run, tight)
    converged = true_errors(tight, tighter)
    rows = []
    for request, (history, peak) in truth.items():
        row: dict[str, Any] = {
            "case": name,
            "request": request,
            "true_history": history,
            "true_peak": peak,
            "reference_error": max(converged.get(request, (float("nan"),) * 2)),
            "events": [(event.name, event.time) for event in run.events],
            "reference_events": [(event.name, event.time) for event in tight.events],
            "steps": run.stats.steps,
        }
        for kind, block, cpu in (("grid", grid, cpu_grid), ("adaptive", adaptive, cpu_adaptive)):
            guess = block.get("estimate", {}).get(request)
            if guess is None:
                continue
            row[f"{kind}_companion"] = block.get("companion")
            row[f"{kind}_note"] = block.get("note", "")
            row[f"{kind}_observed_order"] = block.get("observed_order")
            row[f"{kind}_cpu_s"] = cpu
            for part, true in (("history", history), ("peak", peak)):
                row[f"{kind}_{part}"] = guess[part]
                row[f"{kind}_ratio_{part}"] = guess[part] / true if true else None
                row[f"{kind}_at_target_{part}"] = at_target(guess[part], true)
        rows.append(row)
    return rows


def _print(rows: list[dict[str, Any]]) -> None:
    print(
        f"{'case':15s} {'request':16s} {'true hist':>9s} {'grid':>6s} {'adapt':>6s}"
        f" {'true peak':>9s} {'grid':>6s} {'adapt':>6s} {'ref err':>8s}"
    )
    for r in rows:
        cells = [r.get(f"{k}_ratio_{p}") for p in ("history", "peak") for k in ("grid", "adaptive")]
        g = [f"{c:6.3g}" if c is not None else "     -" for c in cells]
        print(
            f"{r['case']:15s} {r['request']:16s} {r['true_history']:9.2e} {g[0]} {g[1]}"
            f" {r['true_peak']:9.2e} {g[2]} {g[3]} {r['reference_error']:8.1e}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help="of: " + ", ".join([*CASES, GEAR]))
    parser.add_argument("-o", "--output", type=Path, default=None)
    parser.add_argument("--gear", type=Path, default=None, help="the gear free fall's case file")
    args = parser.parse_args(argv)
    cases = dict(CASES)
    if args.gear is not None:
        cases[GEAR] = (args.gear, {})
    names = [name for name in args.cases or cases if name in cases]
    rows = [row for name in names for row in case_rows(name, *cases[name])]
    _print(rows)
    write_rows(rows, args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
