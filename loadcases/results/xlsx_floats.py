"""Exact floats in .xlsx files: openpyxl writes numbers with `%.16g`, which loses the last
digit of doubles that need 17; Excel and openpyxl read 17 digits back exactly. Inside
`exact_floats()` openpyxl's cell writer uses the shortest round-trip text (`repr`), so a
workbook holds exactly the numbers of the CSV results."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from typing import Any

__all__ = ["exact_floats"]


@contextlib.contextmanager
def exact_floats() -> Iterator[None]:
    """Within the block, openpyxl saves finite floats as `repr(float(x))`."""
    from openpyxl.cell import _writer

    original = _writer.safe_string

    def exact(value: Any) -> str:
        if isinstance(value, float) and math.isfinite(value):
            return repr(float(value))
        return original(value)

    _writer.safe_string = exact
    try:
        yield
    finally:
        _writer.safe_string = original
