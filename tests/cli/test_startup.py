"""Start-up of `loads validate` (issue 17 item 5): it loads no compiler, data frame, plotting
or workbook library, none of SciPy's submodules (interpolate, optimize, integrate, linalg,
sparse: the model is built and checked, never solved) and none of mechlib's solvers.
Structural checks in a fresh interpreter, not timings: speed is measured by `loads bench`,
never by timed unit tests."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOOR = ROOT / "loadcases" / "library" / "door"
HEAVY = ("numba", "pandas", "matplotlib", "openpyxl", "plotly")
# imported only to solve, interpolate a table or build a flexible body (mechlib.model.tables,
# mechlib.checks.model_check, mechlib.flexible): a case that validates needs none of them
SOLVER = (
    "scipy.interpolate",
    "scipy.optimize",
    "scipy.integrate",
    "scipy.linalg",
    "scipy.sparse",
    "scipy.special",
    "mechlib.solvers.solve",
    "mechlib.solvers.assembly",
    "mechlib.linalg.factor",
    "mechlib.solvers.radau",
    "mechlib.solvers.genalpha.stepper",
    "mechlib.solvers.modes",
    "mechlib.flexible.fe_model",
    "loadcases.flexible.read",
)


def _validate_script(report: str, imports: str = "") -> str:
    """A script running `loads validate ARGS` in-process (after `imports`), then printing
    the JSON of `report`, an expression of the exit `code` and what the run left."""
    return f"""
import gc, json, sys
from cli.app import main
{imports}
sys.argv = ["loads", "validate", *sys.argv[1:]]
try:
    main()
except SystemExit as done:
    code = done.code
print(json.dumps({report}))
"""


_VALIDATE = _validate_script('{"exit": code, "loaded": sorted(m for m in %r if m in sys.modules)}')
_UNITS = _validate_script(
    '{"exit": code, "cache": None if (folder := units._registry().cache_folder) is None '
    "else str(folder)}",
    "from loadcases.foundation import units",
)
_FROZEN = _validate_script('{"exit": code, "frozen": gc.get_freeze_count()}')

_KERNELS = """
import json, sys
import numpy as np
from mechlib.core import jit
from mechlib.kinematics.kernels import rotation_matrix
p = np.array([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])
with jit.interpreted():
    python = rotation_matrix(p)
before = "numba" in sys.modules
compiled = rotation_matrix(p)
print(json.dumps({"before": before, "after": "numba" in sys.modules,
                  "difference": float(np.abs(python - compiled).max())}))
"""


def _python(code: str, *args: str, env: dict[str, str] | None = None) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", code, *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
        env=env,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_validate_loads_no_solver_stack() -> None:
    """`loads validate` of a door case (its model built and its degrees of freedom
    checked, the kernels run as Python: mechlib.core.jit.interpreted) says ok, exit 0, and
    leaves numba, pandas, matplotlib, openpyxl and plotly unimported."""
    result = _python(_VALIDATE % (HEAVY,), str(DOOR / "opening.case.yaml"))
    assert result == {"exit": 0, "loaded": []}


@pytest.mark.parametrize(
    "case",
    [
        "opening.case.yaml",
        "opened.case.yaml",
        "jam_gearbox.case.yaml",
        "jettison.case.yaml",
        "lifting_inner.case.yaml",
    ],
)
def test_validate_loads_no_scipy_submodule_or_solver(case: str) -> None:
    """`loads validate` of door cases (the door's tables, seals and contacts; kinematic,
    static, quasi-static and dynamic) builds and checks the model without SciPy's
    submodules or mechlib's solvers: a table or a profile contact (the lifting cases)
    builds its spline, a solver its factors, on first use."""
    result = _python(_VALIDATE % (SOLVER,), str(DOOR / case))
    assert result == {"exit": 0, "loaded": []}


def test_second_validate_imports_no_pint(tmp_path: Path) -> None:
    """The first `loads validate` keeps pint's conversions in the user cache folder
    (loadcases.foundation.unit_table); the next, meeting only those units, imports neither pint nor
    the dask pint's compat layer imports when installed."""
    env = os.environ | {"XDG_CACHE_HOME": str(tmp_path)}
    case = str(DOOR / "opening.case.yaml")
    assert _python(_VALIDATE % (("pint", "dask"),), case, env=env) == {
        "exit": 0,
        "loaded": ["dask", "pint"] if importlib.util.find_spec("dask") else ["pint"],
    }
    assert _python(_VALIDATE % (("pint", "dask"),), case, env=env) == {"exit": 0, "loaded": []}


def test_validate_reads_the_unit_registry_from_pints_cache(tmp_path: Path) -> None:
    """The first `loads validate` fills pint's cache of the parsed unit definitions in the
    user cache folder; the next reads the registry from it (instead of parsing pint's
    definitions again, about 0.2 s)."""
    env = os.environ | {"XDG_CACHE_HOME": str(tmp_path)}
    case = str(DOOR / "opening.case.yaml")
    assert _python(_UNITS, case, env=env)["exit"] == 0
    assert _python(_UNITS, case, env=env) == {
        "exit": 0,
        "cache": str(tmp_path / "loads" / "pint"),
    }


def test_interpreted_kernels_match_the_compiled_ones() -> None:
    """A kernel run as Python before numba is loaded (`interpreted()`) and compiled after
    give the same rotation matrix (same arithmetic, no fastmath: measured 0, guarded at
    1e-15); numba is imported only by the first call outside `interpreted()`."""
    result = _python(_KERNELS)
    assert result["before"] is False
    assert result["after"] is True
    assert result["difference"] <= 1e-15


def test_main_leaves_its_objects_out_of_the_exit_collection() -> None:
    """`main` freezes the objects alive when the command ends (gc.freeze), so that the
    interpreter's exit does not walk the imports' tens of thousands of objects in its
    garbage collections (about 0.2 s of `loads validate`); the command's output is unchanged."""
    result = _python(_FROZEN, str(DOOR / "opening.case.yaml"))
    assert result["exit"] == 0
    assert result["frozen"] > 10_000


_COLLECTOR = """
import gc, json, os, sys
from cli.entry import main
sys.argv = ["loads", *sys.argv[1:]]
try:
    main()
except SystemExit as done:
    code = done.code
print(json.dumps({"exit": code, "enabled": gc.isenabled(),
                  "plugins": os.environ.get("PYDANTIC_DISABLE_PLUGINS")}))
"""


@pytest.mark.parametrize(
    "command,args,enabled",
    [
        ("validate", ["validate", str(DOOR / "opening.case.yaml")], False),
        ("schema", ["schema"], False),
        ("run", ["run", str(ROOT / "benchmarks" / "models" / "slider_crank.case.yaml")], True),
    ],
)
def test_the_console_script_pauses_the_collector_for_short_commands(
    command: str, args: list[str], enabled: bool, tmp_path: Path
) -> None:
    """The `loads` script (cli.entry) pauses the cyclic garbage collector for the start-up
    imports; `validate` and `schema` end without it, `run` (and every other command)
    turns it back on as it starts. pydantic's plugins are off."""
    if command == "run":
        args = [*args, "-o", str(tmp_path)]
    result = _python(_COLLECTOR, *args, env=_without_plugin_setting())
    assert result == {"exit": 0, "enabled": enabled, "plugins": "__all__"}


def _without_plugin_setting() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k != "PYDANTIC_DISABLE_PLUGINS"}


def test_the_console_script_keeps_a_users_plugin_setting() -> None:
    """pydantic's plugins are off in `loads` (looking for them reads every installed
    package's metadata) unless the environment says otherwise."""
    env = _without_plugin_setting() | {"PYDANTIC_DISABLE_PLUGINS": "0"}
    result = _python(_COLLECTOR, "validate", str(DOOR / "opening.case.yaml"), env=env)
    assert result == {"exit": 0, "enabled": False, "plugins": "0"}
