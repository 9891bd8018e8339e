"""A set's report modules (matplotlib, openpyxl and the workbook's sheet modules) are
imported while the runs are solved (`campaign._import_report_modules`, called at the first
run back), so that the report after the last run, when this process works alone, imports
nothing: checked in a fresh interpreter, on a set of two kinematic runs."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH

ROOT = Path(__file__).resolve().parents[2]

_SCRIPT = """
import json, sys
from loadcases.report import workbook
from loadcases.sets import campaign

write = workbook.write_workbook
imported = {}

def watched(*args, **kwargs):
    before = set(sys.modules)
    path = write(*args, **kwargs)
    imported["workbook"] = sorted(set(sys.modules) - before)
    return path

workbook.write_workbook = watched
result = campaign.run_set(sys.argv[1], output_dir=sys.argv[2])
print(json.dumps({"failed": len(result.failed), "files": len(result.files), **imported}))
"""


def test_the_workbook_imports_nothing_after_the_last_run(tmp_path: Path) -> None:
    (tmp_path / "crank.mech.yaml").write_text(CRANK_MECH)
    (tmp_path / "crank.case.yaml").write_text(CRANK_CASE)
    set_file = tmp_path / "two.set.yaml"
    set_file.write_text("set: two\ncases: [crank.case.yaml]\nsweep: {stroke: [0.05, 0.2]}\n")
    done = subprocess.run(
        [sys.executable, "-c", _SCRIPT, str(set_file), str(tmp_path / "out")],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=True,
    )
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["failed"] == 0 and result["files"] >= 2
    assert result["workbook"] == []  # before: openpyxl and four sheet modules, 0.07 s of CPU
