"""Compile numba's kernels once, at install time (`make install`, `python -m loadcases.warmup`).

The kernels compile on first use and are cached on disk; without this the first runs after an
install pay the compilation (numba compiles on one core: this warmup takes about 66 s of CPU
from an empty cache, measured 2026-11-29 on the 2-core VM; a first kinematic run 17 s, a
first dynamic run 45 s more; the flexible and servo cases were added later, their share is
in docs/performance.md).
`pip install` alone does not run it: `make install` does.
It solves a few library cases over their first instants: dynamic and quasi-static, every
contact kernel, the flexible bodies' kernels, a valve servo-actuator. Nothing is written
outside a temporary folder.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import yaml

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

LIBRARY = Path(__file__).resolve().parent / "library"
# (case, end s, step s): short runs that call every compiled kernel
CASES = (
    ("verification/pendulum.case.yaml", 0.02, 0.01),  # the compiled Newton loop
    ("verification/ball_in_socket.case.yaml", 0.02, 0.01),
    ("verification/ln_restitution.case.yaml", 0.02, 0.01),
    ("door/lifting_inner_let_go.case.yaml", 0.02, 0.01),
    ("door/lifting_inner.case.yaml", 0.1, 0.05),
    ("examples/flexible/spin_up_beam.case.yaml", 0.02, 0.01),  # modal body, welds, stiffening
    # a valve servo-actuator: its compiled states, the packed force elements' rows of a step
    ("verification/elements/servo_closed_valve.case.yaml", 0.002, 0.0005),
)


def _short_copy(case: Path, end: float, step: float, folder: Path) -> Path:
    """The case over [0, end] in `folder`, its mechanism file (if any) referenced in place."""
    data = yaml.safe_load(case.read_text(encoding="utf-8"))
    if isinstance(data.get("mechanism"), str):
        data["mechanism"] = str(case.parent / data["mechanism"])
    data["analysis"].update(end=end, step=step)
    target = folder / case.name
    target.write_text(yaml.safe_dump(data), encoding="utf-8")
    return target


def main() -> int:
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for name, end, step in CASES:
            run_case(load_case(_short_copy(LIBRARY / name, end, step, Path(tmp))))
    print(f"numba kernels compiled and cached in {time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
