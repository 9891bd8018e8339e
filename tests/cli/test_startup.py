"""Start-up of `loads validate` (issue 17 item 5): it loads no compiler, data frame, plotting
or workbook library. Structural checks in a fresh interpreter, not timings: speed is
measured by `loads bench`, never by timed unit tests."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOOR = ROOT / "loadcases" / "library" / "door"
HEAVY = ("numba", "pandas", "matplotlib", "openpyxl", "plotly")

_VALIDATE = """
import json, sys
from cli.app import main
sys.argv = ["loads", "validate", *sys.argv[1:]]
try:
    main()
except SystemExit as done:
    code = done.code
print(json.dumps({"exit": code, "loaded": sorted(m for m in %r if m in sys.modules)}))
"""

_KERNELS = """
import json, sys
import numpy as np
from mechlib import jit
from mechlib.kernels import rotation_matrix
p = np.array([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])
with jit.interpreted():
    python = rotation_matrix(p)
before = "numba" in sys.modules
compiled = rotation_matrix(p)
print(json.dumps({"before": before, "after": "numba" in sys.modules,
                  "difference": float(np.abs(python - compiled).max())}))
"""


def _python(code: str, *args: str) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", code, *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_validate_loads_no_solver_stack() -> None:
    """`loads validate` of a door case (its model built and its degrees of freedom
    checked, the kernels run as Python: mechlib.jit.interpreted) says ok, exit 0, and
    leaves numba, pandas, matplotlib, openpyxl and plotly unimported."""
    result = _python(_VALIDATE % (HEAVY,), str(DOOR / "opening.case.yaml"))
    assert result == {"exit": 0, "loaded": []}


def test_interpreted_kernels_match_the_compiled_ones() -> None:
    """A kernel run as Python before numba is loaded (`interpreted()`) and compiled after
    give the same rotation matrix (same arithmetic, no fastmath: measured 0, guarded at
    1e-15); numba is imported only by the first call outside `interpreted()`."""
    result = _python(_KERNELS)
    assert result["before"] is False
    assert result["after"] is True
    assert result["difference"] <= 1e-15
