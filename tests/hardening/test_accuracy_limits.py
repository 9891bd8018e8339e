"""Sizes and tolerances out of range (issue 39 item 6, "Size"): `loads accuracy` with a
tolerance of 1e-300, `--repeats` 0 or negative, or `-o` an existing file, and a case whose
`analysis.tolerance` is 1e-300, are input errors (exit 2) before anything is solved, where
they were internal errors (Radau's matrix made infinite by an absolute tolerance of 1e-300)
or ran silently (no repeat: no CPU time measured). A tolerance within the limits passes.
"""

from __future__ import annotations

import pytest

from tests.hardening.conftest import loads

DYNAMIC = (
    'motions:\n  drive: {joint: pivot, value: "speed * t"}\nanalysis: {type: kinematic, end: 0.5',
    "analysis: {type: dynamic, end: 0.1",
)
NO_DRIVE = ("  drive_torque: {motion: drive, quantity: torque}\n", "")


@pytest.mark.parametrize(
    ("option", "words"),
    [
        (("--repeats", "0"), "--repeats: 0 must be a whole number from 1 to 100"),
        (("--repeats", "-1"), "--repeats: -1 must be a whole number from 1 to 100"),
        (("--repeats", "101"), "--repeats: 101 must be a whole number from 1 to 100"),
        (("--tolerances", "1e-4,1e-300"), "each tolerance must lie between 1e-14 and 1"),
        (("--reference-tolerance", "1e-300"), "--reference-tolerance must be at least 1e-14"),
        (("-o", "FILE"), "is a file, not a folder"),
    ],
)
def test_accuracy_options_out_of_range_are_input_errors(crank, tmp_path, option, words) -> None:
    case = crank(case=DYNAMIC)
    existing = tmp_path / "taken.txt"
    existing.write_text("a file\n")
    args = [str(existing) if a == "FILE" else a for a in option]
    out = [] if "-o" in option else ["-o", str(tmp_path / "out")]
    result = loads("accuracy", case, *out, *args)
    assert result.exit_code == 2, result.output
    assert words in result.output and "internal error" not in result.output
    assert not (tmp_path / "out").exists()  # nothing solved, nothing written


@pytest.mark.parametrize(("tolerance", "ok"), [("1e-300", False), ("1e-14", True)])
def test_a_case_tolerance_below_round_off_is_an_input_error(
    crank, tolerance: str, ok: bool
) -> None:
    case = crank(case=(DYNAMIC[0], f"analysis: {{type: dynamic, tolerance: {tolerance}, end: 0.1"))
    text = case.read_text(encoding="utf-8").replace(*NO_DRIVE)
    case.write_text(text, encoding="utf-8")
    result = loads("validate", case)
    if ok:
        assert result.exit_code == 0, result.output
        return
    assert result.exit_code == 2, result.output
    assert "error: analysis.tolerance: must be at least 1e-14 (got 1e-300)" in result.output
