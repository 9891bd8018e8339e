"""Whole runs of steps in one compiled call for systems with modal bodies
(mechlib.solvers.genalpha.modal_run) against the Python-stepped path (`compiled="steps"`:
each step from Python, its Newton loop compiled, mechlib.solvers.genalpha.modal_step).

- Kane's spin-up beam (benchmarks.flexible: driven hub, a function of time read through
  mechlib.kinematics.time_functions), unstiffened and stiffened, 4 s at 1e-6, and the
  flexible slider-crank (34 modes, a crank at constant speed), 0.02 s at 1e-4: the same
  accepted and rejected steps, Newton iterations and factorisations, the compared signals
  (the tip's lag, the slider's x) to 1e-9 of their range (measured: bit for bit, here and
  over the bench's full runs: 2275, 1112 and 558 steps), and the kernel takes all but a few
  of the steps (measured: all but the first, whose differenced tangent is Python's: 96 of
  97, 96 of 97, 133 of 134).
- The driven hub follows its motion, a closed form: the hub angle recorded equals
  SpinUp's f(t) to 1e-9 rad at every output time (the function of time the kernel reads
  at each attempt's end; benchmarks.flexible_compare holds the tip lag against Exudyn).
- A motion whose function fails mid-run (a SolverFailure at t > 2.05 s): the compiled run
  stops before the step and the Python step raises it, so the run fails with the same
  message and keeps the same rows as the Python-stepped run.
- `functions_at` fills the functions at the time asked through the registered filler, and
  leaves them for NO_CALL.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mechlib
from benchmarks.flexible import SpinUp, _kane_lag, flexible_slider_crank, spin_up_beam
from mechlib.kinematics.time_functions import NO_CALL, calling, functions_at
from mechlib.solvers.genalpha import modal_run

from .test_compiled_forces import _kernel_steps

TOL_SAME = 1e-9  # of each signal's range


def _run(name: str, compiled: str, monkeypatch) -> tuple[mechlib.Solution, np.ndarray, int]:
    """The run, its compared signal and the steps the kernel took."""
    if name == "crank":
        mech, end, step, tol = flexible_slider_crank(), 0.02, 1e-3, 1e-4
        requests: list = [mechlib.PointKinematics("slider", "slider")]
    else:
        mech, end, step, tol = spin_up_beam(name == "stiffened"), 4.0, 0.1, 1e-6
        requests = [mechlib.PointKinematics("tip", "tip"), mechlib.JointCoordinate("hub", "hub")]
    spec = mechlib.Dynamic(end=end, step=step, tolerance=tol, compiled=compiled)
    sol, taken = _kernel_steps(mech, spec, (), requests, monkeypatch, modal_run.ModalRun)
    signal = sol.channels["slider.x"] if name == "crank" else _kane_lag(sol)
    return sol, np.asarray(signal), taken


@pytest.mark.parametrize("name", ["plain", "stiffened", "crank"])
def test_runs_equal_the_python_steps(name, monkeypatch):
    fast, fast_signal, taken = _run(name, "runs", monkeypatch)
    slow, slow_signal, none = _run(name, "steps", monkeypatch)
    assert none == 0
    for field in ("steps", "rejected_steps", "newton_iterations", "factorizations"):
        assert getattr(fast.stats, field) == getattr(slow.stats, field), field
    assert np.abs(fast_signal - slow_signal).max() <= TOL_SAME * np.ptp(slow_signal)
    assert taken >= fast.stats.steps - 5
    if name != "crank":
        hub = np.asarray(fast.channels["hub.value"])
        exact = np.array([SpinUp().value(t) for t in fast.time])
        assert np.abs(hub - exact).max() <= 1e-9


def test_functions_at_calls_the_filler():
    out = np.zeros((2, 3))

    def fill(t: float, values: np.ndarray) -> None:
        values[:] = [[t, 1.0, 0.0], [2.0 * t, 2.0, 0.0]]

    with calling(fill) as handle:
        functions_at(handle, 0.5, out)
    assert out.tolist() == [[0.5, 1.0, 0.0], [1.0, 2.0, 0.0]]
    functions_at(NO_CALL, 3.0, out)
    assert out.tolist() == [[0.5, 1.0, 0.0], [1.0, 2.0, 0.0]]


class _Failing(SpinUp):
    """SpinUp until 2.05 s, then a failure (an expression's math error, as
    loadcases.build.context.Guarded reports it)."""

    def value(self, t: float) -> float:
        if t > 2.05:
            raise mechlib.SolverFailure(f"motion spin: math domain error at t = {t:.6g} s", time=t)
        return super().value(t)


def test_a_failing_motion_keeps_the_rows_before_it(monkeypatch):
    runs = []
    for compiled in ("runs", "steps"):
        mech = spin_up_beam(False)
        mech.motions["spin"] = dataclasses.replace(mech.motions["spin"], function=_Failing())
        spec = mechlib.Dynamic(end=4.0, step=0.1, tolerance=1e-6, compiled=compiled)
        runs.append(mechlib.solve(mech, spec, requests=[], throw=False))
    fast, slow = runs
    assert not fast.ok and fast.message == slow.message
    assert fast.message.endswith("math domain error at t = 2.1 s")  # the first step past it
    assert len(fast.time) == len(slow.time) == 21  # 0 to 2.0 s
