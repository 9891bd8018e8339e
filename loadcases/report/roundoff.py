"""Where a peak stops being a load: the round-off threshold and rule shared by the
envelope's noise marks (`noise`), `loads compare` (`compare`) and a set's comparisons
(`comparison`). Imports only its threshold (loadcases.foundation.noise_floor): the report
modules that read it stay a DAG.

A column is round-off when its largest magnitude is at most `fraction` (default
`NOISE_FLOOR`) times the largest magnitude of its request in the same unit, or of any
column of the same (known) unit: the round-off moments of a planar mechanism's pin joints
(4e-13 N*m) beside a 5e4 N*m torque, where every component of the request is noise.
"""

from __future__ import annotations

from collections.abc import Mapping

from loadcases.foundation.noise_floor import NOISE_FLOOR

__all__ = ["NOISE_FLOOR", "roundoff_columns"]


def roundoff_columns(
    magnitudes: Mapping[str, tuple[str, str, float]], fraction: float = NOISE_FLOOR
) -> set[str]:
    """The columns of `magnitudes` {column: (request, unit, largest magnitude)} that are
    round-off (module notes)."""
    per_request: dict[tuple[str, str], float] = {}
    per_unit: dict[str, float] = {}
    for request, unit, size in magnitudes.values():
        per_request[request, unit] = max(per_request.get((request, unit), 0.0), size)
        if unit:
            per_unit[unit] = max(per_unit.get(unit, 0.0), size)
    return {
        column
        for column, (request, unit, size) in magnitudes.items()
        if size <= fraction * max(per_request[request, unit], per_unit.get(unit, 0.0))
    }
