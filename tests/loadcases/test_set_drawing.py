"""A large set solved by forked workers has its envelope plots drawn by a process forked
before the kernels' warm-up (`loadcases.sets.drawing`): the parent never imports matplotlib,
the plots are those a process forked after the last run draws, byte for byte, and no
process is left. Checked in fresh interpreters, `_RUNS_PER_PROCESS` lowered to the set's
four kinematic runs (100 otherwise)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH

ROOT = Path(__file__).resolve().parents[2]

_SCRIPT = """
import json, multiprocessing, sys
from loadcases.sets import campaign
from loadcases.sets.executors import PoolExecutor, SerialExecutor

campaign._RUNS_PER_PROCESS = 2
executor = PoolExecutor(2) if sys.argv[3] == "pool" else SerialExecutor()
result = campaign.run_set(sys.argv[1], output_dir=sys.argv[2], executor=executor)
print(json.dumps({
    "failed": len(result.failed),
    "plots": sorted(p.name for p in result.files if p.suffix == ".png"),
    "matplotlib": "matplotlib" in sys.modules,
    "children": len(multiprocessing.active_children()),
}))
"""


def _run(set_file: Path, out: Path, executor: str) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", _SCRIPT, str(set_file), str(out), executor],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=True,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_a_large_sets_plots_are_drawn_by_the_process_started_before_the_warm_up(
    tmp_path: Path,
) -> None:
    (tmp_path / "crank.mech.yaml").write_text(CRANK_MECH)
    (tmp_path / "crank.case.yaml").write_text(CRANK_CASE)
    set_file = tmp_path / "four.set.yaml"
    set_file.write_text(
        "set: four\ncases: [crank.case.yaml]\nsweep: {speed: [1.0, 2.0, 3.0, 4.0]}\n"
    )
    early = _run(set_file, tmp_path / "pool", "pool")
    late = _run(set_file, tmp_path / "serial", "serial")  # a process forked after the runs
    assert early["failed"] == late["failed"] == 0
    assert len(early["plots"]) >= 2 and early["plots"] == late["plots"]
    assert early["matplotlib"] is False and late["matplotlib"] is True
    assert early["children"] == late["children"] == 0
    for name in early["plots"]:
        drawn = (tmp_path / "pool" / "four" / name).read_bytes()
        assert drawn == (tmp_path / "serial" / "four" / name).read_bytes(), name
