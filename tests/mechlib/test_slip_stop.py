"""Where a sliding joint friction's slip reversal is located within a step
(mechlib.solvers.stick.slip_stop), on a friction whose slip rate is a given function of time.

- A slide through zero (0.167 rad/s -> -0.044 rad/s over the step, linear in time) is located
  at the zero of its rate, 0.167 / 0.211 of the step, within the event tolerance.
- A slide starting from within the regularised band (2e-8 rad/s, below the 1e-3 rad/s
  threshold: the joint just let go, or its stick was tried at the step's start and
  refused) and leaving it the other way is no reversal. It was located before, a hair
  after the start (4e-10 s into a 4.5 ms step of the BepiColombo wing's HL2 hinge), and
  the step re-solved over that sliver: generalized-alpha's velocity then read the
  position round-off over 4e-10 s (1.5e-6 off the velocity constraints, against the
  1e-5 of a whole step), and the next step's accelerations carried it (the in-orbit
  momentum check, tests/verification/test_solar_array.py, 6.5e-3 of its scale against
  the 1e-3 bound with the velocity carried by the step ratio, 2.8e-4 without that sliver).
"""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from mechlib.solvers.stick import slip_stop

THRESHOLD = 1e-3  # rad/s


class _Sliding:
    """A sliding joint friction whose slip rate is the view's `rate` (rad/s)."""

    active, can_stick, locked, stuck = True, True, False, False
    v_threshold = THRESHOLD

    @staticmethod
    def slip_rate(view) -> float:
        return view.rate


def _located(r0: float, r1: float, t0: float = 1.0, t1: float = 1.0045) -> float | None:
    system = SimpleNamespace(elements=[_Sliding()])

    def view_at(t: float) -> SimpleNamespace:  # the rate linear over the step
        return SimpleNamespace(rate=r0 + (r1 - r0) * (t - t0) / (t1 - t0))

    return slip_stop(system, t0, t1, view_at(t0), view_at(t1), view_at)


def test_a_slide_through_zero_is_located_at_its_zero() -> None:
    t = _located(0.167, -0.044)
    assert t is not None
    assert t == pytest.approx(1.0 + 0.0045 * 0.167 / 0.211, abs=1e-9)


def test_a_slide_from_within_the_band_is_no_reversal() -> None:
    assert _located(2e-8, -0.234) is None
    assert _located(-0.5 * THRESHOLD, 0.1) is None
    assert _located(2e-8, 0.234) is None  # no sign change either
