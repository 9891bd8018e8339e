"""Dense output is the default of a dynamic case (issue 14 item 2, 0.7.0): the values do
not depend on the output step; `output: steps` keeps steps on the output times; the
analyses without an integrator are built as before.

Reference: the same case at another output step (its rows at the common times must be
the same); the built mechlib analyses themselves.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

import mechlib as ml
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"


def _pendulum(**analysis):
    """The verification pendulum with its `analysis` keys updated (no accuracy estimate)."""
    cf = load_case(LIBRARY / "pendulum.case.yaml")
    updated = cf.case.analysis.model_copy(update={"accuracy": "off", **analysis})
    return dataclasses.replace(cf, case=cf.case.model_copy(update={"analysis": updated}))


def test_a_dynamic_case_is_dense_unless_it_says_steps() -> None:
    assert build_run(_pendulum()).analysis.dense is True
    assert build_run(_pendulum(output="dense")).analysis.dense is True
    assert build_run(_pendulum(output="steps")).analysis.dense is False


def test_analyses_without_an_integrator_are_unchanged() -> None:
    """Kinematic, quasi-static and static cases build the same analyses as in 0.6.0:
    output at every `step`, no integrator options."""
    kinematic = build_run(load_case(LIBRARY / "slider_crank.case.yaml")).analysis
    assert type(kinematic) is ml.Kinematic
    quasi = build_run(_pendulum(type="quasi-static", end=0.2, step=0.1)).analysis
    assert quasi == ml.QuasiStatic(end=0.2, step=0.1)
    assert build_run(_pendulum(type="static")).analysis == ml.Static(time=0.0)


def test_the_case_values_do_not_depend_on_the_output_step() -> None:
    """The pendulum case over 0.5 s at output steps 0.01 and 0.1 s: the same integrator
    steps and, at the common times, the same values to 1e-12 of each channel's peak
    (measured: identical; with `output: steps` they differ)."""
    fine = build_run(_pendulum(end=0.5, step=0.01)).solve()
    coarse = build_run(_pendulum(end=0.5, step=0.1)).solve()
    assert fine.ok and coarse.ok
    assert fine.stats.steps == coarse.stats.steps
    common = np.isin(np.round(fine.time, 9), np.round(coarse.time, 9))
    assert common.sum() == len(coarse.time) == 6
    for name, values in coarse.channels.items():
        peak = max(float(np.nanmax(np.abs(values))), 1e-9)
        assert np.nanmax(np.abs(fine.channels[name][common] - values)) <= 1e-12 * peak, name
