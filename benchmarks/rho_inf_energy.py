"""Energy drift of a conservative mechanism against generalized-alpha's rho_inf (issue 35
item 3): the IFToMM A01 pendulum (1 kg at 1 m, released horizontal, period 2.4 s) over a
long run at the default tolerance, its energy E = m v^2 / 2 + m g y from the bob's
velocity and height (the ball's own inertia, 1e-6 kg m^2, adds below 1e-6 of it) against
its initial 0, as a fraction of the well depth m g L = 9.81 J; and the angle's error
against the closed form (benchmarks.error_table_long.A01).

    python -m benchmarks.rho_inf_energy [--end 200] [--rho-inf 1,0.95,0.9] [-o FILE]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from benchmarks.error_table import LIBRARY, _with
from benchmarks.error_table_long import A01
from benchmarks.rows import stream_rows
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

WELL = 9.81  # J: m g L
RHO_INF = (1.0, 0.99, 0.98, 0.95, 0.9, 0.8)


def _rhos(text: str) -> tuple[float, ...]:
    return tuple(float(x) for x in text.split(","))


def drift(rho_inf: float, end: float) -> dict[str, float | str]:
    """Energy and angle errors of A01 over `end` s at `rho_inf`, default tolerance."""
    case = load_case(LIBRARY / "hard/iftomm_a01_pendulum.case.yaml")
    started = time.process_time()
    run = run_case(_with(case, end=end, rho_inf=rho_inf, accuracy="off")).solution
    cpu = time.process_time() - started
    c = run.channels
    speed2 = c["bob_vel.x"] ** 2 + c["bob_vel.y"] ** 2
    energy = (0.5 * speed2 + 9.81 * c["bob_pos.y"]) / WELL
    theta, _ = A01.angle(run.time)
    return {
        "rho_inf": rho_inf,
        "end_s": end,
        "status": run.status,
        "steps": run.stats.steps,
        "cpu_s": cpu,
        "energy_end": float(energy[-1]),
        "energy_worst": float(energy[np.argmax(np.abs(energy))]),
        "angle_error": float(np.abs(c["angle.value"] - theta).max() / np.pi),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end", type=float, default=200.0)
    parser.add_argument("--rho-inf", type=_rhos, default=RHO_INF, help="e.g. 0.95,0.9")
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    stream_rows((drift(rho, args.end) for rho in args.rho_inf), args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
