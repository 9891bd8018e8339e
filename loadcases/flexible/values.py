"""Numbers as FE programs write them, and the error of a matrix file that cannot be read."""

from __future__ import annotations

import math
import re
from pathlib import Path

from loadcases.foundation.number_text import SIGNED_DECIMAL

__all__ = ["FileFormatError", "nastran_real"]

# NASTRAN's real numbers: 1.5E+3, 1.5D+3, and the short form 1.5+3 (exponent without E)
_SHORT_EXPONENT = re.compile(rf"^({SIGNED_DECIMAL})([+-][0-9]+)$")


class FileFormatError(ValueError):
    """A matrix or bulk-data file that does not follow its format; `line` (1-based, 0 when
    unknown) is where, `file` which file when the reader read several."""

    def __init__(self, message: str, line: int = 0, file: Path | None = None) -> None:
        super().__init__(message)
        self.message, self.line, self.file = message, line, file


def nastran_real(text: str, line: int = 0) -> float:
    """The finite float of a NASTRAN or Fortran real (`1.0D+05`, `1.0+5`, `.5`, `7.`)."""
    cell = text.strip().upper().replace("D", "E")
    short = _SHORT_EXPONENT.match(cell)
    if short is not None:
        cell = f"{short.group(1)}E{short.group(2)}"
    try:
        value = float(cell)
    except ValueError:
        raise FileFormatError(f"expected a real number, got '{text.strip()[:40]}'", line) from None
    if not math.isfinite(value):
        raise FileFormatError(f"expected a finite number, got '{text.strip()[:40]}'", line)
    return value
