"""The work of generalized-alpha's iteration-matrix refresh rule (mechlib.solvers.genalpha.
rules.slow) on each kind of model (issue 35): the campaign's slider-crank as written (grid
companion included), the models of other kinds (`loads bench --kinds`: contact, events,
friction, hydraulics; their committed cases, the estimate off as the bench runs them), Kane's
spin-up beam and the flexible slider-crank (benchmarks.flexible at its bench tolerance), and
the library's IFToMM A01 over 10 s, A05, the door let go and the servo-actuator. Per case:
accepted and rejected steps, Newton failures (steps Newton could not take), Newton
iterations, factorisations and the solve's CPU (best of `--repeat`, ms). With `--save DIR`
each case's channels go to DIR/<case>.npz; `--compare DIR` prints the largest change of
each case's channels against those, relative to the channel's range.

`--rules` instead counts, without recompiling a kernel, what other refresh rules would do
(`RULES`: by the iterations or by Newton's rate eta at convergence) on the campaign case and
A01 over 10 s: their steps taken in Python (the same iterations as the compiled runs'),
`Integrator.converged_in`'s rule replaced; step attempts, Newton iterations, iteration
matrices factored and their modelled cost (`ITERATION_US`, `REFACTOR_US`: the campaign's
parts, benchmarks.step_kernels).

    python -m benchmarks.refresh_rule [--repeat 3] [--cases a,b] [--save DIR] [--compare DIR]
    python -m benchmarks.refresh_rule --rules
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.solvers.genalpha import rules
from mechlib.solvers.genalpha import run as genalpha_run
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.solvers.genalpha.stepper import GeneralizedAlphaStepper

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "benchmarks" / "models"
LIBRARY = ROOT / "loadcases" / "library"

#: name -> (case file, accuracy estimate kept as the case writes it)
CASES: dict[str, tuple[Path, bool]] = {
    "campaign slider-crank": (MODELS / "slider_crank.case.yaml", True),
    "socket rattle": (MODELS / "socket_rattle.case.yaml", False),
    "flap latches": (MODELS / "flap_latches.case.yaml", False),
    "four-bar friction": (MODELS / "fourbar_friction.case.yaml", False),
    "hydraulic ram": (MODELS / "hydraulic_ram.case.yaml", False),
    "A01 10 s": (LIBRARY / "verification/hard/iftomm_a01_pendulum.case.yaml", True),
    "A05": (LIBRARY / "verification/hard/iftomm_a05_flyball.case.yaml", True),
    "door let go": (LIBRARY / "door/lifting_inner_let_go.case.yaml", True),
    "servo-actuator": (LIBRARY / "verification/elements/servo_actuator.case.yaml", True),
}
FLEXIBLE = ("kane_plain", "slider_crank")

#: refresh rules counted by `--rules`: (iterations, Newton's rate eta at convergence) -> the
#: next step factors a fresh matrix
RULES: dict[str, Callable[[int, float], bool]] = {
    "iterations > 3 (rules.slow)": lambda it, eta: it > 3,
    "iterations > 4": lambda it, eta: it > 4,
    "eta > 1e-2": lambda it, eta: eta > 1e-2,
    "eta > 3e-2": lambda it, eta: eta > 3e-2,
    "eta > 1e-1": lambda it, eta: eta > 1e-1,
    "iterations > 3, eta > 1e-2": lambda it, eta: it > 3 and eta > 1e-2,
}
RULE_CASES = ("campaign slider-crank", "A01 10 s")
ITERATION_US, REFACTOR_US = 2.9, 9.9  # the campaign's iteration and refactorisation, us


def _counted(solve: Callable[[], Any]) -> tuple[Any, int]:
    """(solve's result, the Newton failures it met: steps Newton could not take)."""
    failures = [0]
    original = GeneralizedAlphaStepper.newton_failed

    def counted(self: Any, *args: Any, **kwargs: Any) -> Any:
        failures[0] += 1
        return original(self, *args, **kwargs)

    patched: Any = GeneralizedAlphaStepper
    patched.newton_failed = counted
    try:
        return solve(), failures[0]
    finally:
        patched.newton_failed = original


def _case_solver(name: str) -> Callable[[], Any]:
    """A call solving case `name`, returning (solution, stats)."""
    if name in FLEXIBLE:
        from benchmarks.flexible import BENCH_TOLERANCE, _run

        def flexible() -> Any:
            sol = _run(name, BENCH_TOLERANCE)[0]
            return sol, sol.stats

        return flexible
    path, estimate = CASES[name]
    case_file = load_case(path)
    if not estimate:
        analysis = case_file.case.analysis.model_copy(update={"accuracy": "off"})
        case = case_file.case.model_copy(update={"analysis": analysis})
        case_file = dataclasses.replace(case_file, case=case)

    def case_run() -> Any:
        outcome = run_case(case_file)
        return outcome.solution, outcome.solution.stats

    return case_run


def measure(name: str, repeat: int) -> dict[str, Any]:
    """Case `name`'s work counters (its first solve) and best CPU of `repeat` solves (ms)."""
    solve = _case_solver(name)
    best, first = float("inf"), None
    for _ in range(repeat):
        started = time.process_time()
        (solution, stats), failures = _counted(solve)
        best = min(best, time.process_time() - started)
        first = first or (solution, stats, failures)
    assert first is not None
    solution, stats, failures = first
    return {
        "case": name,
        "steps": stats.steps,
        "rejected": stats.rejected_steps,
        "newton_failures": failures,
        "iterations": stats.newton_iterations,
        "factorizations": stats.factorizations,
        "cpu_ms": 1e3 * best,
        "solution": solution,
    }


ROUND_OFF = 1e-9  # a channel whose range is below this of its request's peak: round-off


def python_counts(name: str, rule: Callable[[int, float], bool]) -> dict[str, int]:
    """Case `name` solved in Python steps with `rule` deciding a fresh matrix after each
    converged step: its step attempts, Newton iterations, matrices factored, accepted and
    rejected steps."""
    counts = {"attempts": 0, "iterations": 0, "matrices": 0}
    step, matrix, converged_in = (
        Integrator.step,
        Integrator._iteration_matrix,
        Integrator.converged_in,
    )

    def counted_matrix(self: Any, *args: Any, **kwargs: Any) -> Any:
        counts["matrices"] += 1
        return matrix(self, *args, **kwargs)

    def counted_step(self: Any, *args: Any, **kwargs: Any) -> Any:
        before = self.stats.newton_iterations
        out = step(self, *args, **kwargs)
        counts["iterations"] += self.stats.newton_iterations - before
        counts["attempts"] += 1
        return out

    def ruled(self: Any, iterations: int, tried: bool) -> None:
        eta = self.eta ** (1.0 / rules.RATE_MEMORY)  # rules.carried_rate's inverse
        slow = rule(iterations, eta)
        self.stale = slow
        self.retangent = slow and (not self.kept_first or rules.retangents(tried))

    patched: Any = Integrator
    step_run: Any = genalpha_run.StepRun
    eligible = step_run.eligible
    patched.step, patched._iteration_matrix, patched.converged_in = (
        counted_step, counted_matrix, ruled,
    )  # fmt: skip
    step_run.eligible = staticmethod(lambda stepper: False)
    try:
        stats = _case_solver(name)()[1]
    finally:
        patched.step, patched._iteration_matrix = step, matrix
        patched.converged_in, step_run.eligible = converged_in, eligible
    return {**counts, "steps": stats.steps, "rejected": stats.rejected_steps}


def print_rules() -> None:
    """`--rules`: each rule's counts on RULE_CASES."""
    print(f"{'case':22s} {'rule':28s} attempts iterations matrices rejected  model ms")
    for name in RULE_CASES:
        for label, rule in RULES.items():
            c = python_counts(name, rule)
            cost = 1e-3 * (ITERATION_US * c["iterations"] + REFACTOR_US * c["matrices"])
            print(
                f"{name:22s} {label:28s} {c['attempts']:8d} {c['iterations']:10d} "
                f"{c['matrices']:8d} {c['rejected']:8d} {cost:9.2f}",
                flush=True,
            )


def largest_change(channels: dict[str, Any], time: Any, saved: Path) -> tuple[float, str]:
    """The largest change of `channels` against the saved ones, relative to each channel's
    range (channels whose range is round-off, below ROUND_OFF of their request's peak, left
    out), and the channel; nan where the rows' times differ."""
    old = np.load(saved)
    if old["time"].shape != np.asarray(time).shape:
        return float("nan"), "rows differ"
    peaks: dict[str, float] = {}
    for column in old.files:
        request = column.rsplit(".", 1)[0]
        peaks[request] = max(peaks.get(request, 0.0), float(np.nanmax(np.abs(old[column]))))
    worst, where = 0.0, ""
    for column, values in channels.items():
        if column not in old.files or column == "time":
            continue
        before = old[column]
        span = float(np.nanmax(before) - np.nanmin(before))
        if span <= ROUND_OFF * peaks[column.rsplit(".", 1)[0]]:
            continue
        relative = float(np.nanmax(np.abs(np.asarray(values, dtype=float) - before))) / span
        if relative > worst:
            worst, where = relative, column
    return worst, where


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cases", default=",".join([*CASES, *FLEXIBLE]))
    parser.add_argument("--save", type=Path, default=None)
    parser.add_argument("--compare", type=Path, default=None)
    parser.add_argument("--rules", action="store_true", help="count other refresh rules")
    args = parser.parse_args(argv)
    if args.rules:
        print_rules()
        return 0
    print(
        f"{'case':24s} {'steps':>6s} {'rejected':>8s} {'failed':>6s} {'iterations':>10s} "
        f"{'factored':>8s} {'CPU ms':>8s} {'change/range':>12s}"
    )
    for name in args.cases.split(","):
        row = measure(name, args.repeat)
        stem = name.replace(" ", "_")
        solution = row.pop("solution")
        change = ""
        if args.compare is not None and (args.compare / f"{stem}.npz").is_file():
            worst, where = largest_change(
                solution.channels, solution.time, args.compare / f"{stem}.npz"
            )
            change = f"{worst:.2e} {where}"
        if args.save is not None:
            args.save.mkdir(parents=True, exist_ok=True)
            arrays: dict[str, Any] = {k: np.asarray(v, float) for k, v in solution.channels.items()}
            arrays["time"] = np.asarray(solution.time)
            np.savez(args.save / f"{stem}.npz", **arrays)
        print(
            f"{name:24s} {row['steps']:6d} {row['rejected']:8d} {row['newton_failures']:6d} "
            f"{row['iterations']:10d} {row['factorizations']:8d} {row['cpu_ms']:8.1f} {change}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
