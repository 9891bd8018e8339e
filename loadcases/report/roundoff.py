"""Where a peak stops being a load: the round-off threshold shared by the envelope's noise
marks (`noise`), `loads compare` (`compare`) and a set's comparisons (`comparison`).
Imports nothing: the report modules that read it stay a DAG."""

from __future__ import annotations

__all__ = ["NOISE_FLOOR"]

NOISE_FLOOR = 1e-6  # of the request's largest magnitude: below it a peak is round-off
