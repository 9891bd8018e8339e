"""Side-by-side speed benchmark of `loads` and Exudyn at equal accuracy.

For each model of `benchmarks.models` (slider_crank, chain20, fourbar10, ball_bounce, chain100),
or with `--kinds` of `benchmarks.kinds` (socket_rattle, flap_latches, fourbar_friction,
hydraulic_ram: contact, events, springs with friction, hydraulics; then Kane's unstiffened
spin-up beam and the flexible slider-crank against Exudyn's ObjectFFRFreducedOrder,
`benchmarks.flexible_compare`):

1. Reference: Exudyn's solution with a very fine fixed step (`REFERENCE_STEP`, 10x to 100x
   below the step the benchmark ends up using), stored in `benchmarks/reference/<model>.npz`
   with an estimate of its own error (the difference to the run at twice that step, / 3 for
   a second-order method). The kinds' reference is `loads`'s own solution at a tolerance of
   1e-11 (`LOADS_REFERENCE_TOLERANCE`): Exudyn's switching (valve, latches) is of
   first order in its step, which makes a fine-step Exudyn reference dear; Exudyn meeting the
   target against it is the independent check. `--make-reference` recomputes the files.
2. Accuracy: error = max over the output times of |y - y_ref| (Euclidean norm over the
   model's main columns), divided by the largest range (max - min) of those columns in the
   reference. Both codes must reach `--tol` (default 1e-4).
3. Exudyn: generalized-alpha with a fixed step, the step halved from `EXUDYN_START_STEP`
   until the error is within `--tol` (then the step 4/3 as long is tried too); then that
   run is timed `--repeat` times (best kept).
4. `loads`: `loadcases.run.run_file` on a copy of `benchmarks/models/<model>.case.yaml` with
   `analysis.tolerance` tightened from 1e-3 by decades until the error is within `--tol`;
   then timed likewise. Both calibrations then try one setting between the last two
   (`benchmarks.accuracy.TOLERANCE_BETWEEN`, `STEP_BETWEEN`) and keep it if it meets `--tol` too.

Process CPU seconds of each solve (time.process_time) go to the table's `cpu` ratio column,
the figure to compare on a shared machine.
Wall times (time.perf_counter): Exudyn `solve` = `SolveDynamic` only; `total` = building
the system (items + Assemble) + solve. `loads` runs the stages of `run_file` one by one:
`solve` = `run_case` (building the mechlib model from the parsed case, and solving it);
`total` = parse + solve + writing the results. The engine's own `stats.cpu_seconds`
(process CPU time, which counts every BLAS thread) goes to the JSON. Imports are never
timed. The ratio is loads / Exudyn.

Run: `.venv/bin/python -m benchmarks.suite [--quick] [--json FILE]`.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.accuracy import (
    EXUDYN_SOLVER,
    LOADS_REFERENCE_TOLERANCE,
    REFERENCE_DIR,
    REFERENCE_STEP,
    STEP_BETWEEN,
    TOLERANCE_BETWEEN,
    CodeResult,
    Reference,
    load_reference,
    make_loads_reference,
    make_reference,
    relative_error,
)
from benchmarks.cases import case_path, case_yaml
from benchmarks.kinds import kind_models
from benchmarks.models import ModelSpec, all_models, model_by_name

__all__ = [
    "EXUDYN_START_STEP",
    "LOADS_TOLERANCES",
    "REFERENCE_DIR",
    "REFERENCE_STEP",
    "Reference",
    "load_reference",
    "machine_info",
    "main",
    "make_reference",
    "relative_error",
]

#: Largest Exudyn step (s) tried; the suite halves it until the accuracy target is met.
EXUDYN_START_STEP: dict[str, float] = {
    "slider_crank": 2e-3,
    "chain20": 2e-3,
    "fourbar10": 1e-2,
    "ball_bounce": 4e-6,
    "chain100": 2e-3,
    "socket_rattle": 4e-6,
    "flap_latches": 2e-4,
    "fourbar_friction": 2e-3,
    "hydraulic_ram": 2e-4,
}

#: `analysis.tolerance` values tried for `loads`, loosest first.
LOADS_TOLERANCES: tuple[float, ...] = (
    1e-3,
    1e-4,
    1e-5,
    1e-6,
    1e-7,
    1e-8,
    1e-9,
    1e-10,
    1e-11,
    1e-12,
)

MAX_HALVINGS = 10


#: `analysis.output` modes calibrated for `loads`; the faster at the target is kept: dense
#: rows between free steps, or steps landing on every output time (no rows to project:
#: cheaper where the error-controlled step is about the output interval, as on slider_crank)
OUTPUT_MODES: tuple[str, ...] = ("dense", "steps")


# --------------------------------------------------------------------------------------
# the two codes
# --------------------------------------------------------------------------------------
def _secondary(
    model: ModelSpec, time_: np.ndarray, channels: dict[str, np.ndarray], ref: Reference
) -> dict[str, float]:
    return {
        c: relative_error(time_, channels, ref, (c,))
        for c in model.secondary
        if c in channels and c in ref.channels
    }


def bench_exudyn(
    model: ModelSpec,
    end: float,
    ref: Reference,
    tol: float,
    repeat: int,
    log: Callable[[str], None],
) -> CodeResult:
    """Calibrate Exudyn's fixed step to `tol`, then time it `repeat` times (best kept)."""
    from benchmarks.exudyn_models import ExudynOptions, run_exudyn

    res = CodeResult()
    step = EXUDYN_START_STEP[model.name]
    chosen = None
    for _ in range(MAX_HALVINGS + 1):
        opts = ExudynOptions(
            step=step, end=end, output_step=model.output_step, linear_solver=EXUDYN_SOLVER
        )
        try:
            run = run_exudyn(model, opts)
            err = relative_error(run.time, run.channels, ref, model.main)
        except RuntimeError as exc:
            res.calibration.append((step, None))
            log(f"  exudyn  step {step:.3g} s: failed ({exc})")
            step /= 2.0
            continue
        res.calibration.append((step, err))
        log(f"  exudyn  step {step:.3g} s: error {err:.2e}")
        if err <= tol:
            chosen = opts
            break
        step /= 2.0
    if chosen is not None and len(res.calibration) > 1:
        between = _exudyn_between(model, chosen)
        if between is not None:
            run = run_exudyn(model, between)
            err = relative_error(run.time, run.channels, ref, model.main)
            res.calibration.append((between.step, err))
            log(f"  exudyn  step {between.step:.3g} s: error {err:.2e}")
            if err <= tol:
                chosen = between
    if chosen is None:
        res.status = "failed"
        res.message = f"no step down to {step * 2:.3g} s reached the error target {tol:g}"
        return res
    best_solve = best_total = best_build = best_cpu = float("inf")
    for _ in range(repeat):
        gc.collect()
        run = run_exudyn(model, chosen)
        best_cpu = min(best_cpu, run.info["solve_cpu_seconds"])
        best_solve = min(best_solve, run.solve_seconds)
        best_build = min(best_build, run.build_seconds)
        best_total = min(best_total, run.build_seconds + run.solve_seconds)
    res.status = "ok"
    res.setting = f"h = {chosen.step:.4g} s"
    res.error = relative_error(run.time, run.channels, ref, model.main)
    res.secondary_errors = _secondary(model, run.time, run.channels, ref)
    res.solve_seconds, res.build_seconds, res.total_seconds = best_solve, best_build, best_total
    res.cpu_seconds = best_cpu
    res.steps = run.steps
    res.extra = {
        "step": chosen.step,
        "spectral_radius": chosen.spectral_radius,
        "linear_solver": chosen.linear_solver,
        "exudyn_module": run.info.get("exudyn_module"),
        "newton_iterations": run.info.get("newton_iterations"),
    }
    return res


def _case_copy(
    model: ModelSpec, end: float, tolerance: float, directory: Path, output: str | None = None
) -> Path:
    """A copy of the committed case file with `analysis.end` and `analysis.tolerance` set,
    `analysis.output` when given (dense or steps), and `accuracy: off`: the bench measures
    the error itself, so the engine's own estimate (a second, coarser solve) would only be
    timed against `loads`. A model without a committed case file (the scaling study's
    chain<N>) is written from its spec."""
    import yaml

    committed = case_path(model)
    text = committed.read_text(encoding="utf-8") if committed.is_file() else case_yaml(model)
    data = yaml.safe_load(text)
    data["analysis"]["end"] = float(end)
    data["analysis"]["tolerance"] = float(tolerance)
    data["analysis"]["accuracy"] = "off"
    if output is not None:
        data["analysis"]["output"] = output
    path = directory / f"{model.name}.case.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def _loads_api() -> tuple[Callable[..., Any], Callable[..., Any] | None]:
    """`run_file`, and a timed runner that splits it into its stages when the engine has them.

    The runner returns `(outcome, parse_s, solve_s, write_s)`: wall times (s) of
    `loader.load_case`, `run.run_case` (building the mechlib model from the case and solving
    it) and `results.write_results` -- the three stages `run_file` is made of.
    """
    from loadcases.run import run_file  # type: ignore[import-not-found]

    try:
        from loadcases.inputs.loader import load_case  # type: ignore[import-not-found]
        from loadcases.results.files import write_results  # type: ignore[import-not-found]
        from loadcases.run import run_case  # type: ignore[import-not-found]
    except ImportError:
        return run_file, None

    def staged(path: Path, output_dir: Path) -> tuple[Any, float, float, float]:
        t0 = time.perf_counter()
        cf = load_case(path)
        t1 = time.perf_counter()
        outcome = run_case(cf)
        t2 = time.perf_counter()
        write_results(outcome, output_dir)
        t3 = time.perf_counter()
        return outcome, t1 - t0, t2 - t1, t3 - t2

    return run_file, staged


def _exudyn_between(model: ModelSpec, chosen: Any) -> Any:
    """Exudyn's options with the step STEP_BETWEEN times the `chosen` one (between it and
    the twice as long step that missed the target), or None where that step would not land
    on the output times."""
    from dataclasses import replace

    per_output = model.output_step / (STEP_BETWEEN * chosen.step)
    if abs(per_output - round(per_output)) > 1e-9 * per_output or round(per_output) < 1:
        return None
    return replace(chosen, step=model.output_step / round(per_output))


def bench_loads(
    model: ModelSpec,
    end: float,
    ref: Reference,
    tol: float,
    repeat: int,
    log: Callable[[str], None],
) -> CodeResult:
    """Calibrate `loads`'s `analysis.tolerance` to `tol` in each output mode (OUTPUT_MODES),
    time each calibrated setting `repeat` times and keep the mode of less solver CPU.

    Calibration calls `run_file`. The timed runs call the stages of `run_file` one by one
    (when the engine exposes them): *solve* is the wall time of `run_case` (model build from
    the parsed case + `mechlib.solve`), *total* the sum of parse, solve and write. Without the
    stages, *total* is the wall time of `run_file` and *solve* the engine's cpu_seconds.
    """
    res = CodeResult()
    try:
        run_file, staged = _loads_api()
    except ImportError as exc:
        res.status = "unavailable"
        res.message = f"loadcases.run cannot be imported yet ({exc})"
        return res

    with tempfile.TemporaryDirectory(prefix=f"bench-{model.name}-") as tmp:
        work = Path(tmp)
        timed: dict[str, dict[str, Any]] = {}
        for output in OUTPUT_MODES:
            calibration = _calibrate(model, end, ref, tol, output, work, run_file, log)
            if isinstance(calibration, CodeResult):  # the engine failed or lacks a column
                return calibration
            chosen, tried = calibration
            timed[output] = {"calibration": tried, "tolerance": chosen}
            if chosen is not None:
                case = _case_copy(model, end, chosen, work, output)
                timed[output].update(_timed(case, work, repeat, run_file, staged))
        done = [o for o in OUTPUT_MODES if timed[o]["tolerance"] is not None]
        if not done:
            tried = [e for o in OUTPUT_MODES for _, e in timed[o]["calibration"] if e is not None]
            res.status = "failed"
            res.calibration = timed[OUTPUT_MODES[0]]["calibration"]
            res.message = (
                f"no tolerance down to {LOADS_TOLERANCES[-1]:g} reached the error target "
                f"{tol:g} in either output mode (best {min(tried, default=float('nan')):.2e})"
            )
            return res
        # the mode of least CPU: on a shared machine the wall time of a run also counts
        # the other jobs' turns on the cores
        output = min(done, key=lambda o: timed[o]["best"]["cpu"])
        best, sol, chosen = (
            timed[output]["best"],
            timed[output]["solution"],
            timed[output]["tolerance"],
        )
        res.status = "ok"
        res.setting = f"tol = {chosen:.1g}, {output}"
        res.calibration = timed[output]["calibration"]
        res.error = relative_error(sol.time, sol.channels, ref, model.main)
        res.secondary_errors = _secondary(model, sol.time, sol.channels, ref)
        res.solve_seconds, res.total_seconds = best["solve"], best["total"]
        res.cpu_seconds = best["cpu"]
        res.steps = int(sol.stats.steps)
        res.extra = {
            "tolerance": chosen,
            "output": output,
            "modes": {
                o: {
                    "tolerance": timed[o]["tolerance"],
                    "calibration": timed[o]["calibration"],
                    "solve_seconds": timed[o].get("best", {}).get("solve"),
                    "cpu_seconds": timed[o].get("best", {}).get("cpu"),
                }
                for o in OUTPUT_MODES
            },
            "stats": sol.stats.as_dict(),
            "solve_timing": "wall of run_case" if staged is not None else "engine cpu_seconds",
            "parse_seconds": best["parse"],
            "write_seconds": best["write"],
            "engine_cpu_seconds": best["cpu"],
        }
    return res


def _calibrate(
    model: ModelSpec,
    end: float,
    ref: Reference,
    tol: float,
    output: str,
    work: Path,
    run_file: Callable[..., Any],
    log: Callable[[str], None],
) -> tuple[float | None, list[tuple[float, float | None]]] | CodeResult:
    """(the loosest tolerance meeting `tol` in output mode `output` or None, the tolerances
    tried with their errors); a failed CodeResult when the engine raised or a column is
    missing."""
    tried: list[tuple[float, float | None]] = []
    for tolerance in LOADS_TOLERANCES:
        case = _case_copy(model, end, tolerance, work, output)
        try:
            outcome = run_file(case, output_dir=work / "out")[0]
        except Exception as exc:  # noqa: BLE001  (any engine error is this model's failed result)
            return CodeResult(
                status="failed", message=f"run_file raised {type(exc).__name__}: {exc}"
            )
        sol = outcome.solution
        if not sol.ok:
            tried.append((tolerance, None))
            log(f"  loads   {output:5s} tolerance {tolerance:.0e}: failed ({sol.message})")
            continue
        missing = [c for c in model.main if c not in sol.channels]
        if missing:
            return CodeResult(
                status="failed",
                message=f"result columns {missing} missing; got {sorted(sol.channels)}",
            )
        err = relative_error(sol.time, sol.channels, ref, model.main)
        tried.append((tolerance, err))
        log(f"  loads   {output:5s} tolerance {tolerance:.0e}: error {err:.2e}")
        if err <= tol:
            if len(tried) == 1 or tried[-2][1] is None:
                return tolerance, tried
            between = tolerance * TOLERANCE_BETWEEN
            case = _case_copy(model, end, between, work, output)
            sol = run_file(case, output_dir=work / "out")[0].solution
            if not sol.ok:
                return tolerance, tried
            err = relative_error(sol.time, sol.channels, ref, model.main)
            tried.append((between, err))
            log(f"  loads   {output:5s} tolerance {between:.1e}: error {err:.2e}")
            return (between if err <= tol else tolerance), tried
    return None, tried


def _timed(
    case: Path,
    work: Path,
    repeat: int,
    run_file: Callable[..., Any],
    staged: Callable[..., Any] | None,
) -> dict[str, Any]:
    """{"best": the best solve, total, parse, write and engine CPU seconds of `repeat`
    runs, "solution": the last run's solution}."""
    best = dict.fromkeys(("solve", "total", "parse", "write", "cpu"), float("inf"))
    outcome = None
    for _ in range(repeat):
        gc.collect()
        if staged is not None:
            outcome, parse_s, solve_s, write_s = staged(case, work / "out")
            total_s = parse_s + solve_s + write_s
        else:
            t0 = time.perf_counter()
            outcome = run_file(case, output_dir=work / "out")[0]
            total_s = time.perf_counter() - t0
            parse_s = write_s = float("nan")
            solve_s = float(outcome.solution.stats.cpu_seconds)
        for key, value in (
            ("solve", solve_s),
            ("total", total_s),
            ("parse", parse_s),
            ("write", write_s),
            ("cpu", float(outcome.solution.stats.cpu_seconds)),
        ):
            best[key] = min(best[key], value)
    assert outcome is not None, "repeat >= 1"
    return {"best": best, "solution": outcome.solution}


# --------------------------------------------------------------------------------------
# machine information and report
# --------------------------------------------------------------------------------------
def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _git(*args: str) -> str | None:
    try:
        out = subprocess.run(
            ["git", *args],
            cwd=Path(__file__).resolve().parent.parent,
            capture_output=True,
            text=True,
            timeout=10,
            check=False,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


def _git_commit() -> str | None:
    """The checkout's commit, with `+dirty` when mechlib/ or loadcases/ have local changes."""
    commit = _git("rev-parse", "--short", "HEAD")
    if commit is None:
        return None
    changes = _git("status", "--porcelain", "--", "mechlib", "loadcases")
    return commit + ("+dirty" if changes else "")


def machine_info() -> dict[str, Any]:
    """Platform, CPU model, cores, Python / numpy / Exudyn / loads versions, date."""
    from importlib.metadata import PackageNotFoundError, version

    from benchmarks.exudyn_models import exudyn_version

    try:
        loads_version: str | None = version("loads")
    except PackageNotFoundError:
        loads_version = None
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count() or 1
    return {
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
        "platform": platform.platform(),
        "machine": platform.machine(),
        "cpu": _cpu_model(),
        "cores": os.cpu_count(),
        "usable_cores": usable,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "exudyn": exudyn_version(),
        "loads": loads_version,
        "git_commit": _git_commit(),
    }


def _fmt(x: float | None, spec: str) -> str:
    return "-" if x is None else format(x, spec)


def _cpu_ratio(loads: CodeResult, exudyn: CodeResult) -> float | None:
    """loads / Exudyn process CPU seconds of the solve, when both were measured."""
    if not loads.cpu_seconds or not exudyn.cpu_seconds:
        return None
    return loads.cpu_seconds / exudyn.cpu_seconds


def format_table(rows: list[dict[str, Any]], tol: float) -> str:
    """The results as a fixed-width text table."""
    head = (
        f"{'model':<13} {'end s':>5} | "
        f"{'exudyn':<15} {'error':>8} {'solve s':>8} {'total s':>8} | "
        f"{'loads':<11} {'error':>8} {'solve s':>8} {'total s':>8} | "
        f"{'ratio solve':>11} {'total':>7} {'cpu':>5}"
    )
    lines = [
        f"accuracy target: error <= {tol:g} of the output's range (vs the model's reference)",
        head,
        "-" * len(head),
    ]
    for r in rows:
        ex: CodeResult = r["exudyn"]
        lo: CodeResult = r["loads"]
        ratio_s = ratio_t = ratio_c = None
        if ex.status == "ok" and lo.status == "ok":
            ratio_s = lo.solve_seconds / ex.solve_seconds
            ratio_t = lo.total_seconds / ex.total_seconds
            ratio_c = _cpu_ratio(lo, ex)
        lines.append(
            f"{r['model']:<13} {r['end']:>5g} | "
            f"{ex.setting or ex.status:<15} {_fmt(ex.error, '.1e'):>8} "
            f"{_fmt(ex.solve_seconds, '.3f'):>8} {_fmt(ex.total_seconds, '.3f'):>8} | "
            f"{lo.setting or lo.status:<11} {_fmt(lo.error, '.1e'):>8} "
            f"{_fmt(lo.solve_seconds, '.3f'):>8} {_fmt(lo.total_seconds, '.3f'):>8} | "
            f"{_fmt(ratio_s, '.1f'):>11} {_fmt(ratio_t, '.1f'):>7} {_fmt(ratio_c, '.2f'):>5}"
        )
    notes = [
        f"  {r['model']}: loads {r['loads'].status}: {r['loads'].message}"
        for r in rows
        if r["loads"].message
    ]
    notes += [
        f"  {r['model']}: exudyn {r['exudyn'].status}: {r['exudyn'].message}"
        for r in rows
        if r["exudyn"].message
    ]
    if notes:
        lines += ["notes:"] + notes
    return "\n".join(lines)


def run_checks(
    models: list[ModelSpec], quick: bool, log: Callable[[str], None]
) -> list[dict[str, Any]]:
    """Physics sanity of the Exudyn models at their start step / 4: energy drift (J, and
    relative to the largest kinetic-plus-potential swing) and the largest joint-point gap (m)."""
    from benchmarks.exudyn_models import ExudynOptions, run_exudyn

    out = []
    for model in models:
        end = model.quick_end if quick else model.end
        step = EXUDYN_START_STEP[model.name] / 4.0
        run = run_exudyn(
            model,
            ExudynOptions(
                step=step,
                end=end,
                output_step=model.output_step,
                linear_solver=EXUDYN_SOLVER,
                check=True,
            ),
        )
        assert run.energy is not None and run.joint_gap is not None
        drift = float(np.max(np.abs(run.energy - run.energy[0])))
        entry = {
            "model": model.name,
            "step": step,
            "end": end,
            "energy_initial": float(run.energy[0]),
            "energy_drift": drift,
            "energy_final_change": float(run.energy[-1] - run.energy[0]),
            "joint_gap_max": float(run.joint_gap.max()),
            "solve_seconds": run.solve_seconds,
        }
        log(
            f"  check {model.name}: step {step:g} s, energy E0 = {entry['energy_initial']:.6g} J, "
            f"max |E - E0| = {drift:.3g} J, E(end) - E0 = {entry['energy_final_change']:.3g} J, "
            f"largest joint gap {entry['joint_gap_max']:.2g} m"
        )
        out.append(entry)
    return out


def main(argv: list[str] | None = None) -> int:
    """Command line of the benchmark suite; returns the process exit code.

    0: done (a `loads` engine that cannot be imported yet is reported, not an error);
    1: a code failed on a model or missed the accuracy target; 2: Exudyn is missing.
    """
    parser = argparse.ArgumentParser(
        prog="loads bench",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--quick", action="store_true", help="shorter end times, one timed repeat")
    parser.add_argument(
        "--json", type=Path, metavar="FILE", help="write the figures and machine info here"
    )
    parser.add_argument(
        "--models",
        default=None,
        help="comma-separated model names (default: the five rigid models; with --kinds the kinds)",
    )
    parser.add_argument(
        "--kinds",
        action="store_true",
        help="the models of benchmarks.kinds instead: contact, events, friction, hydraulics "
        f"({', '.join(m.name for m in kind_models())})",
    )
    parser.add_argument(
        "--tol",
        type=float,
        default=1e-4,
        help="error target relative to the output's range (default 1e-4)",
    )
    parser.add_argument(
        "--repeat", type=int, default=None, help="timed repeats, best kept (default 3, quick 1)"
    )
    parser.add_argument("--exudyn-only", action="store_true", help="skip the loads side")
    parser.add_argument(
        "--check", action="store_true", help="also check Exudyn energy conservation and joint gaps"
    )
    parser.add_argument(
        "--make-reference",
        action="store_true",
        help="recompute the stored Exudyn reference solutions first",
    )
    args = parser.parse_args(argv)
    log = lambda text: print(text, flush=True)  # noqa: E731

    try:
        default = kind_models() if args.kinds else all_models()
        names = args.models.split(",") if args.models else [m.name for m in default]
        models = [model_by_name(n.strip()) for n in names if n.strip()]
    except KeyError as exc:
        print(f"error: {exc.args[0]}", file=sys.stderr)
        return 2
    repeat = args.repeat if args.repeat is not None else (1 if args.quick else 3)

    from benchmarks.exudyn_models import ExudynMissing, exudyn_module_name, import_exudyn

    try:
        import_exudyn()
    except ExudynMissing as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2

    info = machine_info()
    info["exudyn_module"] = exudyn_module_name()
    log(
        f"machine: {info['cpu']}, {info['cores']} cores, "
        f"Python {info['python']}, numpy {info['numpy']}, "
        f"Exudyn {info['exudyn']} ({info['exudyn_module']}), loads {info['loads']}"
    )

    checks = run_checks(models, args.quick, log) if args.check else []
    rows: list[dict[str, Any]] = []
    exit_code = 0
    for model in models:
        end = model.quick_end if args.quick else model.end
        log(f"{model.name}: {model.title}; simulated {end:g} s")
        ref = None if args.make_reference else load_reference(model)
        if ref is None or ref.meta.get("end", 0.0) < end - 1e-9:
            made_by = (
                make_loads_reference
                if model.name in LOADS_REFERENCE_TOLERANCE
                else (make_reference)
            )
            ref = made_by(model, log)
        ref = ref.until(end)
        ex = bench_exudyn(model, end, ref, args.tol, repeat, log)
        lo = (
            CodeResult(status="skipped")
            if args.exudyn_only
            else bench_loads(model, end, ref, args.tol, repeat, log)
        )
        if ex.status != "ok" or lo.status == "failed":
            exit_code = 1
        row: dict[str, Any] = {
            "model": model.name,
            "title": model.title,
            "end": end,
            "main": list(model.main),
            "exudyn": ex,
            "loads": lo,
            "reference": {
                k: ref.meta.get(k) for k in ("code", "exudyn", "step", "self_error", "integrator")
            },
        }
        if ex.status == "ok" and lo.status == "ok":
            row["ratio"] = {
                "solve": lo.solve_seconds / ex.solve_seconds,
                "total": lo.total_seconds / ex.total_seconds,
                "cpu": _cpu_ratio(lo, ex),
            }
        rows.append(row)

    print()
    print(format_table(rows, args.tol))
    flexible = None
    if args.kinds and args.models is None and not args.exudyn_only:
        from benchmarks.flexible_compare import compare_all, format_rows

        log("")
        flexible = compare_all(repeat, log)
        print(format_rows(flexible))
        if any("ratio_cpu" not in row for row in flexible):
            exit_code = 1
    if args.json:
        payload = {
            "machine": info,
            "settings": {
                "tol": args.tol,
                "quick": args.quick,
                "repeat": repeat,
                "exudyn": {
                    "integrator": "generalized-alpha (index 3), fixed step",
                    "spectral_radius": 0.9,
                    "linear_solver": EXUDYN_SOLVER,
                    "newton": "Exudyn default (modified Newton, rel. tol 1e-8)",
                },
                "error": "max_t |y - y_ref| (norm over main columns) / range of y_ref",
            },
            "checks": checks,
            "flexible": flexible,
            "models": [
                {
                    **{k: v for k, v in r.items() if k not in ("exudyn", "loads")},
                    "exudyn": r["exudyn"].as_dict(),
                    "loads": r["loads"].as_dict(),
                }
                for r in rows
            ],
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(payload, indent=2), encoding="utf-8")
        log(f"figures written to {args.json}")
    return exit_code


if __name__ == "__main__":
    raise SystemExit(main())
