"""Start-up time of the `loads` command (issue 17 item 5: `--help` and `validate` of a door
case under 0.3 s on a warm machine).

Runs each command in a fresh process `--repeat` times (default 5) after one unmeasured run
(the warm file cache) and prints the median and the fastest wall time, with the machine and
its load average. No peer comparison.

    python -m benchmarks.startup [--repeat 5] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "loadcases" / "library" / "door" / "opening.case.yaml"
COMMANDS = {"loads --help": ["--help"], "loads validate opening.case.yaml": ["validate", str(CASE)]}
LIMIT = 0.3  # s: the target for each command


def wall_times(args: list[str], repeat: int) -> list[float]:
    """Wall seconds of `loads ARGS` in fresh processes (one warm-up run first)."""
    loads = Path(sys.executable).with_name("loads")
    times = []
    for run in range(repeat + 1):
        start = time.perf_counter()
        subprocess.run([str(loads), *args], capture_output=True, check=True)
        if run:
            times.append(time.perf_counter() - start)
    return times


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    from benchmarks.suite import machine_info

    result: dict[str, Any] = {"machine": machine_info(), "load": os.getloadavg(), "limit_s": LIMIT}
    for label, command in COMMANDS.items():
        times = wall_times(command, args.repeat)
        result[label] = {"median_s": statistics.median(times), "fastest_s": min(times)}
        print(f"{label}: median {statistics.median(times):.2f} s, fastest {min(times):.2f} s")
    print(f"load average {result['load'][0]:.1f} (1 min)")
    if args.json:
        args.json.write_text(json.dumps(result, indent=2), encoding="utf-8")
    return 0 if all(result[label]["median_s"] <= LIMIT for label in COMMANDS) else 1


if __name__ == "__main__":
    raise SystemExit(main())
