"""The `loads` console script ends without the interpreter's teardown (cli.entry): the same
output, exit status and files as before, the teardown skipped only when the console script
runs `main`, never when `main` is called any other way (a test that goes on after it)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOOR = ROOT / "loadcases" / "library" / "door"
SLIDER_CRANK = ROOT / "benchmarks" / "models" / "slider_crank.case.yaml"

# What pip writes as the console script, plus an object whose finaliser tells whether the
# interpreter's teardown ran (module globals are finalised in that teardown only).
_SCRIPT = """
import os
import sys

class Teardown:
    def __del__(self, write=os.write):  # bound now: the teardown clears module globals
        write(2, b"TEARDOWN\\n")

teardown = Teardown()
from cli.entry import main
if __name__ == "__main__":
    sys.exit(main())
"""


def _command(
    tmp_path: Path, *args: str, script: bool = True, name: str = "loads"
) -> subprocess.CompletedProcess:
    """`loads ARGS` through a console script `name` in `tmp_path` (script=True), else the
    same code given with `python -c` (no script file: `main` called another way)."""
    path = tmp_path / name
    path.write_text(_SCRIPT, encoding="utf-8")
    start = [str(path)] if script else ["-c", _SCRIPT]
    env = os.environ | {"PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, *start, *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=env,
        timeout=300,
    )


def test_the_console_script_skips_the_teardown_with_the_same_output(tmp_path: Path) -> None:
    case = str(DOOR / "opening.case.yaml")
    fast = _command(tmp_path, "validate", case)
    usual = _command(tmp_path, "validate", case, script=False)
    assert fast.returncode == usual.returncode == 0
    assert "TEARDOWN" not in fast.stderr
    assert "TEARDOWN" in usual.stderr  # `main` not run by the console script: as before
    assert fast.stdout == usual.stdout
    assert fast.stdout.strip()
    other = _command(tmp_path, "validate", case, name="other_tool.py")  # not pip's script
    assert other.returncode == 0 and "TEARDOWN" in other.stderr


def test_the_console_script_keeps_an_input_errors_status_and_message(tmp_path: Path) -> None:
    bad = tmp_path / "bad.case.yaml"
    bad.write_text("case: bad\nmechanism: nowhere.mech.yaml\n", encoding="utf-8")
    fast = _command(tmp_path, "validate", str(bad))
    usual = _command(tmp_path, "validate", str(bad), script=False)
    assert fast.returncode == usual.returncode == 2
    assert "TEARDOWN" not in fast.stderr
    assert fast.stdout == usual.stdout
    assert fast.stderr == usual.stderr.replace("TEARDOWN\n", "")
    assert "bad.case.yaml" in fast.stdout and "nowhere.mech.yaml" in fast.stdout


def test_the_console_script_writes_a_runs_files_whole(tmp_path: Path) -> None:
    """A run with worker threads and numba's kernels: every file written, status 0."""
    out = tmp_path / "out"
    done = _command(tmp_path, "run", str(SLIDER_CRANK), "-o", str(out))
    assert done.returncode == 0, done.stderr
    assert "TEARDOWN" not in done.stderr
    csv = next(out.rglob("*.csv"))
    summary = next(out.rglob("*.summary.json"))
    assert csv.read_bytes().endswith(b"\n") and csv.stat().st_size > 10_000
    assert summary.read_text(encoding="utf-8").rstrip().endswith("}")
    assert not list(out.rglob("*.tmp*")) and not list(out.rglob(".loads.lock"))
