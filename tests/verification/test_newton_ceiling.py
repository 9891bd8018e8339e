"""IFToMM A02 with N = 40, planar (benchmarks/hard), the error estimate's companion (the
run at the coarser setting, loadcases.run.companion.coarser: tolerance 8e-6) over its first
6 s, which pass the chain's horizontal crossings at about 0.8, 3.5 and 5.5 s: near them
Newton fails above a step size the error law knows nothing of, and the law grew the
accepted retry (a quarter as long, its error far below the tolerance) x4 straight back to
the size Newton had failed at (rules.step_size; issue 35).

Measured 2026-11-29 (Python stepper: a planar system has no compiled runs, so the counts
are exact and repeatable): before the ceiling after a Newton failure 313 steps, 128
rejected (31 Newton failures, 97 by the error test), 2205 Newton iterations; with it 281,
85 (none by Newton), 1760. Over 20 s: 1499 steps, 736 rejected (224 Newton failures), 11 323
iterations -> 1023, 439 (56), 7118 (docs/performance.md). Guards at the measured counts
+ about 10 %.
"""

from __future__ import annotations

from pathlib import Path

import pytest

CASE = Path(__file__).resolve().parents[2] / "benchmarks" / "hard"


def test_companion_does_not_regrow_to_the_size_newton_failed_at() -> None:
    from benchmarks.error_table import _with
    from loadcases.build.model import build_run
    from loadcases.inputs.loader import load_case
    from loadcases.run.companion import coarser

    case = load_case(CASE / "a02_n_four_bar_planar.case.yaml")
    built = build_run(_with(case, tolerance=None, end=6.0))
    companion = coarser(built.analysis)
    assert companion.tolerance == pytest.approx(8e-6)
    solution = built.solve(companion, checks=False)
    assert solution.status == "ok", solution.message
    stats = solution.stats
    assert stats.rejected_steps <= 95, stats  # 85 measured (128 before)
    assert stats.newton_iterations <= 1950, stats  # 1760 measured (2205 before)
    assert stats.steps <= 310, stats  # 281 measured (313 before)
