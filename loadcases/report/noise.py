"""Numerical noise in an envelope: components whose peak is round-off, not a load.

A column is `~0` when its largest magnitude max(|max|, |min|) over all runs is at most
`fraction` (the set's `report.noise_floor`, default 1e-6) times
- the largest magnitude of the other components of the same request in the same unit (the
  out-of-plane fy = 7e-4 N of a joint carrying fx = 3e5 N in a planar mechanism), or
- the largest magnitude of any column of the same (known) unit in the envelope: the
  round-off moments of a planar mechanism's pin joints (4e-4 N*m) beside a 5e4 N*m torque,
  where every component of the request is noise.
Such a row gets no factor and no margin; the loads matrix shows it as `~0`. A set whose
columns are all round-off of one unit (no real load of that unit anywhere) is not detected.
"""

from __future__ import annotations

from collections.abc import Iterable

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.report.envelope import EnvelopeRow
from loadcases.report.roundoff import NOISE_FLOOR, roundoff_columns

__all__ = ["NOISE_MARK", "noise_columns"]

NOISE_MARK = "~0"


def _magnitudes(rows: Iterable[EnvelopeRow]) -> dict[str, tuple[str, str, float]]:
    """{column: (request, unit, largest magnitude)} of the rows with values."""
    out = {}
    for row in rows:
        if row.abs_max is not None and row.column != ABSCISSA_COLUMN:
            out[row.column] = (row.column.rsplit(".", 1)[0], row.unit or "", row.abs_max)
    return out


def noise_columns(rows: Iterable[EnvelopeRow], fraction: float = NOISE_FLOOR) -> set[str]:
    """The columns of `rows` (SI envelope rows) that are numerical noise (module notes)."""
    return roundoff_columns(_magnitudes(rows), fraction)
