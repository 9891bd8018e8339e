"""The global error estimate against the true error, per case and request (issue 35 item 2;
benchmarks/error_table.py, whose cheap cases run here): the run's own estimate of each
request's history error (the largest difference over the run, of the request's peak) and
of its envelope peaks within a factor 3 of the true error (never below a third of it), the
true error measured against the same case at tolerance 1e-9 with `output: steps` at a tenth
of the output interval (its envelope refined between rows: the continuous one).

Measured 2026-11-29 with the companion's rows thinned to about one per step
(loadcases/run/companion.py; benchmarks/results/error-table.json; docs/performance.md):
histories 0.89-1.04 on the pendulum over 2 s, 0.95 on the closed-valve servo, 2.5-3.0 on
IFToMM A01 over 10 s, 0.62-0.75 on Andrews' squeezer. Envelope peaks (Richardson on the
continuous peaks plus the rows' miss of them, loadcases/run/peak_error.py): 0.56-1.3 on the
pendulum, 0.66-2.3 on the servo (2.1-4.4 since the step grows whenever the error law
allows: `HIGH_PEAK`), 0.49-0.92 on A01 (before: 0.26-0.34). Not asserted: peaks
whose true error is below 1e-5 of the peak (ten times the reference's own error: A01's bob
position, 1.5e-8), and Andrews' peaks (0.30-59: where the envelope's extreme moves between
an end row and an interior crest of almost the same height, the pair's difference does not
see it; 59 on a true error of 2.6e-6).
"""

from __future__ import annotations

import pytest

from benchmarks.error_table import CHEAP, case_rows

LOW, HIGH = 1.0 / 3.0, 3.0
MEASURABLE = 1e-5  # of the peak: true errors below it are the reference's own
SINGULAR = ("A02 N=3 3-D",)  # passes a singular position: estimated from a finer run
# overestimates let through, with their measured ratio: the servo's stroke peak, 4.4 (3.97
# measured again) for a true 3.6e-5 of the peak since the step grows whenever the error law
# allows (issue 35 item 3; 2.3 at most before, for a larger true error), and its actuator's
# pressures and force, 3.32 (0.66 before, by one lucky companion crest): the closed valve's
# crests are all equal, so the envelope's error is that of the run's best crest, and the
# per-crest errors scatter 5x from crest to crest (docs/performance.md): tightening at
# worst, never a miss
HIGH_PEAK = {("servo closed valve", "stroke"): 5.0, ("servo closed valve", "actuator"): 3.5}


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
            assert LOW <= row[key] <= HIGH, (name, row["request"], key, row[key])
        assert (row["observed_order"] is not None) == (name in SINGULAR), (name, row)
