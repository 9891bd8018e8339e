"""Engineering number formats of the workbook: a fixed number of significant digits of a
magnitude in the unit shown (128.6 kN reads `128.6`, not `1.286E+02`).

The cell keeps its full float (the CSV's exactly); only the display is rounded. A row or a
column shares one format, chosen from its largest magnitude, so that its decimals line up:
`digits` significant digits of that magnitude in fixed point from `FIXED_LOW` up to
`FIXED_HIGH`, scientific (`0.000E+00`) outside, `0` for a row of zeros.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = ["FIXED_HIGH", "FIXED_LOW", "SIGNIFICANT_DIGITS", "number_format"]

SIGNIFICANT_DIGITS = 4
FIXED_LOW = 1.0e-3  # smaller magnitudes read better as 1.234E-04 than 0.0001234
FIXED_HIGH = 1.0e7  # larger ones too: 12345678 has more digits than are significant


def number_format(values: Iterable[float | None], digits: int = SIGNIFICANT_DIGITS) -> str:
    """The Excel number format showing the largest finite magnitude of `values` with
    `digits` significant digits (`0.0` for 128.6 at 4 digits; `General` when none is
    finite)."""
    finite = [abs(v) for v in values if v is not None and math.isfinite(v)]
    if not finite:
        return "General"
    peak = max(finite)
    if peak == 0.0:
        return "0"
    exponent = math.floor(math.log10(float(f"{peak:.{digits - 1}e}")))  # after rounding
    if not FIXED_LOW <= peak < FIXED_HIGH:
        return "0." + "0" * (digits - 1) + "E+00" if digits > 1 else "0E+00"
    decimals = max(0, digits - 1 - exponent)
    return "0." + "0" * decimals if decimals else "0"
