"""A sweep's runs in one process share what their inputs share, and nothing else: a variant
solved after another gives the same results, bit for bit (every channel, warning,
statistic but CPU time, the accuracy block), as the same variant solved alone in a fresh
process (mechlib.solvers.start_memo, mechlib.linalg.rank's kept checks). The campaign's
rate sweep reuses the placed start; a sweep of a length, a mass, a joint's place or the
initial angle places each variant anew."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case
from loadcases.results.outcome import RunOutcome
from loadcases.run import run_case
from mechlib.linalg import rank
from mechlib.solvers.solve_copy import solve_copy
from mechlib.solvers.start_memo import PLACED, _key
from mechlib.system.planar import make_system

CASE = Path(__file__).parent / "cases" / "sweep_crank.case.yaml"
A02 = Path(__file__).parents[2] / "loadcases/library/verification/hard"
A02_CASE = "iftomm_a02_fourbar_planar.case.yaml"


def _forget() -> None:
    """A fresh worker's memory: nothing kept."""
    PLACED.clear()
    rank._FOUND.clear()


def _run(parameters: dict[str, float], case: Path = CASE) -> RunOutcome:
    return run_case(load_case(case, overrides=parameters))


def _bits(outcome: RunOutcome) -> dict:
    """Everything a run reports but its CPU times; arrays as bytes (bit for bit)."""
    solution = outcome.solution
    stats = {k: v for k, v in vars(solution.stats).items() if k != "cpu_seconds"}
    accuracy = {k: v for k, v in outcome.checks["accuracy"].items() if k != "cpu_seconds"}
    return {
        "status": solution.status,
        "message": solution.message,
        "time": np.asarray(solution.time).tobytes(),
        "channels": {k: np.asarray(v).tobytes() for k, v in solution.channels.items()},
        "warnings": list(solution.warnings),
        "notes": [str(w) for w in outcome.warnings],
        "stats": stats,
        "accuracy": repr(accuracy),
    }


# parameter: (first value, second value, the second's start placed from memory)
SWEEPS = {
    "crank_rate": (5.0, 7.5, True),  # the campaign's sweep: positions unchanged
    "crank_len": (0.1, 0.11, False),  # geometry: the crank pin and its joint
    "rod_mass": (0.8, 0.9, False),  # a mass: the mechanism differs, placed anew
    "guide_y": (0.0, 0.01, False),  # a joint's place
    "crank_angle": (0.0, 0.3, False),  # an initial position
}


@pytest.mark.parametrize("name", list(SWEEPS))
def test_a_variant_after_another_is_the_variant_alone(name: str) -> None:
    first_value, second_value, shared = SWEEPS[name]
    _forget()
    first = _run({name: first_value})
    placed, checked = PLACED.hits, rank._FOUND.hits
    after = _bits(_run({name: second_value}))
    assert (PLACED.hits > placed) is shared
    _forget()
    alone = _bits(_run({name: second_value}))
    assert PLACED.hits == 0  # alone: nothing to reuse
    assert after == alone
    # the variants differ where it shows: a wrong reuse would not go unseen
    assert _bits(first)["channels"] != alone["channels"]
    assert placed == 0 and checked == 0  # the first run reused nothing


def test_the_rate_sweep_checks_and_places_once() -> None:
    _forget()
    for rate in (5.0, 6.0, 7.0):
        outcome = _run({"crank_rate": rate})
        assert outcome.solution.status == "ok"
    assert rank._FOUND.hits == 2  # the model check of the second and third runs
    assert PLACED.hits == 2  # and their placed start (each companion: the run's memo)
    assert len(PLACED) == 1 and len(rank._FOUND) == 1


@pytest.fixture
def planar_case(tmp_path: Path) -> Path:
    """The IFToMM A02 planar four-bar (N = 3; a planar system, a near-singular crossing and
    its warning), its initial angle and rate parameters."""
    shutil.copy(A02 / "iftomm_a02_fourbar_planar.mech.yaml", tmp_path)
    text = (A02 / A02_CASE).read_text(encoding="utf-8")
    given = "  a0: {value: 0, rate: -4.0}\n"
    assert given in text
    text = text.replace(given, "  a0: {value: angle0, rate: rate0}\n")
    text = text.replace("initial:", "parameters: {angle0: 0.0, rate0: -4.0}\ninitial:", 1)
    (tmp_path / A02_CASE).write_text(text, encoding="utf-8")
    return tmp_path / A02_CASE


@pytest.mark.parametrize(
    ("name", "values", "shared"), [("rate0", (-4.0, -3.5), True), ("angle0", (0.0, 0.05), False)]
)
def test_a_planar_variant_after_another_is_the_variant_alone(
    planar_case: Path, name: str, values: tuple[float, float], shared: bool
) -> None:
    _forget()
    first = _bits(_run({name: values[0]}, planar_case))
    after = _bits(_run({name: values[1]}, planar_case))
    assert (PLACED.hits > 0) is shared
    _forget()
    alone = _bits(_run({name: values[1]}, planar_case))
    assert after == alone
    assert first["channels"] != alone["channels"]
    assert any("near-singular" in w for w in alone["warnings"])  # the warnings compared too


LIBRARY = Path(__file__).parents[2] / "loadcases/library/verification"


@pytest.mark.parametrize(
    "case",
    [
        "slider_crank.case.yaml",  # a motion: its function has no value to key by
        "elements/pin_friction.case.yaml",  # a joint friction's memory (stick anchor)
    ],
)
def test_what_is_not_keyed_by_value_is_placed_every_time(case: str) -> None:
    built = build_run(load_case(LIBRARY / case))
    system = make_system(solve_copy(built.mechanism))
    assert _key(system, 0.0, built.initial, built.branches) is None
    _forget()
    for _ in range(2):
        run_case(load_case(LIBRARY / case))
    assert PLACED.hits == 0 and len(PLACED) == 0
