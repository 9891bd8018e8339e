"""Shared fixtures of the verification suite: where the case files are, and running one.

The engine is imported inside the fixtures, so that the reference self-checks
(test_references.py) collect and run even where the engine cannot be imported.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:  # `import references` from the test modules
    sys.path.insert(0, str(HERE))

LIBRARY = HERE.parents[1] / "loadcases" / "library" / "verification"
"""The verification case files (shipped with the package as library data)."""


def solve_case(path: Path, **overrides: float) -> Any:
    """Solve a case file (parameter `overrides` in SI, as a set's sweep gives them) through
    `loadcases.run.run_case`; return its Solution after checking that it reports success.

    A case that sets no `accuracy` runs with `accuracy: off`: its solution is the same (the
    global error estimate's companion run only estimates, it tightens nothing) and these
    tests check the physics, not the estimate (tests/verification/test_global_error.py)."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    outcome = run_case(estimate_off(load_case(path, overrides=overrides or None)))
    assert outcome.solution.ok, outcome.solution.message
    return outcome.solution


def estimate_off(cf: Any) -> Any:
    """The loaded case `cf` with `accuracy: off` when it sets no accuracy: the same
    solution without the global error estimate's companion run (it only estimates)."""
    import dataclasses

    if cf.case.analysis.accuracy is not None:
        return cf
    analysis = cf.case.analysis.model_copy(update={"accuracy": "off"})
    return dataclasses.replace(cf, case=cf.case.model_copy(update={"analysis": analysis}))


@pytest.fixture(scope="session")
def library() -> Path:
    """Directory of the verification case files."""
    return LIBRARY


@pytest.fixture(scope="session")
def run_case(tmp_path_factory: pytest.TempPathFactory) -> Callable[[str], Any]:
    """Run one verification case file through `loadcases.run.run_file` (once per session).

    Returns the single `RunOutcome`, after checking that the solver reports success; the
    results are written to a fresh temporary directory per case.
    """
    cache: dict[str, Any] = {}

    def run(file_name: str) -> Any:
        if file_name in cache:
            return cache[file_name]
        from loadcases.run import run_file

        out_dir = tmp_path_factory.mktemp(Path(file_name).name.split(".")[0])
        outcomes = run_file(LIBRARY / file_name, output_dir=out_dir)
        assert len(outcomes) == 1, f"{file_name}: expected one run, got {len(outcomes)}"
        outcome = outcomes[0]
        assert outcome.solution.status == "ok", (
            f"{file_name}: solver failed: {outcome.solution.message}"
        )
        cache[file_name] = outcome
        return outcome

    return run
