"""Compile numba's kernels once, at install time (`make install`, `python -m loadcases.warmup`).

The kernels compile on first use and are cached on disk; without this the first runs after an
install pay the compilation. It solves a few library cases over their first instants:
dynamic and quasi-static, every contact kernel, the flexible bodies' kernels, a valve
servo-actuator. Nothing is written outside a temporary folder.
`pip install` alone does not run it: `make install` does.

numba compiles on one core, so the cases are solved in two processes at once (`GROUPS`,
of about the same compile time: from an empty cache on the 2-core VM, 2026-11-30, 175 and
162 s against 278 s in one), then all of them once more in this one. Two processes that
compile the same kernel for different argument types may each rewrite its cache index and
drop the other's entry; the last pass makes what is missing (2 s when nothing is).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
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


# the CASES solved by each process (their compile times about equal: the rigid and contact
# kernels; the modal body's and the servo's)
GROUPS = ((0, 1, 2, 3, 4), (5, 6))


def _solve(indices: Sequence[int]) -> None:
    """The CASES at `indices`, each over its first instants."""
    with tempfile.TemporaryDirectory() as tmp:
        for i in indices:
            name, end, step = CASES[i]
            run_case(load_case(_short_copy(LIBRARY / name, end, step, Path(tmp))))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--group", type=int, help=argparse.SUPPRESS)  # one process's share
    args = parser.parse_args(argv)
    if args.group is not None:
        _solve(GROUPS[args.group])
        return 0
    start = time.perf_counter()
    other = subprocess.Popen([sys.executable, "-m", "loadcases.warmup", "--group", "1"])
    _solve(GROUPS[0])
    if other.wait() != 0:
        print("warmup: the second process failed", file=sys.stderr)
        return 1
    _solve(range(len(CASES)))  # what a concurrent cache write dropped
    print(f"numba kernels compiled and cached in {time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
