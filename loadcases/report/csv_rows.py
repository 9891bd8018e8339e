"""One CSV text from a table of dataclass rows: the rule every table file of a set uses
(`envelope.csv`, `margins.csv`, the comparison, `reference-curves.csv`)."""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Sequence
from dataclasses import astuple
from typing import Any

from loadcases.foundation.clip import visible_fields

__all__ = ["rows_csv_text"]


def rows_csv_text(columns: Sequence[str], rows: Iterable[Any]) -> str:
    """CSV text of `columns` then one line per dataclass in `rows`: numbers at full
    precision, a missing value (None) empty, text made visible (no control characters)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    writer.writerows(
        visible_fields("" if value is None else value for value in astuple(row)) for row in rows
    )
    return buffer.getvalue()
