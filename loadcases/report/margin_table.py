"""The margin table of a set: one line per margin of the envelope (column, side, limit or
ultimate), lowest margin first, as a stress office reads it: the limit load and its run, the
factor, the factored load, the allowable and MS = allowable / (factor x load) - 1.

Lines come from the envelope rows (`loadcases.report.margins.apply_margins`), in whatever
units the rows are (SI for `margins.csv`, report units in the workbook); the load is
factored load / factor. A side that never loads towards its allowable (MS left empty) and
rows marked `~0` have no line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path

from loadcases.foundation.atomic import atomic_write_text
from loadcases.report.csv_rows import rows_csv_text
from loadcases.report.envelope import EnvelopeRow

__all__ = [
    "MARGIN_COLUMNS",
    "MarginLine",
    "allowable_lines",
    "margin_csv_text",
    "margin_lines",
    "write_margin_csv",
]


@dataclass(frozen=True)
class MarginLine:
    """One margin: `kind` limit or ultimate, `side` max or min; values in the rows' units."""

    column: str
    unit: str | None
    side: str
    kind: str
    load: float | None
    run: str | None
    factor: float
    factored_load: float | None
    allowable: float
    ms: float | None


MARGIN_COLUMNS = tuple(f.name for f in fields(MarginLine))


def _lines_of(row: EnvelopeRow, ultimate: float) -> list[MarginLine]:
    lines = []
    for side in ("max", "min"):
        factor = row.factor if side == "max" else row.factor_min
        factored = getattr(row, f"ultimate_{side}")
        if factor is None or row.noise:
            continue
        load = None if factored is None else factored / factor
        run = getattr(row, f"ultimate_{side}_run") or getattr(row, f"{side}_run")
        for kind, allowable, ms, used in (
            ("ultimate", getattr(row, f"allowable_{side}"), getattr(row, f"ms_{side}"), factor),
            (
                "limit",
                getattr(row, f"limit_allowable_{side}"),
                getattr(row, f"ms_limit_{side}"),
                factor / ultimate if ultimate else factor,
            ),
        ):
            if allowable is not None and ms is not None:
                scaled = None if load is None else used * load
                lines.append(
                    MarginLine(
                        row.column, row.unit, side, kind, load, run, used, scaled, allowable, ms
                    )
                )
    return lines


def margin_lines(rows: list[EnvelopeRow], ultimate: float = 1.0) -> list[MarginLine]:
    """Every margin of `rows`, lowest first (ties in row order); `ultimate`: the set's
    ultimate factor (the limit factor is the row's factor / ultimate)."""
    lines = [line for row in rows for line in _lines_of(row, ultimate)]
    return sorted(lines, key=lambda line: line.ms if line.ms is not None else math.inf)


def margin_csv_text(lines: list[MarginLine]) -> str:
    """The margin table as CSV text (full precision, missing values empty)."""
    return rows_csv_text(MARGIN_COLUMNS, lines)


def write_margin_csv(lines: list[MarginLine], path: Path) -> Path:
    """Write `margins.csv` atomically."""
    return atomic_write_text(path, margin_csv_text(lines))


def _side_text(kind: str, high: float | None, low: float | None, unit: str | None) -> str | None:
    """`ultimate: max 40 kN, min -25 kN` (a side not given: `none`), or None when neither."""
    if high is None and low is None:
        return None
    show = lambda v: "none" if v is None else f"{v:.6g} {unit or '-'}"  # noqa: E731
    return f"{kind}: max {show(high)}, min {show(low)}"


def allowable_lines(rows: list[EnvelopeRow]) -> list[tuple[str, str]]:
    """(`allowable COLUMN`, `ultimate: max .., min ..; limit: max .., min ..`) of every row
    given an allowable, in the rows' units (the Provenance sheet states what was given)."""
    lines = []
    for row in rows:
        parts = [
            _side_text("ultimate", row.allowable_max, row.allowable_min, row.unit),
            _side_text("limit", row.limit_allowable_max, row.limit_allowable_min, row.unit),
        ]
        given = [p for p in parts if p is not None]
        if given:
            lines.append((f"allowable {row.column}", "; ".join(given)))
    return lines
