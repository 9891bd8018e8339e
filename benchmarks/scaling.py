"""Scaling with the number of bodies: the N-link chain (benchmarks.models.chain) in both codes.

For each N (default 5, 10, 20, 50, 100 links; 3 N DOF) the chain falls for `--end` s (default
0.5) in Exudyn at a fixed step (`--step`, default 2.5e-4 s) and in `loads` at a fixed
`analysis.tolerance` (`--tolerance`, default 1e-7): the settings that meet the suite's 1e-4
target on chain20 (benchmarks/README.md). Measured per run: solve wall time (Exudyn
`SolveDynamic`; `loads` `run_case`: model build, checks, integration, requests), steps, time
per step and per simulated second, the fastest of `--repeat` runs (default 2). Each run's
error against an Exudyn run at a quarter of the step (`relative_error`, the suite's
measure) says how equal the accuracy was; `--no-accuracy` skips those reference runs. A
first short run per code compiles the kernels (not timed).

Writes a log-log PNG (time per step and per simulated second against N, both codes; the
solve's process CPU time, the measure on a shared machine, solid, and its wall time dashed)
and a JSON of the figures with the machine, the date and the load average, by default
`benchmarks/results/scaling.png` and `benchmarks/results/scaling.json` (the latest figures;
earlier ones are in the git history).

    python -m benchmarks.scaling [--links 5,10,20,50,100] [--end 0.5] [--repeat 2]
                                 [--png FILE] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.accuracy import EXUDYN_SOLVER, Reference, relative_error
from benchmarks.models import ModelSpec, chain
from benchmarks.suite import _case_copy, _loads_api, machine_info

HERE = Path(__file__).resolve().parent
DEFAULT_LINKS = (5, 10, 20, 50, 100)
REFERENCE_DIVISOR = 4  # the accuracy reference runs at step / REFERENCE_DIVISOR


def exudyn_run(model: ModelSpec, step: float, end: float) -> dict[str, Any]:
    """One Exudyn run of `model` at the fixed `step` (s) for `end` s: figures and channels."""
    from benchmarks.exudyn_models import ExudynOptions, run_exudyn

    run = run_exudyn(
        model,
        ExudynOptions(
            step=step, end=end, output_step=model.output_step, linear_solver=EXUDYN_SOLVER
        ),
    )
    return {
        "setting": f"h = {step:g} s",
        "steps": run.steps,
        "solve_s": run.solve_seconds,
        "cpu_s": run.info["solve_cpu_seconds"],
        "time": run.time,
        "channels": run.channels,
    }


def loads_run(model: ModelSpec, tolerance: float, end: float) -> dict[str, Any]:
    """One `loads` run of `model`'s case file at `tolerance` for `end` s (staged as the suite
    times it: solve = `run_case`)."""
    _, staged = _loads_api()
    assert staged is not None, "the engine no longer exposes load_case / run_case"
    with tempfile.TemporaryDirectory(prefix=f"scaling-{model.name}-") as tmp:
        case = _case_copy(model, end, tolerance, Path(tmp))
        outcome, _parse, solve, _write = staged(case, Path(tmp) / "out")
    sol = outcome.solution
    if not sol.ok:
        raise RuntimeError(f"loads failed on {model.name}: {sol.message}")
    return {
        "setting": f"tolerance {tolerance:g}",
        "steps": int(sol.stats.steps),
        "solve_s": solve,
        "cpu_s": float(sol.stats.cpu_seconds),
        "time": sol.time,
        "channels": sol.channels,
    }


def measure(links: int, args: argparse.Namespace) -> dict[str, Any]:
    """Both codes on chain(links): per-step and per-simulated-second figures, errors."""
    model = chain(links, end=args.end)
    ex = min(
        (exudyn_run(model, args.step, args.end) for _ in range(args.repeat)),
        key=lambda r: r["solve_s"],
    )
    lo = min(
        (loads_run(model, args.tolerance, args.end) for _ in range(args.repeat)),
        key=lambda r: r["solve_s"],
    )
    row: dict[str, Any] = {"links": links, "dof": 3 * links, "end": args.end}
    ref = None
    if args.accuracy:
        fine = exudyn_run(model, args.step / REFERENCE_DIVISOR, args.end)
        ref = Reference(model.name, fine["time"], fine["channels"], {})
    for name, run in (("exudyn", ex), ("loads", lo)):
        figures = {k: v for k, v in run.items() if k not in ("time", "channels")}
        figures["ms_per_step"] = 1e3 * run["solve_s"] / max(run["steps"], 1)
        figures["s_per_simulated_s"] = run["solve_s"] / args.end
        figures["cpu_ms_per_step"] = 1e3 * run["cpu_s"] / max(run["steps"], 1)
        figures["cpu_s_per_simulated_s"] = run["cpu_s"] / args.end
        if ref is not None:
            figures["error"] = relative_error(run["time"], run["channels"], ref, model.main)
        row[name] = figures
    row["ratio_per_simulated_s"] = lo["solve_s"] / ex["solve_s"]
    row["cpu_ratio_per_simulated_s"] = lo["cpu_s"] / ex["cpu_s"]
    return row


def slope(xs: list[float], ys: list[float]) -> float:
    """Least-squares exponent p of y ~ x^p (log-log)."""
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0])


def plot(rows: list[dict[str, Any]], path: Path, title: str) -> None:
    """Log-log PNG: ms per step and s per simulated second against the number of links."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = [r["links"] for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    panels = (("ms_per_step", "ms per step"), ("s_per_simulated_s", "solve s per simulated s"))
    for ax, (key, label) in zip(axes, panels, strict=True):
        for code, colour in (("exudyn", "C0"), ("loads", "C1")):
            cpu = [r[code][f"cpu_{key}"] for r in rows]
            wall = [r[code][key] for r in rows]
            ax.loglog(n, cpu, "o-", color=colour, label=f"{code} CPU (slope {slope(n, cpu):.2f})")
            ax.loglog(n, wall, "s--", color=colour, alpha=0.5, label=f"{code} wall")
        ax.set_xticks(n, [str(v) for v in n])
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.set_xlabel("links N (bodies; 3 N DOF)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    """Command line of the scaling study; returns the exit code (1 when a run failed)."""
    parser = argparse.ArgumentParser(
        prog="loads bench --scaling", description=__doc__.split("\n")[0]
    )
    parser.add_argument("--links", default=",".join(map(str, DEFAULT_LINKS)))
    parser.add_argument("--end", type=float, default=0.5, help="simulated s (default 0.5)")
    parser.add_argument("--step", type=float, default=2.5e-4, help="Exudyn's fixed step, s")
    parser.add_argument("--tolerance", type=float, default=1e-7, help="loads analysis.tolerance")
    parser.add_argument("--repeat", type=int, default=2, help="timed runs, fastest kept")
    parser.add_argument("--no-accuracy", dest="accuracy", action="store_false")
    date = datetime.now(UTC).date().isoformat()
    # the latest figures of the study, one stable name each (earlier ones: git history)
    parser.add_argument("--png", type=Path, default=HERE / "results" / "scaling.png")
    parser.add_argument("--json", type=Path, default=HERE / "results" / "scaling.json")
    args = parser.parse_args(argv)
    links = [int(n) for n in args.links.split(",") if n.strip()]
    exudyn_run(chain(2), args.step, 0.01), loads_run(chain(2), args.tolerance, 0.01)  # compile
    load_before = os.getloadavg()
    rows = []
    nan = float("nan")
    for n in links:
        try:
            rows.append(measure(n, args))
        except RuntimeError as exc:
            print(f"chain{n}: {exc}")
            return 1
        r = rows[-1]
        print(
            f"N = {n:4d}: exudyn {r['exudyn']['ms_per_step']:8.3f} ms/step "
            f"{r['exudyn']['s_per_simulated_s']:8.2f} s/s | loads {r['loads']['ms_per_step']:8.3f} "
            f"ms/step {r['loads']['s_per_simulated_s']:8.2f} s/s ({r['loads']['steps']} steps) | "
            f"ratio {r['ratio_per_simulated_s']:.1f} (CPU {r['cpu_ratio_per_simulated_s']:.1f}) | "
            "errors "
            f"{r['exudyn'].get('error', nan):.1e} / {r['loads'].get('error', nan):.1e}",
            flush=True,
        )
    load_after = os.getloadavg()
    title = (
        f"chain of N links, {args.end:g} s: Exudyn h = {args.step:g} s, loads tolerance "
        f"{args.tolerance:g}; load average {load_before[0]:.1f} -> {load_after[0]:.1f}, {date}"
    )
    args.png.parent.mkdir(parents=True, exist_ok=True)
    args.json.parent.mkdir(parents=True, exist_ok=True)
    plot(rows, args.png, title)
    payload = {
        "machine": machine_info(),
        "load_average_before": load_before,
        "load_average_after": load_after,
        "settings": {k: v for k, v in vars(args).items() if k not in ("png", "json")},
        "slopes": {
            f"{code}_{key}": slope(links, [r[code][key] for r in rows])
            for code in ("exudyn", "loads")
            for key in ("ms_per_step", "s_per_simulated_s", "cpu_ms_per_step")
        },
        "rows": rows,
    }
    args.json.write_text(json.dumps(payload, indent=2, default=str), encoding="utf-8")
    print(f"plot -> {args.png}; figures -> {args.json}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
