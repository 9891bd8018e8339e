"""The estimate/true table's long cases (issue 35 item 2), against closed forms: IFToMM A01
over 2000 s and A02 (N = 40, 3-D and planar) over its published 20 s, at the engine's
default integrator and tolerance, with the estimate as a run makes it. Both mechanisms
move as one pendulum, I theta'' = -G cos theta with theta the crank's angle from +x:
A01 I = 1 + 1e-6 kg m^2, G = 9.81 N m, theta(0) = 0; A02 I = (N+1)/3 + N,
G = g ((N+1)/2 + N), theta(0) = pi/2, theta'(0) = -1 rad/s; integrated by DOP853 at
1e-12 (its error far below 1e-6 of the peak). The true error of a request: its largest
difference over the run (`history`) and that of its envelope (max and min of the run's
rows against the exact continuous ones, `peak`), of its peak |value|.

    python -m benchmarks.error_table_long [A01|A02|A02-planar ...] [--companion adaptive]
        [-o FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.companion_choice import add_companion_option, use_companion
from benchmarks.error_table import LIBRARY, _with, at_target
from benchmarks.rows import stream_rows
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

HARD = Path(__file__).resolve().parent / "hard"
G = 9.81  # m/s^2
N = 40  # A02's loops


@dataclasses.dataclass(frozen=True)
class Pendulum:
    """I theta'' = -G cos theta from theta0, rate0 (rad, rad/s)."""

    inertia: float  # kg m^2
    moment: float  # N m
    theta0: float
    rate0: float

    def angle(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(theta, theta') at times t (s), with a dense grid for the envelope."""

        def rhs(_: float, y: np.ndarray) -> list[float]:
            return [y[1], -self.moment * math.cos(y[0]) / self.inertia]

        sol = solve_ivp(
            rhs,
            (0.0, float(t[-1])),
            [self.theta0, self.rate0],
            "DOP853",
            rtol=1e-12,
            atol=1e-12,
            dense_output=True,
        )
        return sol.sol(t)


A01 = Pendulum(1.0 + 1e-6, G, 0.0, 0.0)
A02 = Pendulum((N + 1) / 3 + N, G * ((N + 1) / 2 + N), math.pi / 2, -1.0)


def _a01_exact(t: np.ndarray) -> dict[str, np.ndarray]:
    theta, rate = A01.angle(t)
    return {
        "angle.value": theta,
        "rate.value": rate,
        "bob_pos.x": np.cos(theta),
        "bob_pos.y": np.sin(theta),
    }


def _a02_exact(t: np.ndarray) -> dict[str, np.ndarray]:
    theta, _ = A02.angle(t)
    return {"crank_angle.value": theta - math.pi / 2, "b0.x": np.cos(theta), "b0.y": np.sin(theta)}


CASES: dict[str, tuple[Path, dict[str, Any], Callable[[np.ndarray], dict[str, np.ndarray]]]] = {
    "A01": (LIBRARY / "hard/iftomm_a01_pendulum.case.yaml", {"end": 2000.0}, _a01_exact),
    "A02": (HARD / "a02_n_four_bar.case.yaml", {"tolerance": None}, _a02_exact),
    "A02-planar": (HARD / "a02_n_four_bar_planar.case.yaml", {"tolerance": None}, _a02_exact),
}
FINE = 20  # exact samples per output interval: the exact envelope


def rows_of(name: str) -> list[dict[str, Any]]:
    """Per request with a closed form: estimate, true error, ratio, CPU of the run."""
    file, analysis, exact = CASES[name]
    started = time.process_time()
    outcome = run_case(_with(load_case(file), **analysis))
    cpu = time.process_time() - started
    run = outcome.solution
    truth = exact(run.time)
    fine_t = np.linspace(0.0, float(run.time[-1]), FINE * (len(run.time) - 1) + 1)
    fine = exact(fine_t)
    estimate = (outcome.checks.get("accuracy") or {}).get("estimate", {})
    worst: dict[str, list[float]] = {}
    for column, values in truth.items():
        got = run.channels[column]
        request = column.rsplit(".", 1)[0]
        peak = max(float(np.abs(got).max()), float(np.abs(fine[column]).max()))
        history = float(np.abs(got - values).max()) / peak
        envelope = max(abs(got.max() - fine[column].max()), abs(got.min() - fine[column].min()))
        w = worst.setdefault(request, [0.0, 0.0, 0.0])
        w[0], w[1] = max(w[0], history), max(w[1], envelope / peak)
    out = []
    for request, (history, envelope, _) in worst.items():
        guess = estimate.get(request, {"history": math.nan, "peak": math.nan})
        out.append(
            {
                "case": f"{name} ({run.time[-1]:g} s)",
                "request": request,
                "status": run.status,
                "steps": run.stats.steps,
                "cpu_s": cpu,
                "estimate_history": guess["history"],
                "true_history": history,
                "ratio_history": guess["history"] / history,
                "estimate_peak": guess["peak"],
                "true_peak": envelope,
                "ratio_peak": guess["peak"] / envelope if envelope else None,
                "at_target_history": at_target(guess["history"], history),
                "at_target_peak": at_target(guess["peak"], envelope),
                "observed_order": (outcome.checks.get("accuracy") or {}).get("observed_order"),
                "load_average": os.getloadavg()[0],
            }
        )
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=list(CASES))
    parser.add_argument("-o", "--output", type=Path, default=None)
    add_companion_option(parser)
    args = parser.parse_args(argv)
    use_companion(args.companion)
    stream_rows((row for name in args.cases for row in rows_of(name)), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
