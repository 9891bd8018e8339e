"""Where a column stops being a load: its largest magnitude at most NOISE_FLOOR times its
request's peak is round-off (a planar mechanism's out-of-plane reactions, 1e-50 N beside a
58 N force). One threshold for the envelope's `~0` marks and comparisons
(loadcases.report.roundoff, a set's `report.noise_floor` default) and for the accuracy
estimate, which leaves such columns out (loadcases.run.companion.significant)."""

from __future__ import annotations

__all__ = ["NOISE_FLOOR"]

NOISE_FLOOR = 1e-6  # of the request's largest magnitude: below it a peak is round-off
