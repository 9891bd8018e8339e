"""From ok runs to what a sizing report shows: the envelope with factors and margins,
numerical noise marked, envelope curves named by their abscissa, the loads matrix.

Columns marked `~0` get no envelope curve (their numbers stay in the runs' CSV files).
One function for `loads run SET` (`loadcases.sets.campaign`) and `loads envelope`
(`loadcases.report.saved_report`); everything in SI.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.report.curves import EnvelopeCurve, envelope_curves
from loadcases.report.envelope import EnvelopeRow, extract_envelope
from loadcases.report.loads_matrix import LoadsMatrix, loads_matrix
from loadcases.report.margins import ULTIMATE, apply_margins
from loadcases.report.noise import noise_columns
from loadcases.report.peaks import run_peaks
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
    peaks = run_peaks(runs)
    rows = extract_envelope(runs)
    noise = frozenset(noise_columns(rows, report.noise_floor if report else NOISE_FLOOR))
    rows = apply_margins(
        rows,
        factors,
        model.allowables if model is not None else {},
        case_factors=model.case_factors if model is not None else None,
        peaks=peaks,
        noise=noise,
    )
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
    )
    curves = envelope_curves(runs, names, skip=noise, asked=report.charts if report else ())
    return Sizing(rows, curves, matrix, float(factors.get(ULTIMATE, 1.0)), noise)
