"""The compiled quartic rise of a crest between rows (mechlib.outputs.crests) against closed
forms, and against numpy's LAPACK solve of the same systems (the path it replaced); a run's
crests matched with another run's (`crest_match`) against values worked by hand."""

from __future__ import annotations

import numpy as np

# the solver's kernels marked before this file's first call compiles the marked ones
# (tests/loadcases/test_set_warm.py counts only those, whichever test runs first)
import mechlib.solvers.solve  # noqa: F401
from mechlib.outputs.crests import crest_match, quartic_rises

OFFSETS = np.arange(-2, 3)


def _inputs(time: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(powers (k, 5, 5), scaled times (k, 5)) of each crest row's five rows."""
    near = time[rows[:, None] + OFFSETS]
    scaled = (near - time[rows, None]) / (0.5 * (near[:, 3] - near[:, 1]))[:, None]
    return scaled[:, :, None] ** np.arange(5), scaled


def _numpy_rises(table: np.ndarray, rows: np.ndarray, powers: np.ndarray, s: np.ndarray):
    """The rises as numpy computed them before (LAPACK's dgesv per crest, Newton in arrays)."""
    v = table[rows[:, None] + OFFSETS, 0] - table[rows, 0][:, None]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        coef = np.linalg.solve(powers, v[:, :, None])[:, :, 0]
        at = -coef[:, 1] / (2.0 * coef[:, 2])
        for _ in range(4):
            slope = coef[:, 1] + at * (2 * coef[:, 2] + at * (3 * coef[:, 3] + 4 * coef[:, 4] * at))
            bend = 2 * coef[:, 2] + at * (6 * coef[:, 3] + 12 * coef[:, 4] * at)
            at = at - slope / bend
        bend = 2 * coef[:, 2] + at * (6 * coef[:, 3] + 12 * coef[:, 4] * at)
        up = at * (coef[:, 1] + at * (coef[:, 2] + at * (coef[:, 3] + at * coef[:, 4])))
    inside = np.isfinite(up) & (bend < 0.0) & (s[:, 1] < at) & (at < s[:, 3]) & (up >= 0.0)
    return np.where(inside, up, np.nan)


def test_a_quartic_s_crest_is_read_exactly() -> None:
    """Rows of v(t) = 3 - (t - m)^2 - 40 (t - m)^4 at uneven times about a crest at m, 0.3
    of an interval from the middle row: the rise above that row is v(m) - v(t_2) in closed
    form (the quartic through five of its rows is itself), to 1e-12 of the rise."""
    time = np.array([0.0, 0.09, 0.2, 0.32, 0.41, 0.5])
    m = 0.2 + 0.3 * 0.12
    values = 3.0 - (time - m) ** 2 - 40.0 * (time - m) ** 4
    powers, scaled = _inputs(time, np.array([2]))
    one = (np.array([2]), np.array([0]))
    rise = quartic_rises(values[:, None], *one, powers, scaled, np.array([0]))
    expected = (m - 0.2) ** 2 + 40.0 * (m - 0.2) ** 4
    assert abs(rise[0] - expected) < 1e-12 * expected


def test_no_rise_where_the_quartic_has_no_maximum_between_the_neighbours() -> None:
    """A trough (the quartic curving up) and a straight line give nan; so do repeated times'
    exact zero pivots (the rows' powers singular), instead of LAPACK's error."""
    time = np.linspace(0.0, 0.4, 5)
    powers, scaled = _inputs(time, np.array([2]))
    one = (np.array([2]), np.array([0]))
    for values in ((time - 0.21) ** 2, 1.0 + 2.0 * time):
        assert np.isnan(quartic_rises(values[:, None], *one, powers, scaled, np.array([0]))[0])
    singular = np.ones((1, 5, 5))
    assert np.isnan(quartic_rises(-(time**2)[:, None], *one, singular, scaled, np.array([0]))[0])


def test_the_rises_are_lapack_s_to_the_last_bits() -> None:
    """On 200 noisy sines of 400 uneven rows (their 2808 crests) the rises are those of
    numpy's LAPACK solve (dgesv per crest) within 1e-11 of the rise and 1e-16 of the
    column's peak of 1 (measured: 7.2e-13 and 4.2e-17, a third of them bit for bit: another
    order of the same elimination), nan at the same crests."""
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(200):
        time = np.cumsum(rng.uniform(0.7e-2, 1.3e-2, 400))
        values = np.sin(rng.uniform(5.0, 40.0) * time) + 1e-5 * rng.standard_normal(400)
        rows = np.arange(2, 398)
        rows = rows[(values[rows] > values[rows - 1]) & (values[rows] > values[rows + 1])]
        powers, scaled = _inputs(time, rows)
        mine = quartic_rises(
            values[:, None], rows, np.zeros(len(rows), dtype=np.int64), powers, scaled,
            np.arange(len(rows)),
        )  # fmt: skip
        theirs = _numpy_rises(values[:, None], rows, powers, scaled)
        assert np.array_equal(np.isnan(mine), np.isnan(theirs))
        kept = ~np.isnan(mine)
        difference = np.abs(mine[kept] - theirs[kept])
        assert np.all(difference <= 1e-11 * np.abs(theirs[kept]))
        worst = max(worst, float(np.max(difference, initial=0.0)))
    assert worst < 1e-16


CREST, END_ROW = 0.0, 1.0  # a candidate's kind (loadcases.run.peak_error.END: an end row)


def test_crests_pair_with_the_highest_of_their_kind_within_the_window() -> None:
    """The run's crests at 0.1 s (its top, 1.0) and 0.5 s (0.99) and its end row at 1 s
    against the companion's: the top's partner is the companion's crest at 0.11 s (1.02),
    not its end row at 0.12 s (3.0: another kind) nor its crest at 0.3 s (outside 0.05 s);
    the crest at 0.5 s, extrapolated 0.99 + (0.99 - 0.95) / 3 = 1.003333, exceeds the top
    by 0.003333; its lower partner at 0.53 s (0.90) is not the highest within the window."""
    run = np.array([[0.1, 1.0, CREST], [0.5, 0.99, CREST], [1.0, 0.8, END_ROW]])
    companion = np.array(
        [
            [0.3, 7.0, CREST],
            [0.12, 3.0, END_ROW],
            [0.53, 0.90, CREST],
            [0.11, 1.02, CREST],
            [0.52, 0.95, CREST],
            [1.0, 0.81, END_ROW],
        ]
    )
    excess, partner = crest_match(run, 1.0, companion, 0.05, 1.0 / 3.0, -5.0)
    assert partner == 1.02
    assert excess == (0.99 + (0.99 - 0.95) / 3.0) - 1.0
    assert abs(excess - 1.0 / 300.0) < 1e-15


def test_no_partner_and_no_excess() -> None:
    """A top above every candidate (a plateau's row) or a crest with no partner of its kind
    near it gives the companion's extreme; extrapolations below the top give no excess (0,
    not negative); a finer run's negative scale extrapolates the other way."""
    run = np.array([[0.1, 1.0, CREST], [0.5, 0.9, CREST]])
    companion = np.array([[0.1, 0.98, END_ROW], [0.48, 0.95, CREST]])
    assert crest_match(run, 1.0, companion, 0.05, 1.0 / 3.0, -5.0) == (0.0, -5.0)
    assert crest_match(run, 1.2, companion, 0.05, 1.0 / 3.0, -5.0) == (0.0, -5.0)
    excess, _ = crest_match(run, 0.9, companion, 0.05, -4.0 / 3.0, -5.0)
    assert excess == (0.9 - 4.0 / 3.0 * (0.9 - 0.95)) - 0.9  # 0.0667: the finer run's
    assert crest_match(np.zeros((0, 3)), 1.0, companion, 0.05, 1.0 / 3.0, 2.0) == (0.0, 2.0)
