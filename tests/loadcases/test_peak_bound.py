"""The envelope estimate is bounded by the history estimate (loadcases.run.peak_error,
`peak_error`'s `bound`): a peak moves by at most the largest change of the curve, and crests
read through rows a sizeable part of a period apart are not read to better than that. A
linear spring-mass against its closed form x = x0 cos(w t), rows 30 ms apart (6.6 a period):
the displacement's and speed's envelope errors estimated within a factor 3 of the true ones
(they read 51 and 24 times the true error before the bound)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

STIFFNESS, MASS, X0 = 1000.0, 1.0, 0.1  # N/m, kg, m
OMEGA = math.sqrt(STIFFNESS / MASS)  # rad/s: a period of 0.199 s

CASE = f"""\
case: spring-mass-sparse-rows
mechanism:
  name: sm
  bodies:
    mass: {{mass: {MASS}, cm: [0, 0, 0], inertia: [0.01, 0.01, 0.01]}}
  points:
    m_eye: {{body: mass, at: [0, 0, 0]}}
    anchor: {{body: ground, at: [-1, 0, 0]}}
  joints:
    slide: {{type: prismatic, bodies: [mass, ground], at: [0, 0, 0], axis: [1, 0, 0]}}
  forces:
    spring: {{type: spring, points: [m_eye, anchor], stiffness: {STIFFNESS}, free_length: 1.0}}
initial:
  slide: {{value: {X0}, rate: 0}}
analysis: {{type: dynamic, end: 1.0, step: 0.03}}
requests:
  x: {{joint: slide, quantity: travel}}
  v: {{joint: slide, quantity: speed}}
"""


@pytest.fixture(scope="module")
def outcome(tmp_path_factory: pytest.TempPathFactory):
    path = Path(tmp_path_factory.mktemp("sparse")) / "sm.case.yaml"
    path.write_text(CASE)
    return run_case(load_case(path))


def test_the_envelope_estimate_is_within_a_factor_3_with_sparse_rows(outcome) -> None:
    """True envelope error: the rows' max and min against the closed form's +-x0 and
    +-x0 w (5 periods: every crest is reached), the worse, of the peak; the estimate is the
    summary's `peak`."""
    time = outcome.solution.time
    estimate = outcome.checks["accuracy"]["estimate"]
    for name, amplitude in (("x", X0), ("v", X0 * OMEGA)):
        values = outcome.solution.channels[f"{name}.value"]
        true = max(amplitude - values.max(), values.min() + amplitude) / amplitude
        assert true > 1e-3  # the rows miss the crests: a case where the bound matters
        assert 1 / 3 < estimate[name]["peak"] / true < 3, (name, estimate[name], true)
    # the history against x0 cos(w t) on the rows: the bound's own estimate holds
    x = outcome.solution.channels["x.value"]
    history = float(np.abs(x - X0 * np.cos(OMEGA * time)).max()) / X0
    assert 1 / 3 < estimate["x"]["history"] / history < 3
