"""Text cells stay text in .xlsx files. openpyxl turns a string that starts with `=` into a
formula and `#N/A`-like strings into error values; `loads` writes no formulas, and text
from input files (run, case, request and parameter names, messages, paths) must never run
in a spreadsheet. Inside `text_cells()` every such string is saved as a text cell."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import Any

__all__ = ["text_cells"]


@contextlib.contextmanager
def text_cells() -> Iterator[None]:
    """Within the block, openpyxl saves string cells typed formula or error as text."""
    from openpyxl.cell import _writer

    original = _writer._set_attributes

    def as_text(cell: Any, styled: Any = None) -> Any:
        if cell.data_type in ("f", "e") and isinstance(cell._value, str):
            cell.data_type = "s"
        return original(cell, styled)

    _writer._set_attributes = as_text
    try:
        yield
    finally:
        _writer._set_attributes = original
