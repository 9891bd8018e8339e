"""The error floor of IFToMM A01 (issue 35): one suspect varied at a time on the pendulum at
tight tolerances, its energy's trend (m g L per s, a least-squares slope over the run) and
the bob's largest position error against the closed form (m; benchmarks/error_table_long).

The runs take the Python steps (`compiled="python"`), whose Newton test reads the round-off
floor from `mechlib.solvers.genalpha.kernels.ROUNDOFF` at each call, so that a suspect is
varied without compiling the kernels again:

- `roundoff=F`: Newton's acceleration test floored at F eps of q (rules.ROUNDOFF);
- `kappa=K`: Newton's estimated remainder within K (instead of rules.NEWTON_KAPPA);
- `no-noise`: stagnating increments count as round-off only below NOISE_POSITION of the
  position tolerance (rules.POSITION_ROUNDOFF off);
- `scaled-a`: the pseudo-acceleration scaled to a longer step too (rules.pseudo_acceleration);
- `restart-a`: the pseudo-acceleration restarted from the accelerations at each change;
- `rho=R`: generalized-alpha's rho_inf.

    python -m benchmarks.a01_floor [SUSPECT] [--end 20] [--tolerances 2.4e-10,3e-11] [-o FILE]

(`base`: the engine as it is; one suspect per call, the patches stay in the process.)
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.error_table import _with
from benchmarks.error_table_long import A01, CASES
from benchmarks.rows import stream_rows
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case
from mechlib.solvers.genalpha import kernels, rules

G = 9.81  # m/s^2
EPS = float(np.finfo(float).eps)


def _newton_kappa(kappa: float) -> Callable[[float, float, bool], bool]:
    def converged(eta: float, size: float, noise: bool) -> bool:
        return (eta * size <= kappa and size < 1.0) or size < rules.NEWTON_FLOOR or noise

    return converged


def _no_noise(size: float, prev: float, position_size: float, tol: float) -> bool:
    stagnant = prev != math.inf and size > rules.STAGNANT * prev
    return stagnant and position_size <= rules.NOISE_POSITION


def _scaled(qdd: np.ndarray, a: np.ndarray, ratio: float) -> np.ndarray:
    return qdd + ratio * (a - qdd)


def _restarted(qdd: np.ndarray, a: np.ndarray, ratio: float) -> np.ndarray:
    return qdd.copy()


def _apply(suspect: str) -> dict[str, Any]:
    """Patch the Python path for `suspect`; the analysis fields it changes."""
    name, _, value = suspect.partition("=")
    if name == "roundoff":
        kernels.ROUNDOFF = np.float64(float(value) * EPS)
    elif name == "kappa":
        rules.converged = _newton_kappa(float(value))  # type: ignore[assignment]
    elif name == "no-noise":
        rules.is_noise = _no_noise
    elif name == "scaled-a":
        rules.pseudo_acceleration = _scaled
    elif name == "restart-a":
        rules.pseudo_acceleration = _restarted
    elif name == "rho":
        return {"rho_inf": float(value)}
    elif name != "base":
        raise SystemExit(f"unknown suspect {suspect!r}")
    return {}


def measured(suspect: str, end: float, tolerance: float, fields: dict[str, Any]) -> dict:
    """A01 over `end` s at `tolerance`, Python steps, with the suspect's fields."""
    file = CASES["A01"][0]
    built = build_run(_with(load_case(file), end=end, tolerance=tolerance, accuracy="off"))
    analysis = dataclasses.replace(
        built.analysis, compiled="python", max_steps=10_000_000, **fields
    )
    started = time.process_time()
    run = built.solve(analysis)
    cpu = time.process_time() - started
    t, ch = run.time, run.channels
    theta, _ = A01.angle(t)
    bob = np.hypot(ch["bob_pos.x"] - np.cos(theta), ch["bob_pos.y"] - np.sin(theta))
    speed2 = ch["bob_vel.x"] ** 2 + ch["bob_vel.y"] ** 2
    energy = (G * ch["bob_pos.y"] + 0.5 * speed2 + 0.5e-6 * ch["rate.value"] ** 2) / G
    return {
        "suspect": suspect,
        "end_s": end,
        "tolerance": tolerance,
        "status": run.status,
        "steps": run.stats.steps,
        "rejected": run.stats.rejected_steps,
        "newton_iterations": run.stats.newton_iterations,
        "cpu_s": cpu,
        "bob_error_m": float(bob.max()),
        "energy_trend_mgl_per_s": float(np.polyfit(t, energy, 1)[0]),
        "energy_end_mgl": float(energy[-1]),
        "load_average": os.getloadavg()[0],
    }


def _rows(suspect: str, end: float, tolerances: list[float]) -> Iterator[dict]:
    """The suspect's rows, one per tolerance (a process per suspect: the patches stay)."""
    fields = _apply(suspect)
    for tolerance in tolerances:
        yield measured(suspect, end, tolerance, fields)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("suspect", nargs="?", default="base")
    parser.add_argument("--end", type=float, default=20.0)
    parser.add_argument("--tolerances", default="2.4e-10,3e-11")
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    tolerances = [float(x) for x in args.tolerances.split(",")]
    stream_rows(_rows(args.suspect, args.end, tolerances), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
