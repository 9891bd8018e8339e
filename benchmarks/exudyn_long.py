"""Exudyn on the long cases of `analysis.accuracy` (issue 35 item 3): IFToMM A01 over
2000 s and A02 (N = 40, 3-D) over 20 s, built from the same data as the `loads` cases
(benchmarks.models.ModelSpec, benchmarks.exudyn_models), solved with Exudyn's fixed-step
generalized-alpha (rho_inf 0.9, as `loads`' default; Eigen's sparse solver) at steps
halved from `--step` until the largest error of the bob's (A01) or crank tip B0's (A02)
position against the closed form (benchmarks.error_table_long) is within `--error` m, or
the halvings run out; each run's solver CPU (process time of SolveDynamic), steps and
true error.

    python -m benchmarks.exudyn_long [A01|A02 ...] [--error 0.0047] [--halvings 6] [-o FILE]
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

from benchmarks.error_table_long import _a01_exact, _a02_exact
from benchmarks.exudyn_models import ExudynOptions, run_exudyn
from benchmarks.models import BodySpec, JointSpec, ModelSpec, OutputSpec, PointSpec
from benchmarks.rows import stream_rows

N = 40  # A02's loops
Z = (0.0, 0.0, 1.0)


def _diagonal(a: float, b: float, c: float) -> tuple[tuple[float, float, float], ...]:
    return ((a, 0.0, 0.0), (0.0, b, 0.0), (0.0, 0.0, c))


def _outputs(point: str, request: str) -> tuple[OutputSpec, ...]:
    """The position of `point` (m, x and y) as the columns REQUEST.x and REQUEST.y."""
    return tuple(OutputSpec(request, c, "point_position", point) for c in ("x", "y"))


def a01(end: float = 2000.0) -> ModelSpec:
    """IFToMM A01 as loadcases/library/verification/hard/iftomm_a01_pendulum.mech.yaml."""
    return ModelSpec(
        name="A01",
        title="IFToMM A01 pendulum",
        bodies=(BodySpec("ball", 1.0, (1.0, 0.0, 0.0), _diagonal(1e-6, 1e-6, 1e-6)),),
        joints=(JointSpec("hinge", "revolute", ("ball", "ground"), (0.0, 0.0, 0.0), axis=Z),),
        points=(PointSpec("bob", "ball", (1.0, 0.0, 0.0)),),
        gravity=(0.0, -9.81, 0.0),
        end=end,
        quick_end=end,
        output_step=0.01,
        outputs=_outputs("bob", "bob_pos"),
        main=("bob_pos.x", "bob_pos.y"),
    )


def a02(end: float = 20.0) -> ModelSpec:
    """IFToMM A02, N = 40, 3-D, as benchmarks/hard/a02_n_four_bar.case.yaml."""
    bar = 1.0 / 12.0
    cranks = [
        BodySpec(f"crank{i}", 1.0, (i, 0.5, 0.0), _diagonal(bar, 1e-4, bar)) for i in range(N + 1)
    ]
    couplers = [
        BodySpec(f"coupler{i}", 1.0, (i + 0.5, 1.0, 0.0), _diagonal(1e-4, bar, bar))
        for i in range(N)
    ]
    joints = [
        JointSpec(f"a{i}", "revolute", (f"crank{i}", "ground"), (i, 0.0, 0.0), axis=Z)
        for i in range(N + 1)
    ]
    for i in range(N):
        joints.append(JointSpec(f"b{i}", "spherical", (f"coupler{i}", f"crank{i}"), (i, 1.0, 0.0)))
        joints.append(
            JointSpec(f"c{i}", "universal", (f"crank{i + 1}", f"coupler{i}"), (i + 1, 1.0, 0.0),
                      axes=(Z, (0.0, 1.0, 0.0)))
        )  # fmt: skip
    return ModelSpec(
        name="A02",
        title="IFToMM A02 N-four-bar, N = 40",
        bodies=(*cranks, *couplers),
        joints=tuple(joints),
        points=(PointSpec("B0", "crank0", (0.0, 1.0, 0.0)),),
        gravity=(0.0, -9.81, 0.0),
        end=end,
        quick_end=end,
        output_step=0.05,
        outputs=_outputs("B0", "b0"),
        main=("b0.x", "b0.y"),
        initial_rate=("a0", -1.0),
    )


CASES = {"A01": (a01, "bob_pos", _a01_exact), "A02": (a02, "b0", _a02_exact)}


def measured(name: str, step: float, error: float, halvings: int) -> list[dict]:
    """Runs of `name` at steps halved from `step` (s) until the position error is within
    `error` (m)."""
    build, point, exact = CASES[name]
    model, rows = build(), []
    for _ in range(halvings + 1):
        options = ExudynOptions(step, model.end, model.output_step, linear_solver="sparse")
        try:
            run = run_exudyn(model, options)
        except RuntimeError as failure:
            rows.append({"case": name, "step": step, "failed": str(failure)})
            step /= 2.0
            continue
        truth = exact(run.time)
        true = max(
            float(np.abs(run.channels[f"{point}.{c}"] - truth[f"{point}.{c}"]).max()) for c in "xy"
        )
        rows.append(
            {
                "case": name,
                "step": step,
                "steps": run.steps,
                "solve_cpu_s": run.info["solve_cpu_seconds"],
                "true_position_error_m": true,
                "load_average": os.getloadavg()[0],
            }
        )
        if true <= error:
            break
        step /= 2.0
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=list(CASES))
    parser.add_argument("--step", type=float, default=0.01)
    parser.add_argument("--error", type=float, default=0.01, help="m")
    parser.add_argument("--halvings", type=int, default=6)
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args(argv)
    rows = (r for n in args.cases for r in measured(n, args.step, args.error, args.halvings))
    stream_rows(rows, args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
