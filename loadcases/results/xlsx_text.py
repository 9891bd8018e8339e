"""Text cells stay text in .xlsx files. openpyxl turns a string that starts with `=` into a
formula and `#N/A`-like strings into error values; `loads` writes no formulas, and text
from input files (run, case, request and parameter names, messages, paths) must never run
in a spreadsheet. Inside `text_cells()` every such string is saved as a text cell, and its
hidden characters (a control character such as BEL, which makes openpyxl refuse the whole
workbook, or a bidirectional control such as U+202E, which would reorder the cell as
shown) are written as escapes (`\\x07`, `\\u202e`: `loadcases.foundation.clip.visible`)."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import Any

from loadcases.foundation.clip import visible

__all__ = ["text_cells"]


@contextlib.contextmanager
def text_cells() -> Iterator[None]:
    """Within the block, openpyxl saves string cells typed formula or error as text, and
    takes every string with its hidden characters escaped."""
    from openpyxl.cell import _writer
    from openpyxl.cell.cell import Cell

    original = _writer._set_attributes
    original_check = Cell.check_string

    def as_text(cell: Any, styled: Any = None) -> Any:
        if cell.data_type in ("f", "e") and isinstance(cell._value, str):
            cell.data_type = "s"
        return original(cell, styled)

    def escaped(cell: Any, value: Any) -> Any:
        return original_check(cell, visible(value) if isinstance(value, str) else value)

    _writer._set_attributes = as_text
    Cell.check_string = escaped
    try:
        yield
    finally:
        _writer._set_attributes = original
        Cell.check_string = original_check
