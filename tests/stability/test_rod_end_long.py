"""The full hard case of issue 3 item 12: steel ball in a steel socket (0.5 mm clearance,
Hertz, Lankarani-Nikravesh, Stribeck friction) under a 4 Hz duty cycle for 10 s.

It takes about 2 min (130 s measured 2026-11-21 on 2 cores, 120 721 steps): too long for the
suite's budget, so it runs when LOADS_SLOW=1; the suite runs one 0.25 s cycle of the same
model (test_contact_stability.py) with the 10x-tighter-tolerance comparison.
"""
from __future__ import annotations

import dataclasses
import os

import numpy as np
import pytest

import mechlib as ml
from tests.stability import test_contact_stability as short

pytestmark = pytest.mark.skipif(os.environ.get("LOADS_SLOW") != "1",
                                reason="10 s of steel contact: set LOADS_SLOW=1 (about 2 min)")


def test_ten_seconds_of_duty_cycle(monkeypatch) -> None:
    """No failure; steps below 200 000 (measured 120 721); the contact force never pulls and
    stays below 100 N (measured peak 56.7 N for 20 N of drive plus gravity); the ball ends
    against the socket wall at clearance + Hertz deflection (eccentricity within 5e-4 m
    and 5e-4 m + 1e-6 m)."""
    solve = ml.solve
    monkeypatch.setattr(short.ml, "solve", lambda m, an, **kw:
                        solve(m, dataclasses.replace(an, end=10.0), **kw))
    sol = short.rod_end()
    assert sol.ok
    assert sol.stats.steps < 200_000
    normal = sol.channels["socket.normal"]
    assert np.all(normal >= 0.0) and normal.max() < 100.0
    assert 5e-4 <= sol.channels["socket.eccentricity"][-1] <= 5e-4 + 1e-6
