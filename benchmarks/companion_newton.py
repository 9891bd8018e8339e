"""The grid companion's Newton iterations under other predictors and matrix rules (issue 35
item 2: what a companion step costs). Per case of benchmarks/companion_cost.py: the run on
the Python steps (`compiled: python`, the reference the compiled paths follow to round-off),
its states at each accepted step's end kept, then its grid companion
(loadcases.run.companion.on_grid) with the Newton start and matrix rules as they are and
with each variant, and of each: steps, splits, Newton iterations, factorisations and the
largest relative change of the estimate (Richardson's history and peak of every request,
loadcases.run.global_error.request_errors) against the companion as it is.

Variants (the Python path patched for the companion only; nothing here changes the code).
As it is, the grid's steps start from the error-controlled steps' predictor (kernels.predict:
the acceleration kept); then:
- `swing`: from kernels.predict_swing (the integrator's acceleration's step-to-step swing
  about the consistent one reversed, its trend added), the grid's predictor from branch
  comppred (2026-11-29) until 2026-11-30, dropped: IFToMM A01's companion over 2000 s gained
  energy from it (docs/performance.md);
- `run's change`: Newton starts at the companion's state plus the run's change over the
  pair, q(t_k+2) - q(t_k) (qd, qdd by the Newmark relations of that q), and the run's
  change of the integrator's multipliers;
- `run's trend, swing`: the swing reversed plus the run's change of the consistent
  acceleration over the pair, and of the multipliers;
- `refresh`: the iteration matrix factored anew at every step (steps twice as long turn
  the bodies twice as far on one matrix);
- `keep`: a step is slow (a fresh matrix for the next) only above 5 iterations, not 3.

    python -m benchmarks.companion_newton [--case NAME ...] [-o FILE]
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.companion_cost import CASES, built, work
from benchmarks.rows import stream_rows
from loadcases.run.companion import on_grid, order, output_interval
from loadcases.run.global_error import request_errors
from mechlib.solvers.genalpha import integrator as gi
from mechlib.solvers.genalpha import stepper as gs

#: a run's state at a step end: q, the integrator's multipliers and acceleration, the
#: consistent acceleration
Kept = dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]]


@contextlib.contextmanager
def _patched(owner: Any, name: str, make: Callable[[Any], Any]) -> Iterator[None]:
    """owner.name replaced by make(the original) while the block runs."""
    original = getattr(owner, name)
    setattr(owner, name, make(original))
    try:
        yield
    finally:
        setattr(owner, name, original)


def _keeping(kept: Kept) -> contextlib.ExitStack:
    """The stepper's accepted states (and its first) recorded into `kept` by time."""

    def record(s: Any) -> None:
        a = gs._alpha(s)
        kept[a.t] = (a.q.copy(), a.raw_lam.copy(), a.qdd.copy())

    def settle(original: Any) -> Any:
        def settled(self: Any, state: Any) -> Any:
            out = original(self, state)
            record(state)
            return out

        return settled

    def init(original: Any) -> Any:
        def started(self: Any, t: float, q0: Any, qd0: Any) -> Any:
            s = original(self, t, q0, qd0)
            record(s)
            return s

        return started

    stack = contextlib.ExitStack()
    stack.enter_context(_patched(gs.GeneralizedAlphaStepper, "settle", settle))
    stack.enter_context(_patched(gs.GeneralizedAlphaStepper, "init", init))
    return stack


def _newmark(c: Any, h: float, q: Any, qd: Any, qdd: Any, a: Any, guess: Any) -> tuple:
    """(q1, qd1, qdd1) of a step h (s) whose acceleration is `guess`, by generalized-alpha's
    relations (kernels.predict_swing's)."""
    a1 = ((1.0 - c.alpha_f) * guess + c.alpha_f * qdd - c.alpha_m * a) / (1.0 - c.alpha_m)
    q1 = q + h * qd + h * h * ((0.5 - c.beta) * a + c.beta * a1)
    return q1, qd + h * ((1.0 - c.gamma) * a + c.gamma * a1), guess


def _predictor(variant: str, kept: Kept) -> Callable[[Any], Any]:
    """Integrator._predicted as the variant starts Newton (a step whose ends are not both
    among the run's kept states: as it is)."""

    def make(original: Any) -> Any:
        def predicted(self, t, h, q, qd, qdd, a, lam, cons=None):
            bp, gp, q1, qd1, qdd1, lam1, t1, fresh = original(self, t, h, q, qd, qdd, a, lam, cons)
            c, known = self.c, t in kept and t + h in kept
            if known and variant == "run's trend, swing":
                guess = 2.0 * cons - qdd + kept[t1][2] - kept[t][2]
                q1, qd1, qdd1 = _newmark(c, h, q, qd, qdd, a, guess)
            if known and variant == "run's change":
                dq = q + kept[t1][0] - kept[t][0] - q1
                q1, qd1, qdd1 = q1 + dq, qd1 + gp * dq, qdd1 + bp * dq
            if known and kept[t1][1].shape == lam.shape:
                lam1 = lam + kept[t1][1] - kept[t][1]
            return bp, gp, q1, qd1, qdd1, lam1, t1, fresh

        return predicted

    return make


def _swing(original: Any) -> Any:
    """Integrator.__init__ with the grid's predictor kernels.predict_swing (swings on)."""

    def made(self: Any, *args: Any) -> None:
        original(self, *args)
        self.swings = True
        self.past = np.zeros((2, self.system.nq))

    return made


def _variant(variant: str, kept: Kept) -> contextlib.AbstractContextManager:
    """The Python path patched as `variant` says (as it is: nothing)."""
    if variant == "swing":
        return _patched(gi.Integrator, "__init__", _swing)
    if variant == "refresh":
        return _patched(gi.Integrator, "_rebuilds", lambda original: lambda self, h, fresh: True)
    if variant == "keep":
        return _patched(
            gi.Integrator,
            "converged_in",
            lambda original: lambda self, it, tried: original(self, 0 if it <= 5 else it, tried),
        )
    if variant == "as is":
        return contextlib.nullcontext()
    return _patched(gi.Integrator, "_predicted", _predictor(variant, kept))


VARIANTS = ("as is", "swing", "run's change", "run's trend, swing", "refresh", "keep")


def _change(before: dict, after: dict) -> float:
    """The largest relative change of the estimate's histories and peaks."""
    worst = 0.0
    for name, was in before.items():
        for field in ("history", "peak"):
            x, y = getattr(was, field), getattr(after[name], field)
            if x > 0.0:
                worst = max(worst, abs(y / x - 1.0))
    return worst


def case_row(name: str) -> dict[str, Any]:
    """The run's and each variant's companion's work, and the estimate's change."""
    b = built(name)
    analysis = dataclasses.replace(b.analysis, compiled="python")
    kept: Kept = {}
    with _keeping(kept):
        run = b.solve(analysis, checks=False)
    companion = on_grid(analysis, run)
    assert companion is not None, f"{name}: no grid companion"
    p = order(analysis.integrator)
    row: dict[str, Any] = {"case": name, "run": _work(run)}
    base: dict = {}
    for variant in VARIANTS:
        with _variant(variant, kept):
            solved = b.solve(companion, checks=False)
        interval = output_interval(analysis, run)
        errors = request_errors(run, solved, p, interval=interval) if solved.ok else {}
        base = base or errors
        row[variant] = {**_work(solved), "estimate change": round(_change(base, errors), 5)}
    return row


def _work(solution: Any) -> dict[str, Any]:
    """The solve's status and its work (`companion_cost.work`: a grid companion's splits
    are its rejected steps)."""
    return {"status": solution.status, **work(solution)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", action="append", choices=list(CASES))
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    names = args.case or [n for n in CASES if n != "A05"]
    stream_rows((case_row(n) for n in names), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
