"""The rows of each compiled whole-run call (mechlib.solvers.genalpha.call_rows): a run's
rows, steps and work counts are the same however its calls are cut (so a pace that the
machine's load sways changes nothing computed), and the sizes follow the rule.

- The campaign's slider-crank (rigid, mechlib.solvers.genalpha.run, 1001 rows), the
  flexible slider-crank (modal bodies, .modal_run) and the closed-valve servo-actuator
  (element states): calls of 7 rows each against calls as large as the rule allows (one
  or two), every channel bit for bit and the same statistics.
- The rule: FIRST_ROWS first; then the last call's pace over CALL_SECONDS, never fewer than
  FIRST_ROWS, at most MOST_ROWS and MOST_CELLS values; a call that wrote nothing leaves it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mechlib
from benchmarks.flexible import flexible_slider_crank
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.solvers.genalpha import call_rows

ROOT = Path(__file__).resolve().parents[2]
CAMPAIGN = ROOT / "benchmarks" / "models" / "slider_crank.case.yaml"


def _cut(monkeypatch, rows: int | None) -> None:
    """Every call of `rows` rows (None: as many as the rule's caps allow)."""
    if rows is None:
        monkeypatch.setattr(call_rows, "FIRST_ROWS", call_rows.MOST_ROWS)
    else:
        monkeypatch.setattr(call_rows, "FIRST_ROWS", rows)
        monkeypatch.setattr(call_rows, "MOST_ROWS", rows)


def _same(a: mechlib.Solution, b: mechlib.Solution) -> None:
    assert a.status == b.status == "ok"
    assert np.array_equal(a.time, b.time)
    assert a.channels.keys() == b.channels.keys()
    for name, values in a.channels.items():
        assert np.array_equal(values, b.channels[name], equal_nan=True), name
    for field in ("steps", "rejected_steps", "newton_iterations", "factorizations"):
        assert getattr(a.stats, field) == getattr(b.stats, field), field


def test_the_campaign_s_rows_do_not_depend_on_the_calls(monkeypatch) -> None:
    cf = load_case(CAMPAIGN)
    solved = []
    for rows in (7, None):
        _cut(monkeypatch, rows)
        solved.append(run_case(cf).solution)
    _same(*solved)
    assert len(solved[0].time) == 1001


def test_a_modal_run_s_rows_do_not_depend_on_the_calls(monkeypatch) -> None:
    spec = mechlib.Dynamic(end=0.02, step=1e-3, tolerance=1e-4)
    requests = [mechlib.PointKinematics("slider", "slider")]
    solved = []
    for rows in (7, None):
        _cut(monkeypatch, rows)
        solved.append(mechlib.solve(flexible_slider_crank(), spec, requests=requests))
    _same(*solved)


def test_element_states_rows_do_not_depend_on_the_calls(monkeypatch) -> None:
    source = ROOT / "loadcases" / "library" / "verification" / "elements"
    case = source / "servo_closed_valve.case.yaml"
    solved = []
    for rows in (7, None):
        _cut(monkeypatch, rows)
        solved.append(run_case(load_case(case)).solution)
    _same(*solved)


class _Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def clock(monkeypatch) -> _Clock:
    fake = _Clock()
    monkeypatch.setattr(call_rows.time, "perf_counter", fake)
    return fake


def test_the_calls_follow_the_pace_within_their_bounds(clock) -> None:
    calls = call_rows.CallRows()
    assert calls.rows(83) == call_rows.FIRST_ROWS
    clock.now += 0.005  # 256 rows in 5 ms: 5120 fit in 0.1 s
    calls.done(256)
    assert calls.rows(83) == 5120
    clock.now += 1.0  # slow now: 512 rows a second
    calls.done(512)
    assert calls.rows(83) == call_rows.FIRST_ROWS  # never fewer
    clock.now += 1e-6
    calls.done(256)
    assert calls.rows(10) == call_rows.MOST_ROWS
    assert calls.rows(1000) == call_rows.MOST_CELLS // 1000  # 8 MB of recorded state
    clock.now += 5.0
    calls.done(0)  # a call that only refactored: the size stays
    assert calls.rows(10) == call_rows.MOST_ROWS
