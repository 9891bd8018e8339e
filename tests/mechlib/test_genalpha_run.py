"""Runs of generalized-alpha steps in one compiled call (mechlib.solvers.genalpha.run), with
`output: steps` and with dense rows, against the Python loop they replace, and the motion
they give against closed forms.

- Whole runs with the compiled runs and with the Python loop alone (`compiled="steps"`)
  take the same accepted and rejected steps, Newton iterations, factorisations and
  Jacobian evaluations, and give every output to 1e-9 of its peak (measured 0 to 2.8e-10:
  the consistent accelerations at a new step size are solved with the kernel's LU solve,
  not LAPACK's getrs, and the free crank's dead centres amplify that round-off in its
  reactions; 0 to 1e-13 when those were Python's): the free slider-crank (dense LU
  factors, joint angles unwrapped past 180 deg), a 12-link chain (band LU factors, and
  SuperLU's) with steps landing on the output times, the crank, a 6-link chain and the
  12-link chain (48 equations, band factors) with dense rows (projected in the kernel).
  The kernel took every accepted step but at most two (measured: all but one or two,
  98.3-99.9 %; a new step size takes its consistent accelerations in the kernel, a
  rejected attempt is Python's; before that the kernel took 68-99 %); with SuperLU's
  factors at least 90 % (measured 94 %: its new step sizes in Python). Dense and band
  factors are refactored in the kernel (no factorisation in Python), SuperLU's in Python.
- Where the kernel cannot serve (a motion's time function, an armed event, dense rows of a
  system of more than 64 equations) the run is the Python loop's.
- The pendulum released from the horizontal (steps of 1 ms, tolerance 1e-8): its period
  meets the elliptic integral to 3e-6 (measured 1.5e-6) and its energy stays within 2e-5
  of m g L (measured 9.3e-6).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechlib
from mechlib.linalg import factor as linalg
from mechlib.solvers.genalpha import run as genalpha_run

from ._kernel_steps import count_kernel_steps
from ._models import PENDULUM_REQUESTS, Bar, falling_slider_crank, hinged_bar, pendulum_errors
from .test_genalpha_compiled import _chain, _free_crank

TOL_SAME = 1e-9  # of each output's peak
TOL_PERIOD = 3e-6  # measured 1.5e-6 (generalized-alpha's phase error at 1e-8)
TOL_ENERGY = 2e-5  # measured 9.3e-6 (its numerical damping, rho_inf < 1)


def _short_chain() -> tuple[mechlib.Mechanism, list, list]:
    """A 6-link chain: its dense rows are small enough for the compiled projection."""
    return _chain(6)


def _driven_crank() -> tuple[mechlib.Mechanism, list, list]:
    return falling_slider_crank(drive=3.0), [], [mechlib.JointReaction("A_force", "A")]


def _run(model, analysis, monkeypatch, *, compiled: bool, **kwargs):
    """The run of `model` with compiled runs (`Dynamic.compiled = "runs"`) or without
    (`"steps"`: every step from Python); also the steps the kernel took."""

    analysis = dataclasses.replace(analysis, compiled="runs" if compiled else "steps")
    with monkeypatch.context() as patch:
        taken = count_kernel_steps(patch)  # counts; the path is the analysis's
        mech, initial, requests = model()
        sol = mechlib.solve(mech, analysis, initial=initial, requests=requests, **kwargs)
    return sol, taken["steps"]


@pytest.mark.parametrize(
    ("model", "analysis"),
    [
        (_free_crank, mechlib.Dynamic(1.0, 0.001, tolerance=1e-4)),
        (_free_crank, mechlib.Dynamic(0.5, 0.002, tolerance=1e-7)),
        (_chain, mechlib.Dynamic(0.3, 0.005, tolerance=1e-6)),
        (_chain, mechlib.Dynamic(0.3, 0.005, tolerance=1e-6)),
        (_free_crank, mechlib.Dynamic(1.0, 0.001, tolerance=1e-4, dense=True)),
        (_free_crank, mechlib.Dynamic(1.0, 0.001, tolerance=1e-6, dense=True)),
        (_short_chain, mechlib.Dynamic(0.3, 0.005, tolerance=1e-6, dense=True)),
        (_chain, mechlib.Dynamic(0.3, 0.005, tolerance=1e-6, dense=True)),
    ],
    ids=[
        "free-slider-crank-1e-4",
        "free-slider-crank-1e-7",
        "chain-band",
        "chain-superlu",
        "dense-slider-crank-1e-4",
        "dense-slider-crank-1e-6",
        "dense-short-chain",
        "dense-chain-band",
    ],
)
def test_compiled_runs_equal_the_python_loop(model, analysis, monkeypatch, request) -> None:
    superlu = request.node.callspec.id == "chain-superlu"
    if superlu:  # no band LU: SuperLU's factors, made in Python between the calls
        monkeypatch.setattr(linalg, "BAND_SHARE", 0.0)
    in_python = {"factors": 0}
    original = genalpha_run.StepRun._refactor

    def refactor(self, *args):
        in_python["factors"] += 1
        return original(self, *args)

    monkeypatch.setattr(genalpha_run.StepRun, "_refactor", refactor)
    handed = {"steps": 0}  # calls that handed the next step to Python
    call = genalpha_run.StepRun._call

    def count_handed(self, *args):
        out = call(self, *args)
        handed["steps"] += out[2] in (genalpha_run.STOPPED, genalpha_run.FAILED)
        return out

    monkeypatch.setattr(genalpha_run.StepRun, "_call", count_handed)
    fast, in_kernel = _run(model, analysis, monkeypatch, compiled=True)
    slow, none = _run(model, analysis, monkeypatch, compiled=False)
    assert fast.ok and slow.ok
    # the rest: the first step, and the step after each call that hands one to Python (a
    # rejection below the floor, Newton stalling with an old matrix or failing with a new
    # one, a row given back: the slider-crank at 1e-4 through its dead centres, 6 of 149
    # since the step grows whenever the error law allows); with SuperLU's factors, also
    # the steps at a new step size (measured 94 %)
    least = 0.9 * fast.stats.steps if superlu else fast.stats.steps - 2 - handed["steps"]
    assert none == 0 and in_kernel >= least
    # dense and band LU factors are refactored in the kernel, SuperLU's in Python
    assert (in_python["factors"] > 0) if superlu else (in_python["factors"] == 0)
    names = ("steps", "rejected_steps", "newton_iterations", "factorizations")
    for name in (*names, "jacobian_evaluations"):
        assert getattr(fast.stats, name) == getattr(slow.stats, name), name
    assert fast.warnings == slow.warnings
    np.testing.assert_array_equal(fast.time, slow.time)
    for name, values in slow.channels.items():
        peak = np.abs(values).max()
        if peak > 1e-9:  # components at round-off (out-of-plane ones) have no scale
            assert np.abs(fast.channels[name] - values).max() <= TOL_SAME * peak, name


def test_the_crank_turns_past_half_a_turn_in_the_kernel(monkeypatch) -> None:
    """The free crank's angle, unwrapped by the kernel, runs on past pi (a full turn in
    1 s at about 2 pi rad/s) as in the Python loop."""
    fast, _ = _run(_free_crank, mechlib.Dynamic(1.0, 0.001, tolerance=1e-4), monkeypatch,
                   compiled=True)  # fmt: skip
    angle = fast.channels["A_angle.value"]
    assert angle.max() > 1.5 * math.pi and np.all(np.diff(angle) > 0.0)


@pytest.mark.parametrize("case", ["motion", "event", "large-dense"])
def test_what_the_kernel_cannot_serve_goes_to_python(case, monkeypatch) -> None:
    """A motion's time function, an armed event, and dense rows of a system of more than
    SCHUR_ROWS (64) equations (a 20-link chain: 80; its rows' dense Schur complement would
    cost more than the Python path's band solves)."""
    analysis = mechlib.Dynamic(0.2, 0.002, tolerance=1e-6)
    if case == "motion":
        sol, in_kernel = _run(_driven_crank, analysis, monkeypatch, compiled=True)
    elif case == "large-dense":
        analysis = mechlib.Dynamic(0.1, 0.005, tolerance=1e-6, dense=True)
        sol, in_kernel = _run(lambda: _chain(20), analysis, monkeypatch, compiled=True)
    else:
        stop = mechlib.Event("turned", lambda t, view: view.angle("A") - 10.0, ())
        sol, in_kernel = _run(_free_crank, analysis, monkeypatch, compiled=True, events=[stop])
    assert sol.ok and in_kernel == 0


def test_pendulum_through_compiled_runs_meets_the_closed_form(monkeypatch) -> None:
    """A bar released from the horizontal swings through 180 deg and back with the period
    T = 4 sqrt(I_O / (m g L/2)) K(sin^2(pi/4)); m g (L/2) sin(theta) + I_O omega^2 / 2
    stays near m g L."""
    bar = Bar()

    def model():
        return hinged_bar(bar), [], list(PENDULUM_REQUESTS)

    sol, in_kernel = _run(
        model, mechlib.Dynamic(3.0, 0.001, tolerance=1e-8), monkeypatch, compiled=True
    )
    assert sol.ok and in_kernel > 0.5 * sol.stats.steps
    period, energy = pendulum_errors(sol, bar)
    assert period < TOL_PERIOD and energy < TOL_ENERGY
