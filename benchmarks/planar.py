"""Planar four-bar chains: `plane:` (3 coordinates per body) against the same model in 3-D.

The chain is fourbar10's geometry (benchmarks.models) with four revolutes per loop, all about
the plane's normal: links k = 0..N hang from ground pivots G_k = 0.2 k e1 (0.15 m along -e2,
0.2 kg), coupler k (0.1 kg) joins S_k = G_k + (0.03, -0.15) on link k to U_(k+1) =
G_(k+1) + (0, -0.15) on link k+1. In 3-D each loop has 3 redundant equations (issue 17: a
40-loop chain has 120), which the 3-D run drops (`redundant: drop`); the planar model has
none. Link 0 starts at 2 rad/s, gravity along -e2; generalized-alpha at the default
tolerance. Reports wall and CPU seconds (check + solve; CPU is the measure on a shared
machine), steps, equations, redundant equations and
the largest difference of the last rocker's angle.

    python -m benchmarks.planar [--loops 40] [--end 2] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from typing import Any

import numpy as np

import mechlib as ml
from benchmarks.suite import machine_info
from mechlib.model.plane import plane_axes

PITCH, LINK, OFFSET = 0.2, 0.15, 0.03  # m
LINK_MASS, COUPLER_MASS = 0.2, 0.1  # kg
LINK_INERTIA = (3.75e-4, 1e-5, 3.75e-4)  # kg m^2, link axes (e1, e2, n)
COUPLER_INERTIA = (5e-6, 2.4e-4, 2.4e-4)
RATE = 2.0  # rad/s, link 0 at the start


def fourbar_chain(loops: int, *, plane: str = "xy", planar: bool = True) -> ml.Mechanism:
    """`loops` R-R-R-R four-bar loops in series, laid out in `plane`; a planar mechanism
    (`Mechanism.plane`) when `planar`, else the same model in 3-D."""
    e1, e2, n = plane_axes(plane)
    rot = np.column_stack([e1, e2, n])
    m = ml.Mechanism(
        name=f"chain{loops}", gravity=tuple(-9.81 * e2), plane=plane if planar else None
    )

    def at(a: float, b: float) -> tuple:
        return tuple(a * e1 + b * e2)

    def inertia(diagonal) -> np.ndarray:
        return rot @ np.diag(diagonal) @ rot.T

    for k in range(loops + 1):
        m.add_body(
            f"link{k}", mass=LINK_MASS, cm=at(PITCH * k, -LINK / 2), inertia=inertia(LINK_INERTIA)
        )
        m.add_joint(
            f"r{k}", "revolute", bodies=(f"link{k}", "ground"), at=at(PITCH * k, 0.0), axis=tuple(n)
        )
    for k in range(loops):
        s, u = PITCH * k + OFFSET, PITCH * (k + 1)
        m.add_body(
            f"coupler{k}",
            mass=COUPLER_MASS,
            cm=at(0.5 * (s + u), -LINK),
            inertia=inertia(COUPLER_INERTIA),
        )
        m.add_joint(
            f"s{k}", "revolute", bodies=(f"coupler{k}", f"link{k}"), at=at(s, -LINK), axis=tuple(n)
        )
        m.add_joint(
            f"u{k}",
            "revolute",
            bodies=(f"link{k + 1}", f"coupler{k}"),
            at=at(u, -LINK),
            axis=tuple(n),
        )
    return m


def run(loops: int, end: float, planar: bool) -> dict[str, Any]:
    """One dynamic run: wall s (check + solve), steps, equations, redundant, last angle."""
    mechanism = fourbar_chain(loops, planar=planar)
    start, cpu = time.perf_counter(), time.process_time()
    check = ml.inspect_mechanism(mechanism)
    solution = ml.solve(
        mechanism,
        ml.Dynamic(end=end, step=0.01),
        requests=[ml.JointCoordinate("rocker", f"r{loops}")],
        initial=[ml.InitialValue(joint="r0", rate=RATE)],
        redundant="drop",
        throw=False,
    )
    return {
        "model": "planar" if planar else "3-D",
        "wall_s": time.perf_counter() - start,
        "cpu_s": time.process_time() - cpu,
        "status": solution.status,
        "steps": solution.stats.steps,
        "bodies": check.bodies,
        "equations": check.equations,
        "redundant": len(check.redundant),
        "rocker": solution.channels["rocker.value"],
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loops", type=int, default=40)
    parser.add_argument("--end", type=float, default=2.0, help="s of motion")
    parser.add_argument("--json", default=None, help="write the figures here")
    args = parser.parse_args(argv)
    run(1, 0.05, True), run(1, 0.05, False)  # compile (or load) the kernels first
    rows = [run(args.loops, args.end, planar) for planar in (True, False)]
    gap = float(np.abs(rows[0]["rocker"] - rows[1]["rocker"]).max())
    print(f"{args.loops} loops, {args.end:g} s of motion, generalized-alpha, tolerance 1e-6")
    for r in rows:
        print(
            f"  {r['model']:6s} {r['wall_s']:8.2f} s wall {r['cpu_s']:8.2f} s CPU "
            f"{r['steps']:6d} steps  "
            f"{r['equations']:5d} equations  {r['redundant']:4d} redundant  {r['status']}"
        )
    speedup = rows[1]["cpu_s"] / rows[0]["cpu_s"]
    print(f"  speed-up {speedup:.1f}x (CPU); the last rocker's angle differs by {gap:.2e} rad")
    if args.json:
        info = {
            "machine": machine_info(),
            "load_average": os.getloadavg(),
            "loops": args.loops,
            "end": args.end,
            "angle_difference_rad": gap,
            "runs": [{k: v for k, v in r.items() if k != "rocker"} for r in rows],
        }
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(info, f, indent=2)
    return 0 if all(r["status"] == "ok" for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
