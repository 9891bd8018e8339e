"""The envelope peak's error estimate (loadcases.run.peak_error) against closed forms:
a sine sampled at rows that miss its crest, and two runs whose peaks differ by a known
amount."""

from __future__ import annotations

import math

import numpy as np
import pytest

from loadcases.run.peak_error import (
    _cubic_rise,
    _quartic_rise,
    extremes,
    extremes_of,
    peak_error,
    row_peaks,
)

DT = 0.01  # s, output interval
OMEGA = 2.0 * math.pi * 1.3  # rad/s


def _rows(shift: float, amplitude: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    time = np.arange(0.0, 0.6 + DT / 2, DT)  # one crest and one trough
    return time, amplitude * np.sin(OMEGA * time + shift)


def test_the_continuous_peak_is_found_between_rows() -> None:
    """sin's crest of 1 between rows: the rows miss it by up to (omega dt / 2)^2 / 2 =
    8.3e-4; the parabola's vertex is within (omega dt)^3 / 16 = 3.3e-5 of it (order 3)."""
    time, values = _rows(0.3)
    found = extremes(time, values)
    assert 1.0 - found.row_max > 1e-4  # the rows miss the crest
    assert abs(found.max - 1.0) < (OMEGA * DT) ** 3 / 16
    assert abs(found.min + 1.0) < (OMEGA * DT) ** 3 / 16
    assert found.row_max == float(values.max()) and found.row_min == float(values.min())


def test_an_end_row_or_a_kink_has_no_vertex() -> None:
    """A ramp's peak at its last row, a triangle's apex on a row: the row is the peak."""
    time = np.linspace(0.0, 1.0, 11)
    ramp = extremes(time, 3.0 * time)
    assert (ramp.max, ramp.min) == (3.0, 0.0)
    tent = extremes(time, 1.0 - np.abs(time - 0.5))
    # a kink's vertex: the parabola through a symmetric apex has zero slope there
    assert tent.max == pytest.approx(1.0, abs=1e-15)


def test_a_crest_between_the_end_row_and_the_row_beside_it_is_found() -> None:
    """sin's crest of 1 a fifth of a row interval before the last row (and, mirrored, after
    the first): no row is a crest, the end row misses it by (omega dt / 5)^2 / 2, and the
    cubic through the four end rows finds it (order 4: within (omega dt)^4 of it)."""
    time = np.arange(0.0, 0.3 + DT / 2, DT)
    last = extremes(time, np.sin(OMEGA * (time - time[-1] + 0.2 * DT) + math.pi / 2))
    first = extremes(time, np.sin(OMEGA * (time[0] + 0.2 * DT - time) + math.pi / 2))
    for found in (last, first):
        assert 1.0 - found.row_max > 1e-5  # the end row misses the crest
        assert abs(found.max - 1.0) < (OMEGA * DT) ** 4


def test_peak_error_bounds_richardson_on_continuous_peaks_plus_the_rows_miss() -> None:
    """Run amplitude 1 + 1e-3, companion (order 2: 4 x its error) 1 + 4e-3, exact 1: the
    Richardson part is 3e-3 / 3 = 1e-3 (within 5e-5), the sampling part the run's miss of
    its own crest, computed exactly here; the estimate bounds the true error of the run's
    row peak, which is their difference (they have opposite signs)."""
    run_t, run_v = _rows(0.3, 1.0 + 1e-3)
    comp_t = run_t[1::2]  # rows at 2 dt, not those of the run's crest
    comp_v = (1.0 + 4e-3) * np.sin(OMEGA * comp_t + 0.3)
    found = extremes(run_t, run_v), extremes(comp_t, comp_v)
    estimate, sampling = peak_error(*found, scale=1.0 / 3.0)
    miss = (1.0 + 1e-3) * (1.0 - np.sin(OMEGA * run_t + 0.3).max())
    assert miss > 1e-4
    assert sampling == pytest.approx(miss, abs=(OMEGA * DT) ** 3 / 16)
    assert estimate - miss == pytest.approx(1e-3, abs=5e-5)
    true = max(abs(run_v.max() - 1.0), abs(run_v.min() + 1.0))
    assert true <= estimate <= true + 2.0 * miss + 5e-5
    # the companion's own missed crest (4x the run's) would enter the plain difference
    naive = max(abs(run_v.max() - comp_v.max()), abs(run_v.min() - comp_v.min())) / 3
    assert abs(naive - 1e-3) > abs(estimate - miss - 1e-3)


def test_noise_on_the_rows_does_not_read_as_a_missed_crest() -> None:
    """A flat crest (curvature 1e-3 /s^2, on a row) whose two neighbours carry noise of
    -1e-6 and -1e-7: the three-row parabola reads a crest 7.8e-8 above the row
    ((a - b)^2 / (8 (a + b)) with drops a, b), the rows two apart bound it by their
    curvature to 1e-3 (dt / 2)^2 = 2.5e-8."""
    time = np.arange(-0.05, 0.05 + DT / 2, DT)
    values = 1.0 - 1e-3 * time**2
    centre = len(time) // 2
    values[centre - 1] -= 1e-6
    values[centre + 1] -= 1e-7
    a, b = values[centre] - values[centre - 1], values[centre] - values[centre + 1]
    assert (a - b) ** 2 / (8.0 * (a + b)) > 7e-8  # what the three rows alone would say
    found = extremes(time, values)
    assert 0.0 <= found.max - found.row_max <= 2.5e-8 * 1.01


def test_a_step_has_no_crest_between_rows() -> None:
    """A column that steps from 0 to a constant (a friction torque switching on: the
    repro wheel's `rub`, 0 then 0.981 N m) has no peak between its rows: the corner of the
    step is not a vertex (it read 4.4 % of the peak and a false accuracy warning)."""
    time = np.linspace(0.0, 1.0, 101)
    values = np.full_like(time, 0.981)
    values[0] = 0.0
    found = extremes(time, values)
    assert found.max == found.row_max == 0.981
    assert found.min == found.row_min == 0.0


def test_a_leap_at_the_start_is_not_a_crest() -> None:
    """The IFToMM A05 flyball's spring tension in its first rows (N, 10 ms apart): 0 at
    rest, then 44.28, 42.90, 44.90, 44.54. The parabola through the first three alone
    reads a crest 5.0 N above 44.28 (its estimate was 4 times the true error); the
    parabola through the rows after it curves up, so the leap is no crest: its row is its
    value. A smooth crest (a sine sampled 10 times a period) keeps its vertex."""
    time = np.arange(5) * 0.01
    values = np.array([0.0, 44.28, 42.90, 44.90, 44.54])
    assert extremes(time, values).max == 44.90  # row 3: the rows before it curve up
    values[3:] = [42.0, 41.5]  # no later crest: the leap's row is the largest
    assert extremes(time, values).max == 44.28
    sine_t = np.linspace(0.0, 1.0, 11) + 0.03
    sine = np.sin(2.0 * np.pi * sine_t)
    found = extremes(sine_t, sine)
    assert found.row_max < found.max <= 1.0 + 1e-3


def test_an_end_across_an_event_has_no_crest() -> None:
    """The door jettison's hinge rate (rad/s) in its first rows: 0 until its rod is
    disconnected at 1 ms (an event, its row the state before), then rising. The cubic
    through the four first rows spans that kink and reads a trough 3.3e-3 below the
    first row (the envelope's estimate was 8.6 times its true error, 1.0 without); with
    the event known the end is its row. A stop at the last row is no break: its end's
    cubic is kept (the same trough read when the only event is the last row's)."""
    time = np.array([0.0, 0.001, 0.002, 0.004, 0.006, 0.008])
    rate = np.array([0.0, 2.4e-16, 0.0191057833, 0.0572220371, 0.0954446939, 0.133447104])
    assert extremes(time, rate).min < -3e-3
    assert extremes(time, rate, [0.001]).min == 0.0
    assert extremes(time, rate, [0.008]).min == extremes(time, rate).min
    mirrored = extremes(-time[::-1], rate[::-1], [-0.001])  # the same at the last rows
    assert mirrored.min == 0.0 and extremes(-time[::-1], rate[::-1]).min < -3e-3


def _two_crests(rows: float, first: float, second: float) -> tuple[np.ndarray, np.ndarray]:
    """Rows `rows` s apart over 1 s of two parabolic crests, heights `first` (t = 0.24 s)
    and `second` (t = 0.76 s), above a floor of 0.5: the crests lie on every grid used
    here, so each vertex is its row and the rows' miss is nil."""
    time = np.round(np.arange(0.0, 1.0 + rows / 2, rows), 12)
    values = np.maximum.reduce(
        [first - 50.0 * (time - 0.24) ** 2, second - 50.0 * (time - 0.76) ** 2, 0.5 + 0 * time]
    )
    return time, values


def test_a_competing_crest_is_extrapolated() -> None:
    """The truth's crests 1.0 and 1.002; the run's errors +1e-4 and -3e-3 (its peak the
    first, 1.0001), the companion's 4 times as large (1.0004 and 0.990): the peaks of the
    two runs agree to 3e-4, where the true error of the run's peak is 1.9e-3 (the truth's
    is the second crest). The second crest's extrapolation, 0.999 + (0.999 - 0.990) / 3 =
    1.002, exceeds the run's peak by that 1.9e-3 (exact for an order-2 error)."""
    run = extremes(*_two_crests(0.01, 1.0001, 0.999))
    companion = extremes(*_two_crests(0.02, 1.0004, 0.990))
    estimate, sampling = peak_error(run, companion, scale=1.0 / 3.0)
    assert sampling == 0.0
    assert estimate == pytest.approx(1.9e-3, abs=1e-9)
    assert abs(run.max - companion.max) / 3.0 == pytest.approx(1e-4, abs=1e-9)  # the top alone
    # the same from a finer run (steps half as long: its errors a quarter of the run's),
    # Richardson's (fine - run) / (2^-2 - 1): scale -4/3
    fine = extremes(*_two_crests(0.01, 1.000025, 1.002 - 0.00075))
    estimate, _ = peak_error(run, fine, scale=-4.0 / 3.0)
    assert estimate == pytest.approx(1.9e-3, abs=1e-9)


def test_a_thinned_companion_compares_its_peak_only() -> None:
    """A companion whose rows are 8 times as far apart as the run's (thinned: its single
    crests carry a vertex error up to 8^3 times the run's): only the peaks are compared."""
    run = extremes(*_two_crests(0.01, 1.0001, 0.999))
    companion = extremes(*_two_crests(0.08, 1.0004, 0.990))
    estimate, _ = peak_error(run, companion, scale=1.0 / 3.0)
    assert estimate == pytest.approx(1e-4, abs=1e-9)


def test_a_noisy_long_column_is_compared_in_linear_memory() -> None:
    """200 001 rows of noise (about 67 000 crests in each run): the crests are matched by
    bisection (an all-pairs comparison took 20 GB on IFToMM A01 over 2000 s), and a
    companion that reads the same noise adds no excess."""
    rng = np.random.default_rng(7)
    time = np.linspace(0.0, 2000.0, 200_001)
    values = 1e-9 * rng.standard_normal(len(time))
    run = extremes(time, values)
    assert len(run.tops) > 60_000
    estimate, _ = peak_error(run, extremes(time[::2], values[::2]), scale=1.0 / 3.0)
    assert estimate < 1e-8


def test_a_sparse_crest_is_read_by_the_quartic_through_five_rows() -> None:
    """A cosine sampled 15 rows a period (the closed-valve servo's companion: its 84 Hz
    ringing at 0.8 ms rows), its crest at every phase between two rows: the parabola
    through three rows misses the crest by up to 7.1e-4 of the amplitude (measured here: 7e-4
    of an error the integrator makes below 1e-5, the stroke's estimate 4 times its true
    error), the quartic through five rows by at most 2.3e-5 (order 6 in the row interval;
    closed form: the crest is 1)."""
    h = 2.0 * math.pi / 15.0
    worst_quartic = worst_parabola = 0.0
    # crests up to 0.45 of a row interval from a row: nearer half way the bound from the
    # curvature of the rows beside (the leap's guard, the same as before) caps the rise
    for phase in np.linspace(-0.45, 0.45, 37):
        time = (np.arange(-3, 4) + phase) * h
        values = np.cos(time)
        worst_quartic = max(worst_quartic, abs(extremes(time, values).max - 1.0))
        slope = (values[4] - values[2]) / (2.0 * h)
        c = (values[4] - 2.0 * values[3] + values[2]) / (2.0 * h * h)
        parabola = values[3] - slope**2 / (4.0 * c)
        worst_parabola = max(worst_parabola, abs(parabola - 1.0))
    assert worst_parabola > 5e-4  # what the crest's three rows alone say
    assert worst_quartic < 3e-5


def test_the_run_s_peak_is_compared_with_the_same_crest_of_the_companion() -> None:
    """The truth's crests 1.0 (t = 0.24 s) and 0.99 (0.76 s); the run's errors +1e-4 at
    both, the companion's +4e-4 at the first (Richardson's range: 4 times) and +0.02 at the
    second (outside it, as a stiff spring's unresolved ringing: IFToMM A05's hinge force),
    so the companion's peak is its second crest. The run's peak is its first crest, whose
    error (1e-4) is Richardson on that crest in both runs, (1.0004 - 1.0001) / 3; the two
    peaks' difference would read 0.0099 / 3 = 3.3e-3, 33 times it. The second crest's
    extrapolation (0.9901 - 0.0199 / 3) competes with nothing."""
    run = extremes(*_two_crests(0.01, 1.0001, 0.9901))
    companion = extremes(*_two_crests(0.02, 1.0004, 1.01))
    estimate, sampling = peak_error(run, companion, scale=1.0 / 3.0)
    assert sampling == 0.0
    assert estimate == pytest.approx(1e-4, abs=1e-9)
    assert abs(run.max - companion.max) / 3.0 == pytest.approx(3.3e-3, abs=1e-9)


def test_a_repeated_time_among_a_crest_s_five_rows_is_no_quartic() -> None:
    """An event's row repeats a time two rows before a crest: the five rows have no
    interpolating quartic (its matrix is singular); the rise is nan, for the parabola to be
    used, not an error (extremes itself leaves such a crest to the parabola's rules: the
    parabola beside it through the repeated time has no curvature)."""
    time = np.array([0.0, 0.1, 0.1, 0.2, 0.3, 0.4, 0.5])
    values = np.sin(np.pi * time / 0.5 + 0.3)
    rise = _quartic_rise(time, values, np.array([3, 4]))
    assert np.isnan(rise[0])
    assert np.isfinite(rise[1])  # rows 2-6: distinct times
    assert extremes(time, values).row_max == float(values.max())


def test_a_peak_on_a_plateau_is_compared_with_the_companion_s_peak() -> None:
    """The run's peak on a plateau (two equal rows: no crest, its row its value; 1.0 at
    0.5-0.51 s) above a lower crest (0.9 at 0.2 s): the plateau is no candidate, so the
    companion's value there is its own peak (0.997: Richardson 1e-3), not its value at the
    lower crest (0.9 + 3e-3, which would read 0.0323)."""
    time = np.round(np.arange(0.0, 1.0 + 0.005, 0.01), 12)
    crest = 0.9 - 50.0 * (time - 0.2) ** 2
    run_v = np.maximum(crest, np.where((time >= 0.5) & (time <= 0.51), 1.0, 0.5))
    comp_t = time[::2]
    comp_v = np.maximum(crest[::2] + 3e-3, np.where(comp_t == 0.5, 0.997, 0.5))
    estimate, sampling = peak_error(extremes(time, run_v), extremes(comp_t, comp_v), 1.0 / 3.0)
    assert sampling == 0.0
    assert estimate == pytest.approx(1e-3, abs=1e-9)


def test_columns_at_once_are_the_columns_one_by_one() -> None:
    """`extremes_of` over a table (crests, troughs, two columns cresting on the same rows,
    an end crest, a column with a nan row, one without a finite row) gives each column's
    extremes bit for bit as `extremes` of that column alone does: numpy over the columns
    changes no arithmetic."""
    time = np.round(np.arange(0.0, 0.6 + DT / 2, DT), 12)
    gappy = np.cos(OMEGA * time)
    gappy[7] = np.nan
    table = np.column_stack(
        (
            np.sin(OMEGA * time + 0.3),
            0.5 * np.sin(OMEGA * time + 0.3) + 0.2,  # its crests on the same rows
            2.0 * np.sin(OMEGA * (time - time[-1] + 0.2 * DT) + math.pi / 2),  # end crest
            gappy,
            np.full(len(time), np.nan),
            3.0 * time,
        )
    )
    together = extremes_of(time, table)
    for j, found in enumerate(together):
        alone = extremes(time, table[:, j])
        for name in ("row_max", "row_min", "max", "min", "interval"):
            assert getattr(found, name) == getattr(alone, name)
        assert np.array_equal(found.tops, alone.tops)
        assert np.array_equal(found.bottoms, alone.bottoms)


def test_the_end_crest_s_cubic_reads_a_cubic_s_maximum() -> None:
    """Four rows (s = -3 to 0, rows 0.01 s apart) of the cubic v = 1 + (s + 0.4)^2 (s - 2)
    / 4, whose slope -- (s + 0.4)(3 s - 3.6) / 4 -- vanishes at s = -0.4 (its maximum, v = 1)
    and s = 1.2 (past the last row): the rise above the last row (v = 0.92) is 0.08 by the
    closed form, read within 1e-12; and capped at `down` times the row interval squared."""
    s = np.array([-3.0, -2.0, -1.0, 0.0])
    v = 1.0 + (s + 0.4) ** 2 * (s - 2.0) / 4.0
    assert _cubic_rise(0.01 * s, v, down=1e9) == pytest.approx(0.08, abs=1e-12)
    assert _cubic_rise(0.01 * s, v, down=0.5) == pytest.approx(0.5 * 0.01**2, abs=1e-15)
    assert _cubic_rise(0.01 * s, -v, down=1e9) == 0.0  # a trough: no crest


def test_the_value_just_after_an_event_between_rows_is_read() -> None:
    """The door jettison's top acceleration (m/s^2): 0 until its rod is disconnected at
    1 ms, an event between the rows at 0 and 2 ms (its row the state before), then
    19.168 - 27.8 (t - 0.001) + 300 (t - 0.001)^2 (a parabola: read exactly). The rows' top
    is 19.140 at 2 ms; the peak is the jump's top at the event, from the parabola through
    the first three rows after it. Harmless cases: the same rows with the event's row
    after its actions as well (an output time at the event) or a value rising after the
    event (its top is a later row) or continuous at it (a kink: its top is the event's
    row) read their rows' top, and so do rows without events."""
    time = np.array([0.0, 0.001, 0.002, 0.004, 0.006, 0.008])
    after = 19.168 - 27.8 * (time - 0.001) + 300.0 * (time - 0.001) ** 2
    values = np.where(time > 0.001, after, 0.0)
    found = extremes(time, values, [0.001])
    assert found.row_max == pytest.approx(19.1405, abs=1e-9)
    assert found.max == pytest.approx(19.168, abs=1e-12)
    assert extremes(time, values).max == found.row_max  # no event known: its rows
    both = extremes(np.insert(time, 2, 0.001), np.insert(values, 2, 19.168), [0.001])
    assert both.max == pytest.approx(19.168, abs=1e-12) == both.row_max
    rising = extremes(time, np.where(time > 0.001, 19.0 + 27.8 * time, 0.0), [0.001])
    assert rising.max == rising.row_max
    continuous = np.where(time > 0.001, after - 19.168, 0.0) + 1.0 + 1e-4 * time  # a kink
    assert extremes(time, continuous, [0.001]).max == extremes(time, continuous).row_max


def _pulse(time: np.ndarray, error: float) -> np.ndarray:
    """A contact pulse of 1335 N at 0.648 s, 3 ms wide (the door let go's guide force),
    with a relative error `error`."""
    return 1335.0 * (1.0 + error) * np.exp(-(((time - 0.648) / 0.003) ** 2))


def test_a_one_row_spike_is_compared_at_its_row_and_its_miss_read_on_the_companion() -> None:
    """Rows every 10 ms see the pulse at one row (855 N at 0.65 s, 1 N beside): its
    envelope misses the crest by 480 N, which no parabola through the rows can read. The
    companion (error 4 times the run's, 1e-3) with rows every 20 ms and at quarters of the
    run's intervals about 0.65 s (loadcases.run.companion.spikes) reads the crest there:
    the estimate is within 10 % of the true error (the run's row against the truth's
    crest); with the companion's rows only every 20 ms the spike's row is compared with
    another place's value (the companion's largest row, 25 N at 0.64 s)."""
    time = np.round(np.arange(0.6, 0.7 + 1e-9, 0.01), 12)
    run = extremes(time, _pulse(time, 1e-3))
    true = 1335.0 - run.row_max
    assert true > 400.0 and run.max == run.row_max  # the rows miss it; no crest read
    fine = np.round(0.65 + 0.0025 * np.arange(-3, 4), 12)
    sparse = np.round(np.arange(0.6, 0.7 + 1e-9, 0.02), 12)
    rows = np.union1d(sparse, fine)
    estimate, sampling = peak_error(run, extremes(rows, _pulse(rows, 4e-3)), 1.0 / 3.0)
    assert estimate == pytest.approx(true, rel=0.1)
    assert sampling > 0.9 * (estimate - 3e-3 * 855.0)  # the miss, beside Richardson's part
    other = extremes(sparse, _pulse(sparse, 4e-3))
    without, _ = peak_error(run, other, 1.0 / 3.0)  # the spike against another place
    assert without == pytest.approx((run.row_max - other.max) / 3.0)


def test_a_column_ringing_faster_than_its_rows_has_no_one_row_spike() -> None:
    """A motion the rows do not resolve zigzags from row to row (modes the steps do not
    resolve: the flexible pendulum's tip deformation, 49 of 101 rows standing out): its
    largest row is one swing of many (4 or more rows standing out within 5 either side),
    not a spike, and is estimated as a crest (that pendulum's envelope estimate 5.46 ->
    1.29 times its true error). An isolated pulse among the same rows stays a spike."""
    time = np.round(np.arange(0.0, 1.0 + 1e-9, 0.01), 12)
    ringing = np.sin(2.0 * np.pi * 47.0 * time) * (1.0 + 0.3 * time)  # 47 Hz at 100 rows/s
    assert row_peaks(extremes(time, ringing)) == []
    pulse = np.zeros_like(time)
    pulse[50] = 855.0
    assert row_peaks(extremes(time, pulse)) == [0.5]
    pulse[52] = 300.0  # a second, smaller contact row after the pulse: 3 rows stand out
    assert row_peaks(extremes(time, pulse)) == [0.5]
    pulse[48] = 300.0  # and one before it: 4 standing out within 5 rows of it, a zigzag
    assert row_peaks(extremes(time, pulse)) == []


def _powers(scaled: np.ndarray) -> np.ndarray:
    """The powers `_quartic_rise` takes: once a distinct row of `scaled` (told apart by
    their bits, as mechlib.outputs.crests.scaled_groups does), each row's from its
    distinct row's (`_distinct_powers`)."""
    from loadcases.run.peak_error import _distinct_powers

    keys = np.ascontiguousarray(scaled).view(np.dtype((np.void, 8 * scaled.shape[1])))[:, 0]
    _, first, each = np.unique(keys, return_index=True, return_inverse=True)
    return _distinct_powers(scaled[first])[each]


def test_the_quartic_s_scaled_times_are_grouped_by_their_bits() -> None:
    """`scaled_groups` (compiled) gives each crest row's five scaled times as numpy's arrays
    compute them, bit for bit, from its group of equal bits (even rows share one; a row
    whose five times do not all increase, an event's repeated time, or that lies within
    two rows of an end is not fitted)."""
    from mechlib.outputs.crests import scaled_groups

    rng = np.random.default_rng(23)
    for _ in range(50):
        even = np.arange(int(rng.integers(5, 200))) * 1e-3
        time = np.concatenate((even, even[-1] + np.cumsum(rng.uniform(5e-4, 2e-3, 100))))
        if rng.random() < 0.5:
            time[len(time) // 2] = time[len(time) // 2 - 1]  # an event's two rows of one time
        rows = rng.integers(0, len(time), 300)
        fitted, distinct, which = scaled_groups(time, rows)
        inside = (rows >= 2) & (rows <= len(time) - 3)
        steps = np.diff(time) > 0.0
        increasing = np.zeros(len(rows), dtype=bool)
        r = rows[inside]
        increasing[inside] = steps[r - 2] & steps[r - 1] & steps[r] & steps[r + 1]
        assert np.array_equal(fitted, increasing)
        kept = rows[fitted]
        near = time[kept[:, None] + np.arange(-2, 3)]
        scaled = (near - time[kept, None]) / (0.5 * (near[:, 3] - near[:, 1]))[:, None]
        assert np.array_equal(distinct[which].view(np.int64), scaled.view(np.int64))
        assert len(distinct) == len(np.unique(scaled.view(np.int64), axis=0))


def test_the_quartic_s_powers_are_numpy_s_to_the_last_bit() -> None:
    """The five scaled times' powers of each crest (`_powers`: powers 0 and 1 and the
    crest's own row set, the others by numpy's power) are `scaled[:, :, None] **
    np.arange(5)` bit for bit, on 100 runs of 500 rows with uneven intervals (+-30 %)."""
    rng = np.random.default_rng(5)
    for _ in range(100):
        steps = rng.uniform(1e-4, 1e-2) * (1.0 + 0.3 * rng.uniform(-1.0, 1.0, 500))
        time = np.cumsum(steps) + rng.uniform(0.0, 100.0)
        rows = np.arange(2, 498)
        near = time[rows[:, None] + np.arange(-2, 3)]
        scaled = (near - time[rows, None]) / (0.5 * (near[:, 3] - near[:, 1]))[:, None]
        expected = scaled[:, :, None] ** np.arange(5)
        assert np.array_equal(_powers(scaled).view(np.int64), expected.view(np.int64))


def test_the_quartic_s_powers_of_repeated_rows_are_the_same_bits() -> None:
    """Rows of the same bits are taken once (`_powers`): even output rows (the same scaled
    times again and again, as a run's dense rows give them) among uneven ones, a signed
    zero and none at all give `scaled[:, :, None] ** np.arange(5)` bit for bit."""
    rng = np.random.default_rng(11)
    time = np.concatenate((np.arange(300) * 1e-3, 0.3 + np.cumsum(rng.uniform(5e-4, 2e-3, 200))))
    rows = np.arange(2, len(time) - 2)
    near = time[rows[:, None] + np.arange(-2, 3)]
    scaled = (near - time[rows, None]) / (0.5 * (near[:, 3] - near[:, 1]))[:, None]
    scaled[7, 0] = -0.0  # the bits of -0.0 kept apart from those of +0.0 (cubes differ)
    scaled[8, 0] = 0.0
    assert len(np.unique(scaled, axis=0)) < len(scaled) // 2  # the rows do repeat
    for table in (scaled, scaled[:0]):
        expected = table[:, :, None] ** np.arange(5)
        assert np.array_equal(_powers(table).view(np.int64), expected.view(np.int64))


def _beside(c: np.ndarray) -> np.ndarray:
    """Per interior row: the smaller downward curvature -c (at least 0) of the parabolas
    through the row before and the row after (one of them at the first and last)."""
    down = np.maximum(-c, 0.0)
    out = np.full_like(down, np.inf)
    out[1:] = down[:-1]
    out[:-1] = np.minimum(out[:-1], down[1:])
    return out


def _rises_over_every_row(time: np.ndarray, values: np.ndarray, crest: np.ndarray):
    """The crests' rises as `_highest` took them before, over every row in numpy (the
    reference of the compiled mechlib.outputs.crests.crest_bounds)."""
    from loadcases.run import peak_error

    _curvature = peak_error._curvature
    slope, c = _curvature(time, values, 1)
    h = np.maximum(np.diff(time)[:-1], np.diff(time)[1:])[:, None]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        rise = -(slope**2) / (4.0 * c)
        bound = -c * (0.5 * h) ** 2
        if len(values) >= 5:
            _, wide = _curvature(time, values, 2)
            bound[1:-1] = np.minimum(bound[1:-1], np.maximum(-wide, 0.0) * (0.5 * h[1:-1]) ** 2)
        if len(values) >= 4:
            bound = np.minimum(bound, _beside(c) * (0.5 * h) ** 2)
    local = crest & (c < 0.0) & np.isfinite(rise) & np.isfinite(bound)
    inner, columns = np.nonzero(local[1:-1])
    if len(inner):
        fine = peak_error._quartic_rise(time, values, inner + 2, columns)
        rise[inner + 1, columns] = np.where(np.isfinite(fine), fine, rise[inner + 1, columns])
    return local, np.where(local, np.minimum(rise, bound), 0.0)


def _highest_over_every_row(time: np.ndarray, values: np.ndarray, events: np.ndarray):
    """`_highest` as numpy took it before, over every row and column at once (the reference
    of the compiled mechlib.outputs.crests.crest_table and crest_tops)."""
    from loadcases.run import peak_error

    row_max = np.max(np.where(np.isfinite(values), values, -np.inf), axis=0)
    ends = peak_error._ends(time, values, events)
    v1 = values[1:-1]
    crest = (v1 > values[:-2]) & (v1 > values[2:])
    crest &= ((np.diff(time)[:-1] > 0.0) & (np.diff(time)[1:] > 0.0))[:, None]
    local, rise = _rises_over_every_row(time, values, crest)
    crests = v1 + rise
    top = np.maximum(np.max(np.where(local, crests, -np.inf), axis=0), row_max)
    columns, rows = np.nonzero(crest.T)
    found = np.column_stack((time[1:-1][rows], crests[rows, columns], np.zeros(len(rows))))
    return row_max, top, peak_error._with_ends(found, columns, ends, top)


def _bits(a: np.ndarray) -> np.ndarray:
    """The values' bits, a zero's sign aside (numpy's max takes -0.0 or 0.0 by its loop)."""
    return (np.asarray(a, dtype=float) + 0.0).view(np.int64)


@pytest.mark.parametrize("quartic", [True, False])
def test_crests_compiled_are_those_numpy_took_over_every_row(monkeypatch, quartic) -> None:
    """`_highest` finds and reads the crests compiled, at the crest rows alone: the same
    largest rows, tops and candidates, bit for bit (a zero's sign aside), as numpy over
    every row, on 1000 random tables (noisy sines, zig-zags, plateaus, rows that are not
    finite, an event's repeated time, 3 to 60 rows); without the quartic too (its rises
    nan: the parabola's, which the bounds cap more often, the wide one included)."""
    import loadcases.run.peak_error as module

    if not quartic:
        monkeypatch.setattr(
            module, "_quartic_rise", lambda t, v, rows, c: np.full(len(rows), np.nan)
        )
    rng = np.random.default_rng(17)
    none = np.zeros(0)
    for _ in range(1000):
        n, columns = int(rng.integers(3, 60)), int(rng.integers(1, 6))
        time = np.cumsum(rng.uniform(0.5, 1.5, n)) if rng.random() < 0.5 else np.arange(n) * 1e-3
        if n > 4 and rng.random() < 0.3:
            time[n // 2] = time[n // 2 - 1]
        values = np.sin(time[:, None] * rng.uniform(0.5, 9.0, columns))
        values += [0.0, 1e-3, 0.3][int(rng.integers(0, 3))] * rng.standard_normal((n, columns))
        values[rng.integers(0, n), 0] = [np.nan, np.inf, 0.5][int(rng.integers(0, 3))]
        if rng.random() < 0.2:
            values[:, -1] = np.round(values[:, -1], 1)
        if rng.random() < 0.3:  # a zig-zag on a slope: the rows two apart curve less
            values[:, 0] = rng.uniform(-1.0, 1.0) * time + 0.01 * (-1.0) ** np.arange(n)
        row_max, top, candidates = module._highest(time, values, none)
        expected = _highest_over_every_row(time, values, none)
        assert np.array_equal(_bits(row_max), _bits(expected[0]))
        assert np.array_equal(_bits(top), _bits(expected[1]))
        for found, reference in zip(candidates, expected[2], strict=True):
            assert np.array_equal(_bits(found), _bits(reference))


def test_end_candidates_gathered_at_once_are_those_column_by_column() -> None:
    """`_ends` gathers every column's end rows and rows after events at once: the same
    candidates, bit for bit and in the same order, as built column by column, on 500
    random tables with events between rows and rows that are not finite."""
    from loadcases.run import peak_error

    rng = np.random.default_rng(23)
    seen_after = 0
    for _ in range(500):
        n, columns = int(rng.integers(1, 40)), int(rng.integers(1, 5))
        time = np.arange(n) * 1e-3
        events = np.array([], dtype=float)
        if n > 8 and rng.random() < 0.6:  # an event's row, then the rows after its actions
            at = int(rng.integers(2, n - 5))
            time = np.insert(time, at + 1, time[at] + 1e-4)
            events = np.array([time[at + 1]])
        values = np.sin(time[:, None] * rng.uniform(50.0, 900.0, columns))
        if len(events):
            values[int(np.flatnonzero(time == events[0])[0]) + 1 :] += 1.0  # a jump
        values[rng.integers(0, len(time)), 0] = [np.nan, 0.5][int(rng.integers(0, 2))]
        rises = {e: peak_error._end_rises(time, values, e) for e in (0, -1)}
        after = peak_error._after_events(time, values, events)
        seen_after += sum(np.isfinite(start).sum() for _, start in after)
        expected = [
            np.concatenate(
                (
                    np.array(
                        [
                            [time[e], values[e, j] + rises[e][j], peak_error.END]
                            for e in (0, -1)
                            if np.isfinite(values[e, j])
                        ]
                    ).reshape(-1, 3),
                    *(
                        np.array([[t, start[j], peak_error.END]])
                        for t, start in after
                        if np.isfinite(start[j])
                    ),
                )
            )
            for j in range(columns)
        ]
        got = peak_error._ends(time, values, events)
        for a, b in zip(got, expected, strict=True):
            assert a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))
    assert seen_after > 50  # rows after events were among the candidates


def _sharp_crest(time: np.ndarray, error: float) -> np.ndarray:
    """A crest of 100 about 10 ms wide at 0.2513 s (between rows), scaled by 1 + `error`:
    an integrator's error proportional to the motion."""
    return (1.0 + error) * 100.0 * np.exp(-(((time - 0.2513) / 0.01) ** 2))


def test_a_sharp_crest_is_compared_on_the_rows_the_companion_kept_about_it() -> None:
    """A run's rows every 2 ms with an error of 1e-3 of the motion, a companion of four times
    that error (Richardson, p = 2) thinned to rows every 16 ms: through its own rows the
    companion's crest reads 80.5 for 100.4 (the parabola's miss, 19.9, not the
    integrator's), and the estimate is 18 times the true error of the run's envelope (its
    row 99.611 against the crest's 100: 0.389). With the run's rows about the crest kept
    (loadcases.run.companion.crest_rows: the crest's row and three either side) the two
    vertices are read alike: 0.587, 1.51 times the true error."""
    run_t = np.round(np.arange(0.0, 0.5 + 1e-12, 0.002), 12)
    sparse = np.round(np.arange(0.0, 0.5 + 1e-12, 0.016), 12)
    crest = int(np.argmax(_sharp_crest(run_t, 0.0)))
    kept = np.union1d(sparse, run_t[crest - 3 : crest + 4])
    run = extremes(run_t, _sharp_crest(run_t, 1e-3))
    true = abs(run.row_max - 100.0)
    assert true == pytest.approx(0.38929, abs=1e-5)
    estimates = {}
    for name, rows in (("thinned", sparse), ("kept", kept)):
        companion = extremes_of(rows, _sharp_crest(rows, 4e-3)[:, None], interval=0.016)[0]
        estimates[name] = peak_error(run, companion, 1.0 / 3.0)[0] / true
    assert estimates["thinned"] == pytest.approx(18.03, abs=0.01)
    assert estimates["kept"] == pytest.approx(1.508, abs=0.001)
    # a second, broader crest at 0.4 s, 99 high in the run and 101 in the companion: the
    # companion's highest, but not the crest of the run's peak, which is compared with its
    # partner on the kept rows (loadcases.run.peak_error.dense_beside), not with it
    second = 99.0 * np.exp(-(((run_t - 0.4) / 0.05) ** 2))
    run = extremes(run_t, _sharp_crest(run_t, 1e-3) + second)
    other = 101.0 * np.exp(-(((kept - 0.4) / 0.05) ** 2))
    companion = extremes_of(kept, (_sharp_crest(kept, 4e-3) + other)[:, None], interval=0.016)
    assert companion[0].max > 100.9
    assert peak_error(run, companion[0], 1.0 / 3.0)[0] / true == pytest.approx(1.508, abs=0.01)
