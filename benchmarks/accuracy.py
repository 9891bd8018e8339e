"""Reference solutions, the error measure and the per-code result record of the suite.

Kept apart from `benchmarks.suite` so that its dataclasses belong to an importable module
(`loads bench` executes the suite under another module name).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.models import ModelSpec

__all__ = [
    "EXUDYN_SOLVER",
    "REFERENCE_DIR",
    "REFERENCE_STEP",
    "STEP_BETWEEN",
    "TOLERANCE_BETWEEN",
    "CodeResult",
    "Reference",
    "load_reference",
    "make_loads_reference",
    "make_reference",
    "reference_path",
    "relative_error",
]

REFERENCE_DIR = Path(__file__).resolve().parent / "reference"

#: Each calibration (benchmarks.suite, benchmarks.flexible_compare) tries one setting
#: between the first that meets the target and the one before it, which missed: `loads`'s
#: tolerance TOLERANCE_BETWEEN times looser, Exudyn's step STEP_BETWEEN times as long (each
#: about 1.4x fewer steps than the setting that met it). On the coarse grids alone (decades,
#: halvings) a code that just missed the target paid up to twice the steps it needed: the
#: socket at 1.2e-4 of the range at 1e-10, then 1.5e-5 at 1e-11, against Exudyn's 3.6e-5
#: at its step: not equal accuracy.
TOLERANCE_BETWEEN = math.sqrt(10.0)
STEP_BETWEEN = 4.0 / 3.0

#: Fixed step (s) of the stored Exudyn reference solution of each model.
REFERENCE_STEP: dict[str, float] = {
    "slider_crank": 1e-5,
    "chain20": 2.5e-5,
    "fourbar10": 2.5e-5,
    "ball_bounce": 1e-7,
    "chain100": 5e-5,
}

#: Tolerance of the `loads` run that is the reference of each bench model of
#: `benchmarks.kinds` (Exudyn's fixed steps converge to it at first or second order; its own
#: error is estimated from the run at ten times the tolerance).
LOADS_REFERENCE_TOLERANCE: dict[str, float] = {
    "socket_rattle": 1e-11,
    "flap_latches": 1e-11,
    "fourbar_friction": 1e-11,
    "hydraulic_ram": 1e-11,
}

#: Exudyn's sparse solver (EigenSparse) is its faster one here: 4x to 6x on chain20 and
#: fourbar10, equal on slider_crank (measured with this suite's models).
EXUDYN_SOLVER = "sparse"


@dataclass
class Reference:
    """A stored reference solution: `time` (s), `channels` (SI) at the model's output step,
    and `meta` (Exudyn version, step, end, self-error estimate ...)."""

    model: str
    time: np.ndarray
    channels: dict[str, np.ndarray]
    meta: dict[str, Any]

    def until(self, end: float) -> Reference:
        """The part with time <= end (s)."""
        keep = self.time <= end + 1e-9
        return Reference(
            self.model, self.time[keep], {k: v[keep] for k, v in self.channels.items()}, self.meta
        )


def reference_path(model: ModelSpec) -> Path:
    """The file of the stored reference of `model`."""
    return REFERENCE_DIR / f"{model.name}.npz"


def load_reference(model: ModelSpec) -> Reference | None:
    """The stored reference of `model`, or None when there is none."""
    path = reference_path(model)
    if not path.exists():
        return None
    with np.load(path, allow_pickle=False) as data:
        columns = [str(c) for c in data["columns"]]
        values = data["values"]
        meta = json.loads(str(data["meta"]))
        return Reference(
            model.name,
            data["time"].copy(),
            {c: values[:, i].copy() for i, c in enumerate(columns)},
            meta,
        )


def relative_error(
    time: np.ndarray,
    channels: dict[str, np.ndarray],
    reference: Reference,
    columns: tuple[str, ...] | list[str],
) -> float:
    """Largest deviation from the reference, relative to the reference's range.

    At each time of `time` within the reference's span, the Euclidean norm over `columns` of
    (value - reference interpolated linearly to that time); the largest of these, divided by
    the largest (max - min) of the columns in the reference. Dimensionless.
    """
    t = np.asarray(time, dtype=float)
    inside = (t >= reference.time[0] - 1e-12) & (t <= reference.time[-1] + 1e-9)
    if not np.any(inside):
        raise ValueError(f"{reference.model}: no output time inside the reference")
    sq = np.zeros(int(inside.sum()))
    scale = 0.0
    for c in columns:
        ref = reference.channels[c]
        scale = max(scale, float(ref.max() - ref.min()))
        diff = np.asarray(channels[c], dtype=float)[inside] - np.interp(
            t[inside], reference.time, ref
        )
        sq += diff * diff
    if scale == 0.0:
        raise ValueError(f"{reference.model}: the reference of {columns} is constant")
    return float(np.sqrt(sq.max()) / scale)


def make_reference(model: ModelSpec, log: Callable[[str], None] = print) -> Reference:
    """Compute and store the Exudyn reference of `model` (full end time) at REFERENCE_STEP,
    with a self-error estimate from a second run at twice that step."""
    from benchmarks.exudyn_models import ExudynOptions, exudyn_version, run_exudyn

    step = REFERENCE_STEP[model.name]
    runs = {}
    for h in (2.0 * step, step):
        log(f"  reference {model.name}: Exudyn step {h:g} s, {round(model.end / h)} steps")
        runs[h] = run_exudyn(
            model,
            ExudynOptions(
                step=h, end=model.end, output_step=model.output_step, linear_solver=EXUDYN_SOLVER
            ),
        )
    fine, coarse = runs[step], runs[2.0 * step]
    columns = [o.column for o in model.outputs]
    ref = Reference(model.name, fine.time, dict(fine.channels), {})
    self_error = relative_error(coarse.time, coarse.channels, ref, model.main) / 3.0
    meta = {
        "model": model.name,
        "code": "exudyn",
        "exudyn": exudyn_version(),
        "exudyn_module": fine.info.get("exudyn_module"),
        "step": step,
        "end": model.end,
        "output_step": model.output_step,
        "integrator": "generalized-alpha, index 3",
        "spectral_radius": fine.options.spectral_radius,
        "linear_solver": EXUDYN_SOLVER,
        "self_error": self_error,
        "self_error_method": "error of the run at 2*step against this one, / 3 (second order)",
        "solve_seconds": fine.solve_seconds,
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
    }
    ref.meta = meta
    _store(model, ref, columns)
    log(f"  reference {model.name}: stored, estimated error {self_error:.1e}")
    return ref


def make_loads_reference(model: ModelSpec, log: Callable[[str], None] = print) -> Reference:
    """Compute and store the `loads` reference of `model` (full end time, steps landing on
    the output times) at LOADS_REFERENCE_TOLERANCE, with a self-error estimate: its
    difference to the run at ten times that tolerance."""
    import tempfile

    from benchmarks.suite import _case_copy  # the suite's case writer (imports this module)
    from loadcases.run import run_file

    tolerance = LOADS_REFERENCE_TOLERANCE[model.name]
    runs = {}
    with tempfile.TemporaryDirectory(prefix=f"ref-{model.name}-") as tmp:
        for tol in (10.0 * tolerance, tolerance):
            log(f"  reference {model.name}: loads tolerance {tol:g}")
            case = _case_copy(model, model.end, tol, Path(tmp), "steps")
            solution = run_file(case, output_dir=Path(tmp) / "out")[0].solution
            if not solution.ok:
                raise RuntimeError(f"{model.name}: reference run failed: {solution.message}")
            runs[tol] = solution
    fine, coarse = runs[tolerance], runs[10.0 * tolerance]
    columns = [o.column for o in model.outputs]
    time = np.asarray(fine.time, dtype=float)
    channels = {c: np.asarray(fine.channels[c], dtype=float) for c in columns}
    ref = Reference(model.name, time, channels, {})
    coarse_channels = {c: np.asarray(coarse.channels[c]) for c in columns}
    self_error = relative_error(np.asarray(coarse.time), coarse_channels, ref, model.main)
    ref.meta = {
        "model": model.name,
        "code": "loads",
        "tolerance": tolerance,
        "end": model.end,
        "output_step": model.output_step,
        "integrator": "generalized-alpha, output: steps",
        "steps": int(fine.stats.steps),
        "self_error": self_error,
        "self_error_method": "error of the run at 10 x tolerance against this one",
        "cpu_seconds": float(fine.stats.cpu_seconds),
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
    }
    _store(model, ref, columns)
    log(f"  reference {model.name}: stored, estimated error {self_error:.1e}")
    return ref


def _store(model: ModelSpec, ref: Reference, columns: list[str]) -> None:
    REFERENCE_DIR.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(
        reference_path(model),
        time=ref.time,
        values=np.column_stack([ref.channels[c] for c in columns]),
        columns=np.array(columns),
        meta=np.array(json.dumps(ref.meta)),
    )


@dataclass
class CodeResult:
    """The figures of one code on one model (times in s, errors dimensionless; the CPU
    seconds are the process time of the solve alone)."""

    status: str = "not run"
    setting: str = ""
    error: float | None = None
    secondary_errors: dict[str, float] = field(default_factory=dict)
    solve_seconds: float | None = None
    total_seconds: float | None = None
    build_seconds: float | None = None
    cpu_seconds: float | None = None
    steps: int | None = None
    calibration: list[tuple[float, float | None]] = field(default_factory=list)
    message: str = ""
    extra: dict[str, Any] = field(default_factory=dict)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return dict(self.__dict__)
