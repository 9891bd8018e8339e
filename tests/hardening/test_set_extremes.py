"""`--set` values that drive the crank far beyond its design (issue 39, long fuzzing of
`--set`): a run finishes with bounded work or fails naming why (exit 1), with nothing from
NumPy or LAPACK on the way.

Closed form (crank: m = 1 kg, centre of mass r = 0.05 m from the pivot, turned at a
constant omega): the pivot pushes the crank to the centre with m omega^2 r."""

from __future__ import annotations

import json
import math
from pathlib import Path

from loadcases.results.files import read_results
from tests.hardening.conftest import loads


def _summary(folder: Path) -> dict:
    (path,) = folder.glob("*.summary.json")
    return json.loads(path.read_text(encoding="utf-8"))


def test_force_text_given_to_speed_turns_25000_rad_s_with_bounded_work(
    crank, tmp_path: Path
) -> None:
    """`--set 'speed=-025 kN'` (a force text for a parameter without a unit: a warning,
    then -25 000 rad/s, 199 turns per output step): was `ok` after 10 220 halved steps and
    13 s CPU; now no halved step and 2 Newton iterations per output time (measured), the
    pivot force m omega^2 r = 3.125e7 N to 1e-10 (measured 3e-13: the angle's round-off)."""
    case = crank()
    result = loads("run", case, "--set", "speed=-025 kN", "-o", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert "expected an angle" in result.output  # the dimension warning stays
    summary = _summary(tmp_path / "out")
    assert summary["status"] == "ok"
    assert summary["stats"]["rejected_steps"] == 0
    assert summary["stats"]["newton_iterations"] <= 3 * summary["stats"]["steps"]
    (table,) = (tmp_path / "out").glob("*.csv")
    time, channels = read_results(table)
    omega, m_r = -25000.0, 1.0 * 0.05
    for t, fx, fy in zip(time, channels["pivot_force.fx"], channels["pivot_force.fy"]):
        angle = omega * t
        expected = (-(omega**2) * m_r * math.cos(angle), -(omega**2) * m_r * math.sin(angle))
        assert abs(fx - expected[0]) < 1e-10 * omega**2 * m_r
        # the pivot also carries the weight (9.81 N) and the push (load: 10 N)
        assert abs(fy - 19.81 - expected[1]) < 1e-10 * omega**2 * m_r


def test_speed_1e150_fails_by_name_without_numpy_or_lapack_noise(
    crank, tmp_path: Path, capfd
) -> None:
    """`--set speed=1e150`: the first step asks the drive for an angle beyond 4.5e8 rad (a
    double no longer holds it to the position tolerance): exit 1 saying so, the row at
    t = 0 kept with finite numbers (its pivot force 5e298 N: the magnitude column is a
    hypot, not the root of overflowing squares); no NumPy warning, no LAPACK 'DLASCL'."""
    case = crank()
    result = loads("run", case, "--set", "speed=1e150", "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    summary = _summary(tmp_path / "out")
    assert summary["status"] == "failed"
    assert "drive: angle of pivot is set to " in summary["message"]
    assert "beyond +-4.5e+08 rad" in summary["message"]
    (table,) = (tmp_path / "out").glob("*.csv")
    time, channels = read_results(table)
    assert time.tolist() == [0.0]
    assert math.isclose(channels["pivot_force.f"][0], 5e298, rel_tol=1e-12)
    printed = capfd.readouterr()
    for text in (result.output, printed.out, printed.err):
        assert "Warning" not in text and "DLASCL" not in text, text
