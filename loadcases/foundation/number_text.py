"""The text of a decimal number (`12`, `-1.5`, `.5`, `7.`, `2.5e-3`): one regular
expression for every reader of numbers in text (quantities, expressions, the unit table,
FE matrix files, saved results).

A digit run has one way to match: `[0-9]+\\.?[0-9]*` lets the regex engine try every split
of a run of digits between its two parts, quadratic in the run's length whenever what
follows does not match (a `--set` value of 40 000 digits and an `=` took 23 s; one of 2.7
million, hours). ASCII digits only, as the quantity parser reads them.
"""

from __future__ import annotations

__all__ = ["EXPONENT", "SIGNED_DECIMAL", "SIGNED_NUMBER", "UNSIGNED_NUMBER"]

UNSIGNED_DECIMAL = r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)"  # 12, 1.5, 7., .5
SIGNED_DECIMAL = rf"[-+]?{UNSIGNED_DECIMAL}"
EXPONENT = r"(?:[eE][-+]?[0-9]+)"
UNSIGNED_NUMBER = rf"{UNSIGNED_DECIMAL}{EXPONENT}?"
SIGNED_NUMBER = rf"[-+]?{UNSIGNED_NUMBER}"
