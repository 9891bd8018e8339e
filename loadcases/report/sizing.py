"""From ok runs to what a sizing report shows: the envelope with factors and margins,
numerical noise marked, envelope curves named by their abscissa, the loads matrix.

Runs whose case gives ultimate-level loads are first brought to limit level
(`loadcases.report.levels`): envelope, curves and matrix are limit loads, and the ultimate
loads factor x limit (an ultimate-level run's computed loads).

Columns marked `~0` get no envelope curve (their numbers stay in the runs' CSV files).
One function for `loads run SET` (`loadcases.sets.campaign`) and `loads envelope`
(`loadcases.report.saved_report`); everything in SI.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.report.curves import EnvelopeCurve, envelope_curves
from loadcases.report.envelope import EnvelopeRow, extract_envelope
from loadcases.report.levels import at_limit_level
from loadcases.report.loads_matrix import LoadsMatrix, loads_matrix
from loadcases.report.margins import ULTIMATE, apply_margins, case_factor, column_factor
from loadcases.report.noise import noise_columns
from loadcases.report.peaks import RunPeak, run_peaks
from loadcases.report.roundoff import NOISE_FLOOR
from loadcases.results.saved import SavedRun

__all__ = ["Sizing", "size_runs"]


@dataclass
class Sizing:
    """The envelope rows, curves and loads matrix of a set of runs (SI); `ultimate`: the
    ultimate factor; `noise`: the columns marked `~0`."""

    rows: list[EnvelopeRow]
    curves: list[EnvelopeCurve]
    matrix: LoadsMatrix
    ultimate: float = 1.0
    noise: frozenset[str] = field(default_factory=frozenset)


def size_runs(
    runs: Sequence[SavedRun],
    model: Any | None = None,
    abscissae: Mapping[str, str] | None = None,
) -> Sizing:
    """Size `runs` (status ok) with the factors, allowables and report settings of a
    `SetModel` (none: no factors); `abscissae` {family: abscissa expression}."""
    factors = model.factors if model is not None else {}
    report = model.report if model is not None else None
    allowables = model.allowables if model is not None else {}
    case_factors = model.case_factors if model is not None else {}
    levels = {run.name: run.level for run in runs}
    runs = at_limit_level(runs, factors, frozenset(allowables))
    peaks = run_peaks(runs)
    rows = extract_envelope(runs)
    noise = frozenset(noise_columns(rows, report.noise_floor if report else NOISE_FLOOR))
    rows = apply_margins(
        rows, factors, allowables, case_factors=case_factors, peaks=peaks, noise=noise
    )
    rows = [
        replace(row, max_level=levels.get(str(row.max_run)), min_level=levels.get(str(row.min_run)))
        for row in rows
    ]
    names = dict(abscissae or {})
    at = {
        run.family: (names.get(run.family, ABSCISSA_COLUMN), run.units.get(ABSCISSA_COLUMN, ""))
        for run in runs
        if ABSCISSA_COLUMN in run.channels
    }
    units = {c: u for run in runs for c, u in run.units.items()}
    matrix = loads_matrix(
        peaks,
        [(run.name, run.family) for run in runs],
        units=units,
        at=at,
        noise=noise,
        by=report.matrix if report else "runs",
        levels=levels,
        factor=_CellFactor(units, factors, allowables, case_factors),
    )
    curves = envelope_curves(runs, names, skip=noise, asked=report.charts if report else ())
    return Sizing(rows, curves, matrix, float(factors.get(ULTIMATE, 1.0)), noise)


class _CellFactor:
    """Ultimate x fitting x case factor of one run's peak of a column (None: not a load),
    each column's and each run's part found once (a matrix of 1000 runs asks 10^5 times)."""

    def __init__(
        self,
        units: Mapping[str, str],
        factors: Mapping[str, float],
        allowables: Mapping[str, Any],
        case_factors: Mapping[str, float],
    ) -> None:
        self.units, self.factors = units, factors
        self.allowables, self.case_factors = allowables, case_factors
        self.columns: dict[str, float | None] = {}
        self.runs: dict[str, float] = {}

    def __call__(self, column: str, peak: RunPeak) -> float | None:
        if column not in self.columns:
            unit, named = self.units.get(column), column in self.allowables
            self.columns[column] = column_factor(column, unit, self.factors, named)
        factor = self.columns[column]
        if factor is None:
            return None
        if peak.run not in self.runs:
            self.runs[peak.run] = case_factor(peak.run, peak.family, self.case_factors)
        return factor * self.runs[peak.run]
