"""The history estimate of loadcases.run.global_error.request_errors against closed forms:
an oscillation whose run drifts in phase as c t and whose companion (order 2: steps twice
as long) drifts four times faster."""

from __future__ import annotations

import time
import types

import numpy as np
import pytest

import mechlib as ml
from loadcases.run.global_error import request_errors

OMEGA = 3.0  # rad/s


def _solutions(drift: float, end: float) -> tuple[ml.Solution, ml.Solution, float]:
    """Run and companion of x = sin(omega t + phase error), the run's phase error drift t
    (rad), the companion's 4 drift t; and the run's true largest error."""
    time = np.linspace(0.0, end, 2001)
    run = np.sin(OMEGA * time + drift * time)
    companion = np.sin(OMEGA * time + 4.0 * drift * time)
    true = float(np.abs(run - np.sin(OMEGA * time)).max())

    def solution(values: np.ndarray) -> ml.Solution:
        return ml.Solution("ok", "", "dynamic", time, {"x.value": values})

    return solution(run), solution(companion), true


def test_a_small_phase_error_is_richardsons() -> None:
    """Phase error 0.05 rad at the end: |run - companion| / 3 within 1 % of the truth."""
    run, companion, true = _solutions(0.05 / 20.0, 20.0)
    estimate = request_errors(run, companion, order=2)["x"].history
    assert estimate == pytest.approx(true, rel=0.01)


@pytest.mark.parametrize(("phase", "richardson"), [(1.0, 0.70), (2.5, 0.35)])
def test_a_lost_phase_is_bounded_by_the_range(phase: float, richardson: float) -> None:
    """Phase error 1 or 2.5 rad at the end (true error 0.95 and 1.9): the companion's, 4
    and 10 rad, has lost the phase and folded back; Richardson's difference / 3 reads 0.70
    and 0.35 of the truth, the range (2) 2.1 and 1.05 times it."""
    run, companion, true = _solutions(phase / 20.0, 20.0)
    estimate = request_errors(run, companion, order=2)["x"].history
    difference = float(np.abs(run.channels["x.value"] - companion.channels["x.value"]).max())
    assert difference / 3.0 / true == pytest.approx(richardson, abs=0.01)
    assert true <= estimate <= 3.0 * true
    assert estimate == pytest.approx(2.0, rel=1e-3)


def test_a_steady_offset_on_a_still_column_keeps_richardsons_value() -> None:
    """A column that hardly moves (range 1e-9) whose companion is 3e-3 off: not a lost
    phase; the estimate is the difference / 3 (the error's own order)."""
    time = np.linspace(0.0, 1.0, 101)
    still = 1.0 + 1e-9 * np.sin(time)
    run = ml.Solution("ok", "", "dynamic", time, {"x.value": still})
    companion = ml.Solution("ok", "", "dynamic", time, {"x.value": still + 3e-3})
    assert request_errors(run, companion, order=2)["x"].history == pytest.approx(1e-3)


def test_a_finer_run_estimates_the_run_by_the_difference_times_four_thirds() -> None:
    """A finer run (steps half as long, order 2: a quarter of the run's error) at a phase
    error of 0.05 rad: (fine - run) / (2^-2 - 1) within 1 % of the run's true error."""
    time = np.linspace(0.0, 20.0, 2001)
    drift = 0.05 / 20.0
    run, fine = (
        ml.Solution("ok", "", "dynamic", time, {"x.value": np.sin(OMEGA * time + d * time)})
        for d in (drift, drift / 4.0)
    )
    true = float(np.abs(run.channels["x.value"] - np.sin(OMEGA * time)).max())
    estimate = request_errors(run, fine, order=2, ratio=0.5)["x"].history
    assert estimate == pytest.approx(true, rel=0.01)


def test_a_lost_phase_pairs_no_crests() -> None:
    """A companion half a period off (its difference the whole range: the phase lost) with
    a ripple of small crests everywhere (every second row 0.01 up): crest by crest, the
    run's crest at 1 would pair with a ripple crest near -1 and read an excess of 0.66
    (IFToMM A01 over 2000 s read 0.28 of the rate's peak so, for a true 3.4e-4); only the
    extremes are compared (their difference 0.01 / 3)."""
    time = np.linspace(0.0, 20.0, 2001)
    run = ml.Solution("ok", "", "dynamic", time, {"x.value": np.sin(OMEGA * time)})
    ripple = -np.sin(OMEGA * time) + 0.01 * (np.arange(len(time)) % 2)
    companion = ml.Solution("ok", "", "dynamic", time, {"x.value": ripple})
    error = request_errors(run, companion, order=2)["x"]
    assert error.history == pytest.approx(2.0, rel=1e-3)  # the range
    assert error.peak < 0.01


@pytest.mark.parametrize(("level", "counted"), [(0.9e-6, False), (1.1e-6, True)])
def test_a_column_of_round_off_beside_its_requests_peak_has_no_error(
    level: float, counted: bool
) -> None:
    """A reaction's force at 50 N, the same in run and companion (no error of its history),
    and its out-of-plane moment at `level` of that peak, the companion's half the run's
    (round-off: a crest at almost every row): below NOISE_FLOOR (1e-6) of the peak it is
    left out, and the request's estimate is the force's alone (history and envelope);
    above, its difference counts, Richardson's third of it (level / 2 / 3 of the peak)."""
    time = np.linspace(0.0, 2.0, 1001)
    force = 50.0 * np.sin(OMEGA * time)
    noise = np.random.default_rng(7).standard_normal(len(time))
    moment = level * 50.0 * noise / np.abs(noise).max()

    def solution(tz: np.ndarray | None) -> ml.Solution:
        channels = {"f.fx": force} if tz is None else {"f.fx": force, "f.tz": tz}
        return ml.Solution("ok", "", "dynamic", time, channels)

    found = request_errors(solution(moment), solution(0.5 * moment), order=2)["f"]
    alone = request_errors(solution(None), solution(None), order=2)["f"]
    assert found.history == pytest.approx(level / 6.0 if counted else 0.0, rel=1e-9)
    if not counted:
        assert found == alone


def test_a_column_still_in_the_run_but_moving_in_the_companion_counts() -> None:
    """A reaction's fx, the same in both runs, and its fy: 0 in the run, 0.1 fx in the
    companion (no round-off: the companion moved where the run did not). The column
    counts though the run alone would call it round-off: its history estimate is
    Richardson's third of the difference, a tenth of the request's peak (both columns
    sampled at the same rows): 1/30."""
    time = np.linspace(0.0, 2.0, 1001)
    force = 50.0 * np.sin(OMEGA * time)
    run = ml.Solution("ok", "", "dynamic", time, {"f.fx": force, "f.fy": 0.0 * time})
    moving = 0.1 * force
    companion = ml.Solution("ok", "", "dynamic", time, {"f.fx": force, "f.fy": moving})
    found = request_errors(run, companion, order=2)["f"]
    assert found.history == pytest.approx(1.0 / 30.0, rel=1e-12)


def test_an_accuracy_warning_names_five_requests_and_counts_the_others() -> None:
    """Seven requests miss the target 1e-3 in their histories, none in their peaks: one
    warning, the five worst named with their estimates (largest first), the two others
    counted; three missing name all three."""
    from loadcases.run.global_error import AccuracyEstimate, RequestError, _warnings

    errors = {f"r{k}": RequestError(history=k * 1e-3 + 1e-4, peak=1e-4) for k in range(1, 8)}
    estimate = AccuracyEstimate(1e-3, "generalized-alpha", 1e-6, 0.1, 1000, 0, errors, 0.0)
    (warning,) = _warnings(estimate, tightened=False)
    assert warning.endswith(
        "r7 0.0071, r6 0.0061, r5 0.0051, r4 0.0041, r3 0.0031 and 2 other requests"
    )
    assert "time histories" in warning and "(not tightened)" in warning
    estimate.requests = {k: v for k, v in errors.items() if k in ("r1", "r2", "r3")}
    (warning,) = _warnings(estimate, tightened=False)
    assert warning.endswith("r3 0.0031, r2 0.0021, r1 0.0011")


def _burn(seconds: float) -> float:
    """Spin for about `seconds` of CPU; the CPU s spent."""
    started = time.process_time()
    while time.process_time() - started < seconds:
        pass
    return time.process_time() - started


def test_a_runs_cost_leaves_out_the_kernels_it_made(monkeypatch) -> None:
    """The first solve of a process also loads (or compiles) the kernels: 0.6 s of CPU for
    0.01 s of steps on the pendulum, which a CPU budget doubled for the next halving
    (`budget: {cpu: 0.5 s}` refused a first tightening that took 0.04 s). A solve that
    spends 0.2 s making kernels (mechlib.core.jit.compile_seconds) and 0.02 s on its
    steps costs 0.02 s to the budget, and predicts 0.04 s for a halving."""
    from loadcases.run import global_error

    made = [0.0]
    monkeypatch.setattr(global_error, "compile_seconds", lambda: made[0])

    def solve(analysis, checks=True):
        made[0] += _burn(0.2)  # the kernels made
        _burn(0.02)  # the steps
        return types.SimpleNamespace(stats=types.SimpleNamespace(steps=100, rejected_steps=0))

    spent = global_error.Spent()
    global_error._timed(solve, None, spent, counted=False)
    assert 0.015 < spent.last_cpu < 0.1
    assert spent.exhausts(global_error.Budget(cpu_seconds=0.3), 0) == ""


def test_making_a_kernel_is_counted_in_compile_seconds() -> None:
    """A kernel compiled in this process (a new numba function: its compilation holds
    numba's compiler lock) adds its CPU to mechlib.core.jit.compile_seconds, which a run's
    cost to the budget leaves out (loadcases.run.global_error._cpu): the compilation's
    CPU is nearly all counted, and a second call, compiled already, adds nothing."""
    from loadcases.run.global_error import _cpu
    from mechlib.core import jit

    jit.compile_all()
    made, cpu, clean = jit.compile_seconds(), time.process_time(), _cpu()

    @jit.njit(cache=False)
    def twice(x):
        return 2.0 * x + 3.0

    assert twice(1.5) == 6.0
    spent, counted = time.process_time() - cpu, jit.compile_seconds() - made
    assert spent > 0.01 and counted > 0.8 * spent
    assert _cpu() - clean < 0.2 * spent
    again = jit.compile_seconds()
    assert twice(2.5) == 8.0 and jit.compile_seconds() == again
