"""The accuracy companion solved beside its run, in a second thread (loadcases.run.beside):
its grid paired as the run's steps come is the whole run's, and its estimate is the one
the companion solved after the run gives, to the last bit."""

from __future__ import annotations

import dataclasses
import signal
import threading
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import mechlib as ml
from loadcases.build.model import build_run
from loadcases.foundation.accuracy_target import DEFAULT_ACCURACY
from loadcases.inputs.loader import load_case
from loadcases.run import beside as beside_module
from loadcases.run import global_error
from loadcases.run.global_error import solve_to_accuracy
from mechlib.model.step_feed import GridWithdrawn, GrowingGrid, StepFeed

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"
BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "models" / "slider_crank.case.yaml"


def _walk(grid: GrowingGrid, walked: list[float], end: float) -> None:
    """A companion's steps along `grid`: to the first end after t, until `end`."""
    t = 0.0
    try:
        while t < end:
            ends, _, _ = grid.covering(t)
            t = float(ends[np.searchsorted(ends, t + 1e-12)])
            walked.append(t)
    except GridWithdrawn:
        walked.append(-1.0)


@pytest.mark.parametrize("batch", [1, 3, 7])
def test_the_pairs_made_as_the_steps_come_are_the_whole_runs(batch: int) -> None:
    """A run's 40 step ends recorded `batch` at a time, an event at the 11th and the
    24th (a stretch of 11 steps: its odd last one alone), walked by a companion in
    another thread: the ends it steps to are StepGrid.paired's of the whole run."""
    rng = np.random.default_rng(batch)
    ends = np.cumsum(rng.uniform(0.5, 1.5, 40))
    stops = [ends[10], ends[23]]
    feed = StepFeed()
    grid = GrowingGrid(feed)
    walked: list[float] = []
    walker = threading.Thread(target=_walk, args=(grid, walked, ends[-1]))
    walker.start()
    for first in range(0, len(ends), batch):
        for t in ends[first : first + batch]:
            feed.ends.append(float(t))
            if t in stops:
                feed.events.append(SimpleNamespace(time=float(t)))
        threading.Event().wait(0.003)
    whole = ml.StepGrid.paired(ends, stops)
    assert grid.complete(whole)
    walker.join(5.0)
    assert not walker.is_alive()
    assert walked == whole.ends.tolist()
    assert np.isnan(whole.middles[5])  # the stretch of 11: its last end alone (the case's check)


def test_a_grid_whose_pairs_differ_is_refused_and_its_steps_stop() -> None:
    feed = StepFeed()
    grid = GrowingGrid(feed)
    feed.ends.extend([1.0, 2.0, 3.0])
    ends, middles, reach = grid.covering(0.0)
    assert ends.tolist() == [2.0] and middles.tolist() == [1.0] and reach == 2.0
    assert not grid.complete(ml.StepGrid.paired([1.5, 2.0, 3.0]))  # another run's
    grid.withdraw("refused")
    with pytest.raises(GridWithdrawn, match="refused"):
        grid.covering(2.0)


def _solver(file: Path, **changes):
    case_file = load_case(file)
    if changes:
        analysis = case_file.case.analysis.model_copy(update=changes)
        case_file = dataclasses.replace(
            case_file, case=case_file.case.model_copy(update={"analysis": analysis})
        )
    built = build_run(case_file)

    def solve(analysis, checks=True, stage="", quiet=False):
        return built.solve(analysis, checks=checks)

    return solve, built.analysis


@pytest.fixture(autouse=True)
def _follow_short_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """The companion follows these short runs too (loads run leaves it after the run
    where the run's steps take under FOLLOW_SECONDS)."""
    monkeypatch.setattr(beside_module, "FOLLOW_SECONDS", 0.0)


def _estimates(file: Path, **changes):
    solve, analysis = _solver(file, **changes)
    out = []
    for beside in (False, True):
        run, estimate = solve_to_accuracy(
            solve, analysis, DEFAULT_ACCURACY, budget=None, beside=beside
        )
        out.append((run, estimate))
    assert not [t for t in threading.enumerate() if t.name == "accuracy companion"]
    return out


@pytest.mark.parametrize(
    ("file", "changes"),
    [
        (LIBRARY / "pendulum.case.yaml", {"end": 2.0, "step": 0.01}),
        (BENCH, {}),
        # a stiff spring-damper's dissipated energy: a column summed over the rows
        (LIBRARY / "hard" / "iftomm_a05_flyball.case.yaml", {"end": 2.0}),
    ],
    ids=["pendulum", "bench slider-crank", "A05 2 s"],
)
def test_the_estimate_beside_the_run_is_the_one_after_it(file: Path, changes: dict) -> None:
    """Every request's history and envelope estimates the same to the last bit, from the
    companion on the run's own steps; the runs written the same."""
    (run_after, after), (run_beside, beside) = _estimates(file, **changes)
    assert after.companion == beside.companion == "grid"
    assert beside.beside and not after.beside and beside.summary()["beside"] is True
    assert after.requests == beside.requests
    assert after.richardson == beside.richardson and after.splits == beside.splits
    for column, values in run_after.channels.items():
        assert np.array_equal(values, run_beside.channels[column], equal_nan=True), column
    assert beside.cpu_seconds > 0.0


def test_a_run_without_a_grid_companion_withdraws_the_one_beside(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A run whose steps make no grid (here: `on_grid` finding none, as for a modal run's
    unrecorded steps): the companion started beside it is withdrawn and the adaptive one
    solved after the run, as without it; its CPU counted."""
    made: list[beside_module.CompanionBeside] = []
    start = beside_module.CompanionBeside.__init__

    def counted(self, solve, analysis):
        start(self, solve, analysis)
        made.append(self)

    monkeypatch.setattr(beside_module.CompanionBeside, "__init__", counted)
    monkeypatch.setattr(global_error, "on_grid", lambda *args, **kwargs: None)
    (_, after), (_, beside) = _estimates(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    assert len(made) == 1 and made[0].grid.withdrawn == "the run has no grid companion"
    assert after.companion == beside.companion == "adaptive" and not beside.beside
    assert after.requests == beside.requests


def test_a_failed_run_leaves_no_companion_running() -> None:
    solve, analysis = _solver(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    run, estimate = solve_to_accuracy(
        solve, dataclasses.replace(analysis, max_steps=20), DEFAULT_ACCURACY, budget=None,
        beside=True,
    )  # fmt: skip
    assert run.status == "failed" and estimate is None
    assert not [t for t in threading.enumerate() if t.name == "accuracy companion"]


def test_a_signal_while_the_companion_is_awaited_saves_the_run_interrupted(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """As a signal during the companion after the run: the run kept, `interrupted`, its
    error not estimated; the companion stopped (a signal arrives in `finish`'s wait)."""
    _always_followed(monkeypatch)
    finish = beside_module.CompanionBeside.finish

    def signalled(self, grid):
        wait, signals = self._thread.join, [signal.SIGTERM]

        def join(timeout=None):
            if signals:
                signals.pop()
                raise KeyboardInterrupt
            return wait(timeout)

        self._thread.join = join
        return finish(self, grid)

    monkeypatch.setattr(beside_module.CompanionBeside, "finish", signalled)
    solve, analysis = _solver(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    run, estimate = solve_to_accuracy(solve, analysis, DEFAULT_ACCURACY, budget=None, beside=True)
    assert run.status == "interrupted" and len(run.time) == 201
    assert estimate is not None and not estimate.estimated
    assert not [t for t in threading.enumerate() if t.name == "accuracy companion"]


def _signal_in_a_kernel() -> None:
    """What a compiled kernel's dispatcher raises when a signal met it: a SystemError with
    the interrupt as its context."""
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt:
        raise SystemError("returned a result with an exception set") from None


@pytest.mark.parametrize("in_kernel", [False, True])
@pytest.mark.parametrize("beside", [False, True])
def test_a_signal_after_the_run_keeps_it(
    monkeypatch: pytest.MonkeyPatch, beside: bool, in_kernel: bool
) -> None:
    """A signal while the run's extremes are read (after the run, before any companion;
    met in Python or in a compiled kernel): the run kept as `interrupted`, not estimated,
    no companion left running."""
    _always_followed(monkeypatch)

    def interrupted(run):
        if in_kernel:
            _signal_in_a_kernel()
        raise KeyboardInterrupt

    monkeypatch.setattr(global_error, "run_extremes", interrupted)
    solve, analysis = _solver(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    run, estimate = solve_to_accuracy(solve, analysis, DEFAULT_ACCURACY, budget=None, beside=beside)
    assert run.status == "interrupted" and len(run.time) == 201
    assert "while its error was estimated" in run.message
    assert estimate is not None and not estimate.estimated and estimate.requests == {}
    assert not [t for t in threading.enumerate() if t.name == "accuracy companion"]


def test_the_companion_follows_only_runs_worth_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """Not a run whose steps are taken in Python (Andrews' squeezer: the two threads would
    take turns at the GIL), nor, at the default FOLLOW_SECONDS, a run of a few hundredths
    of a second: both estimated by the companion after the run, the same estimate."""
    (_, after), (_, beside) = _estimates(LIBRARY / "hard" / "andrews_squeezer.case.yaml")
    assert after.companion == beside.companion == "grid" and not beside.beside
    assert after.requests == beside.requests
    monkeypatch.setattr(beside_module, "FOLLOW_SECONDS", 0.5)
    (_, after), (_, beside) = _estimates(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    assert not beside.beside and after.requests == beside.requests


def _always_followed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(
        beside_module.CompanionBeside, "_worth_following", lambda self, first, took: True
    )


def test_a_run_with_events_followed_in_python_steps(monkeypatch: pytest.MonkeyPatch) -> None:
    """The door jettison (its steps in Python while its events are armed; it stops at its
    `release` event, 0.497 s of 1.5 s), followed nonetheless: its events' times stay step
    ends of the pairs made as they come; the same estimate."""
    _always_followed(monkeypatch)
    (run_after, after), (_, beside) = _estimates(LIBRARY.parent / "door" / "jettison.case.yaml")
    assert run_after.events and beside.beside and after.companion == "grid"
    assert after.requests == beside.requests and after.richardson == beside.richardson


def test_the_python_steps_follow_a_growing_grid(monkeypatch: pytest.MonkeyPatch) -> None:
    """The pendulum with every step taken in Python (`compiled: python`), run and
    companion: the companion's steps wait for the run's in `trial_step`; the same estimate."""
    _always_followed(monkeypatch)
    solve, analysis = _solver(LIBRARY / "pendulum.case.yaml", end=1.0, step=0.01)
    analysis = dataclasses.replace(analysis, compiled="python")
    found = []
    for beside in (False, True):
        _, estimate = solve_to_accuracy(
            solve, analysis, DEFAULT_ACCURACY, budget=None, beside=beside
        )
        found.append(estimate)
    assert found[1].beside and found[0].requests == found[1].requests


def test_a_companion_beside_that_fails_says_so_and_is_solved_after(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def fails(self, first, took):
        raise RuntimeError("boom")

    monkeypatch.setattr(beside_module.CompanionBeside, "_worth_following", fails)
    (_, after), (_, beside) = _estimates(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    assert not beside.beside and after.requests == beside.requests
    assert "the companion beside the run failed (RuntimeError: boom): solved after it" in (
        beside.note
    )


@pytest.mark.parametrize(
    ("cores", "load", "beside"),
    [(2, 0.3, True), (2, 1.2, False), (1, 0.0, False), (8, 5.0, True), (8, 7.5, False)],
)
def test_loads_run_solves_it_beside_where_a_core_is_free(
    monkeypatch: pytest.MonkeyPatch, cores: int, load: float, beside: bool
) -> None:
    monkeypatch.delenv("LOADS_COMPANION_BESIDE", raising=False)
    monkeypatch.setattr(beside_module.os, "sched_getaffinity", lambda pid: set(range(cores)))
    monkeypatch.setattr(beside_module.os, "getloadavg", lambda: (load, load, load))
    assert beside_module.beside_by_default() is beside


# the library's pendulum (1 s, rows 10 ms apart) with its hinge locked at 0.51 s
LOCKED = 'events:\n  hold: {when: "t >= 0.51", then: [{lock: hinge}]}\n'


def test_an_event_at_an_output_time_the_companion_leaves_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The hinge locked at 0.51 s, an output time of the run that the companion's thinned
    rows do not hold: the companion beside the run keeps its event's row there (as the
    one after the run does) and leaves out only the output row; the same estimate (the
    rate's history read 2e-4 of its peak for 1.0 when both rows went)."""
    _always_followed(monkeypatch)
    case = tmp_path / "pendulum_locked.case.yaml"
    pendulum = (LIBRARY / "pendulum.case.yaml").read_text(encoding="utf-8")
    case.write_text(pendulum + LOCKED, encoding="utf-8")
    (run_after, after), (_, beside) = _estimates(case)
    assert [e.name for e in run_after.events] == ["hold"] and beside.beside
    assert after.requests == beside.requests


@pytest.mark.parametrize(("said", "beside"), [("1", True), ("0", False)])
def test_the_environment_says_where_the_companion_is_solved(
    monkeypatch: pytest.MonkeyPatch, said: str, beside: bool
) -> None:
    """LOADS_COMPANION_BESIDE overrides the load rule (a benchmark, a script of runs)."""
    monkeypatch.setattr(
        beside_module.os, "getloadavg", lambda: (0.0, 0.0, 0.0) if not beside else (9.0,) * 3
    )
    monkeypatch.setenv("LOADS_COMPANION_BESIDE", said)
    assert beside_module.beside_by_default() is beside


def test_a_signal_while_the_requests_are_evaluated_keeps_the_run(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A signal after the run's last step, while its requests are evaluated at its rows
    (0.3 s of A01 over 2000 s): the run is kept, `interrupted`, with all its rows and
    columns (evaluated again: the run's wrap-up), where it was lost before."""
    from mechlib.solvers import solve as solve_module

    evaluate, signals = solve_module._channels, ["SIGTERM"]

    def interrupted(*args):
        if signals:
            signals.pop()
            _signal_in_a_kernel()
        return evaluate(*args)

    monkeypatch.setattr(solve_module, "_channels", interrupted)
    solve, analysis = _solver(LIBRARY / "pendulum.case.yaml", end=2.0, step=0.01)
    run = solve(analysis)
    assert run.status == "interrupted" and len(run.time) == 201
    assert np.all(np.isfinite(run.channels["hinge_angle.value"]))
    assert len(run.channels["hinge_angle.value"]) == 201
