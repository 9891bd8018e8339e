"""The refresh-rule benchmark's channel comparison (benchmarks.refresh_rule.largest_change):
a change relative to the channel's range, round-off channels left out."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.refresh_rule import largest_change


def test_largest_change_is_relative_to_range_and_skips_round_off(tmp_path: Path) -> None:
    """Before: a force whose x swings 0..10 N and whose z is round-off (1e-15 of the
    force's peak 10), a position 0..0.2 m. After: x moved 0.01 N (1e-3 of its range), z
    moved by its whole range (left out), the position 1e-5 m (5e-5 of its range)."""
    time = np.linspace(0.0, 1.0, 5)
    force_x = np.array([0.0, 5.0, 10.0, 5.0, 0.0])
    force_z = np.array([0.0, 1e-14, -1e-14, 0.0, 0.0])
    position = np.array([0.0, 0.05, 0.1, 0.15, 0.2])
    saved = tmp_path / "case.npz"
    arrays: dict[str, Any] = {"time": time, "f.fx": force_x, "f.fz": force_z, "p.x": position}
    np.savez(saved, **arrays)
    after = {"f.fx": force_x + [0, 0, 0.01, 0, 0], "f.fz": -force_z, "p.x": position + 1e-5}
    worst, where = largest_change(after, time, saved)
    assert where == "f.fx"
    assert abs(worst - 1e-3) < 1e-12
    worst, where = largest_change({"p.x": position + 1e-5}, time, saved)
    assert where == "p.x" and abs(worst - 5e-5) < 1e-12
    assert np.isnan(largest_change(after, time[:4], saved)[0])  # other rows: not compared
