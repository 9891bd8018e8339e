"""Dense rows left where the interpolant puts them (`Dynamic.project_rows` False,
mechlib.solvers.dense_unprojected): the accuracy companion's rows, which only serve a
comparison. The same steps as projected rows; the rows against the pendulum's closed form
(period T = 4 sqrt(I_O / (m g L/2)) K(sin^2(pi/4)), energy m g L) as projected rows meet
it, and against the projected rows themselves to the constraint residual the integrator
leaves."""

from __future__ import annotations

import dataclasses

import numpy as np

import mechlib

from ._models import PENDULUM_REQUESTS, Bar, hinged_bar, pendulum_errors
from .test_genalpha_compiled import _free_crank

# dense rows at 1e-8, projected or not (measured 3.98e-6 and 9.6e-6 both, the same to 1e-8)
TOL_PERIOD = 5e-6  # of the period: generalized-alpha's phase error
TOL_ENERGY = 2e-5  # of m g L: its numerical damping
# of each column's peak: the rows' positions as interpolated, off the position constraints
# by the interpolant's error (measured 3.6e-8 here; 1.2e-6 on the bench slider-crank's
# companion at tolerance 8e-6)
TOL_ROWS = 1e-6


def _both(model, analysis):
    """The run with projected rows and with rows as interpolated."""
    mech, initial, requests = model()
    projected = mechlib.solve(mech, analysis, initial=initial, requests=requests)
    left = dataclasses.replace(analysis, project_rows=False)
    return projected, mechlib.solve(mech, left, initial=initial, requests=requests)


def test_unprojected_rows_meet_the_pendulum_closed_form() -> None:
    bar = Bar()
    analysis = mechlib.Dynamic(3.0, 0.001, tolerance=1e-8, dense=True)
    projected, left = _both(lambda: (hinged_bar(bar), [], list(PENDULUM_REQUESTS)), analysis)
    assert left.ok and left.stats.steps == projected.stats.steps
    period, energy = pendulum_errors(left, bar)
    assert period < TOL_PERIOD and energy < TOL_ENERGY
    assert np.allclose((period, energy), pendulum_errors(projected, bar), rtol=1e-6, atol=0)


def test_unprojected_rows_agree_with_projected_ones() -> None:
    """The free slider-crank through its dead centres (reactions, angle) at 1e-6."""
    analysis = mechlib.Dynamic(1.0, 0.001, tolerance=1e-6, dense=True)
    projected, left = _both(_free_crank, analysis)
    assert left.ok and left.stats.steps == projected.stats.steps
    np.testing.assert_array_equal(left.time, projected.time)
    moved = 0.0
    for name, values in projected.channels.items():
        peak = np.abs(values).max()
        if peak > 1e-9:  # out-of-plane components at round-off have no scale
            moved = max(moved, np.abs(left.channels[name] - values).max() / peak)
    assert 0.0 < moved <= TOL_ROWS  # the rows were left unprojected, within the bound
