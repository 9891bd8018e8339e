"""Flexible-body benchmark (issue 40): steps, rejected steps and CPU of `loads` on two
flexible models, each at a bench tolerance and against a tight run of its own.

- `kane`: Kane, Ryan & Banerjee's spin-up beam (J. Guid. Control Dyn. 10 (1987) 139): a
  10 m beam (E I = 1.4e4 N m^2, rho A = 1.2 kg/m, 6 Euler-Bernoulli elements, 4 modes held
  at the root) on a hub turned by omega(t) = (W/T)(t - T/(2 pi) sin(2 pi t/T)) up to
  W = 4 rad/s at T = 15 s, for 20 s; with and without geometric stiffening (the stiffened
  run should take no more steps: issue 40). Compared: the tip's lag in the hub frame (m).
- `slider_crank`: a slider-crank with a flexible steel rod (crank 0.15 m, rod 0.30 m of
  8 x 8 mm, 20 elements, 34 Craig-Bampton modes of the rod held at both ends, 460 Hz to
  40 kHz), the crank driven at 150 rad/s from its design position (along +y, 90 deg
  from the slider's line), for 0.1 s. Compared: the slider's x.

Error = max |y - y_ref| over the output times / the reference's range. The Exudyn sides of
the unstiffened Kane beam and of the slider-crank are `benchmarks.flexible_exudyn` and
`benchmarks.flexible_exudyn_crank` (ObjectFFRFreducedOrder given these modes and inertia
invariants; no geometric stiffening there), compared at equal accuracy by
`benchmarks.flexible_compare` in `loads bench --kinds`.
Run: `.venv/bin/python -m benchmarks.flexible [--json FILE]`. SI units.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import mechlib
from mechlib.flexible.beam import Material, Section, assemble_beams
from mechlib.flexible.craig_bampton import craig_bampton
from mechlib.flexible.fe_model import FEModel

__all__ = [
    "CRANK_PIN",
    "CRANK_SPEED",
    "ROD_MODES",
    "SLIDER_PIN",
    "SpinUp",
    "flexible_slider_crank",
    "kane_beam",
    "main",
    "slider_crank_rod",
    "spin_up_beam",
]

RESULTS = Path(__file__).parent / "results" / "flexible.json"
BENCH_TOLERANCE, TIGHT_TOLERANCE = 1e-5, 1e-8


@dataclass(frozen=True)
class SpinUp:
    """Kane's hub angle (rad): rate `top` (rad/s) reached at `ramp` (s)."""

    top: float = 4.0
    ramp: float = 15.0

    def value(self, t: float) -> float:
        w, T = self.top, self.ramp
        if t < T:
            return (
                w / T * (t * t / 2 + (T / (2 * math.pi)) ** 2 * (math.cos(2 * math.pi * t / T) - 1))
            )
        return w * (t - T / 2)

    def rate(self, t: float) -> float:
        w, T = self.top, self.ramp
        return w / T * (t - T / (2 * math.pi) * math.sin(2 * math.pi * t / T)) if t < T else w

    def accel(self, t: float) -> float:
        w, T = self.top, self.ramp
        return w / T * (1 - math.cos(2 * math.pi * t / T)) if t < T else 0.0


@dataclass(frozen=True)
class Drive:
    """Crank angle (rad) from `start` at `speed` (rad/s)."""

    start: float
    speed: float

    def value(self, t: float) -> float:
        return self.start + self.speed * t

    def rate(self, t: float) -> float:
        return self.speed

    def accel(self, t: float) -> float:
        return 0.0


KANE_LENGTH, KANE_ELEMENTS, KANE_MODES = 10.0, 6, 4  # m, beam elements, Craig-Bampton modes


def kane_beam() -> FEModel:
    """Kane's beam as an FE model: 10 m, E I = 1.4e4 N m^2, rho A = 1.2 kg/m, 6 elements,
    root node 0 the interface."""
    xyz = np.outer(np.linspace(0.0, KANE_LENGTH, KANE_ELEMENTS + 1), [1.0, 0.0, 0.0])
    section = Section(4e-4, 2e-7, 2e-7, 4e-7, None, None)
    aluminium = Material(7e10, 0.3, 3000.0)
    beams = [(i, i + 1, section, aluminium, (0.0, 1.0, 0.0)) for i in range(KANE_ELEMENTS)]
    return assemble_beams(xyz, beams, interface=(0,))


def spin_up_beam(stiffening: bool) -> mechlib.Mechanism:
    """Kane's beam on its hub (revolute about z at the root, driven by `SpinUp`)."""
    length, elements = KANE_LENGTH, KANE_ELEMENTS
    comp = craig_bampton(
        kane_beam(),
        damping=0.0,
        fixed_interface_modes=KANE_MODES,
        keep_nodes=(elements,),
        stiffening=stiffening,
    )
    m = mechlib.Mechanism(name="spin-up-beam")
    m.add_flexible_body("beam", comp)
    m.add_joint("hub", "revolute", bodies=("beam", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    m.add_motion("spin", joint="hub", function=SpinUp())
    m.add_point("tip", body="beam", at=(length, 0, 0))
    return m


CRANK, ROD, ROD_ELEMENTS = 0.15, 0.30, 20  # m, m, beam elements of the flexible rod
CRANK_PIN = np.array([0.0, CRANK, 0.0])  # m, the rod's end on the crank at t = 0
SLIDER_PIN = np.array([math.sqrt(ROD**2 - CRANK**2), 0.0, 0.0])  # m, its end on the slider
CRANK_SPEED = 150.0  # rad/s
ROD_MODES = 34  # Craig-Bampton modes of the rod, held at both ends


def slider_crank_rod() -> FEModel:
    """The flexible rod's FE model: steel, 8 x 8 mm, 20 beam elements from CRANK_PIN
    (node 0) to SLIDER_PIN (node 20), both interface nodes."""
    a, b = CRANK_PIN, SLIDER_PIN
    xyz = a + np.outer(np.linspace(0.0, 1.0, ROD_ELEMENTS + 1), b - a)
    steel, section = Material(2e11, 0.3, 7870.0), Section.rectangle(0.008, 0.008, False)
    beams = [(i, i + 1, section, steel, (0, 0, 1)) for i in range(ROD_ELEMENTS)]
    return assemble_beams(xyz, beams, interface=(0, ROD_ELEMENTS))


def flexible_slider_crank() -> mechlib.Mechanism:
    """The slider-crank with a flexible rod (module docstring)."""
    crank, a, b = CRANK, CRANK_PIN, SLIDER_PIN
    comp = craig_bampton(
        slider_crank_rod(), modes=ROD_MODES, fixed_interface_modes=ROD_MODES, damping=0.0
    )
    m = mechlib.Mechanism(name="flexible-slider-crank")
    m.add_body("crank", mass=0.38, cm=(0.0, crank / 2, 0.0), inertia=[7.1e-4, 1e-5, 7.1e-4])
    m.add_flexible_body("rod", comp)
    m.add_body("slider", mass=0.76, cm=tuple(b), inertia=[1e-4] * 3)
    m.add_joint("A", "revolute", bodies=("crank", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    m.add_joint("B", "spherical", bodies=("rod", "crank"), at=tuple(a))
    m.add_joint(
        "C", "universal", bodies=("rod", "slider"), at=tuple(b), axes=((0, 0, 1), (0, 1, 0))
    )
    m.add_joint("D", "prismatic", bodies=("slider", "ground"), at=tuple(b), axis=(1, 0, 0))
    m.add_motion("drive", joint="A", function=Drive(0.0, CRANK_SPEED))
    m.add_point("slider", body="slider", at=tuple(b))
    return m


def _kane_lag(sol: mechlib.Solution) -> np.ndarray:
    angle = np.array([SpinUp().value(t) for t in sol.time])
    return -np.sin(angle) * sol.channels["tip.x"] + np.cos(angle) * sol.channels["tip.y"]


def _run(name: str, tolerance: float) -> tuple[mechlib.Solution, np.ndarray, float]:
    """(solution, compared signal, CPU s) of model `name` at `tolerance`."""
    if name.startswith("kane"):
        mech, end, step = spin_up_beam(name == "kane_stiffened"), 20.0, 0.1
        requests = [mechlib.PointKinematics("tip", "tip")]
    else:
        mech, end, step = flexible_slider_crank(), 0.1, 1e-3
        requests = [mechlib.PointKinematics("slider", "slider")]
    start = time.process_time()
    sol = mechlib.solve(
        mech, mechlib.Dynamic(end=end, step=step, tolerance=tolerance), requests=requests
    )
    cpu = time.process_time() - start
    assert sol.ok, sol.message
    signal = _kane_lag(sol) if name.startswith("kane") else sol.channels["slider.x"]
    return sol, np.asarray(signal), cpu


def bench(name: str, repeat: int) -> dict[str, Any]:
    """One model: the bench run (best CPU of `repeat`) and its error against the tight run."""
    reference = _run(name, TIGHT_TOLERANCE)[1]
    runs = [_run(name, BENCH_TOLERANCE) for _ in range(repeat)]
    sol, signal, _ = runs[0]
    span = float(reference.max() - reference.min())
    return {
        "model": name,
        "tolerance": BENCH_TOLERANCE,
        "steps": sol.stats.steps,
        "rejected_steps": sol.stats.rejected_steps,
        "newton_iterations": sol.stats.newton_iterations,
        "cpu_seconds": min(cpu for *_, cpu in runs),
        "error": float(np.abs(signal - reference).max()) / span,
        "reference_tolerance": TIGHT_TOLERANCE,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, default=RESULTS)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args(argv)
    from benchmarks.suite import machine_info

    rows = [bench(name, args.repeat) for name in ("kane_stiffened", "kane_plain", "slider_crank")]
    print(f"{'model':16} {'steps':>6} {'rejected':>8} {'CPU s':>7} {'error':>9}")
    for r in rows:
        print(
            f"{r['model']:16} {r['steps']:6d} {r['rejected_steps']:8d} "
            f"{r['cpu_seconds']:7.2f} {r['error']:9.2e}"
        )
    args.json.write_text(json.dumps({"machine": machine_info(), "rows": rows}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
