"""Saved results read as input (issue 39 item 6): `loads envelope` and `loads compare` check
every file they read and name the file, line and column of what is wrong (exit 2), never
a traceback or an internal error; a CSV changed since its summary was written is a warning
that stays silent on the files `loads` wrote.

The runs are written by `write_results` from hand-made outcomes (no solve): run `a` has
fx = [1, 2, 3] N and tz = [0.5, -0.5, 0.25] N*m at t = 0, 0.1, 0.2 s; run `b` twice those.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from loadcases.results.files import write_results
from loadcases.results.outcome import RunOutcome
from mechlib.core.outcome import Solution
from tests.hardening.conftest import loads

FX = np.array([1.0, 2.0, 3.0])
TZ = np.array([0.5, -0.5, 0.25])


def _outcome(name: str, scale: float, status: str = "ok") -> RunOutcome:
    solution = Solution(
        status=status,
        message="finished" if status == "ok" else "Newton failed at t = 0.2 s",
        analysis="kinematic",
        time=np.array([0.0, 0.1, 0.2]),
        channels={"pin.fx": scale * FX, "pin.tz": scale * TZ},
    )
    return RunOutcome(
        name,
        Path("door.case.yaml"),
        "kinematic",
        solution,
        "ab" * 32,
        {"pin.fx": "N", "pin.tz": "N*m"},
    )


@pytest.fixture
def saved(tmp_path: Path) -> Path:
    """A folder of two saved runs, `a` and `b`."""
    folder = tmp_path / "runs"
    write_results(_outcome("a", 1.0), folder, version="0")
    write_results(_outcome("b", 2.0), folder, version="0")
    return folder


def _refused(result, where: str, *words: str) -> str:
    """Exit 2, the place named, the words said, one short line per problem, no traceback."""
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and "internal error" not in result.output
    assert where in result.output, result.output
    for word in words:
        assert word in result.output, result.output
    assert len(result.output) < 2000  # a huge field is quoted clipped, never whole
    return result.output


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_untouched_results_give_their_envelope_without_a_word(saved: Path) -> None:
    result = loads("envelope", saved)
    assert result.exit_code == 0, result.output
    assert "warning" not in result.output
    row = next(line for line in result.output.splitlines() if line.startswith("pin.fx,"))
    assert row.startswith("pin.fx,6.0,b,0.2,1.0,a,0.0,")


def test_truncated_csv_names_its_last_line(saved: Path) -> None:
    path = saved / "a.csv"
    path.write_bytes(path.read_bytes()[:-4])  # cut inside the last row: `0.2,3.0,0.` (3 values)
    text = path.read_text()
    _edit(path, text.splitlines()[-1], "0.2,3.0")
    _refused(loads("envelope", saved), f"{path}:4:1: error", "2 values for 3 columns")


def test_csv_cut_at_a_line_end_disagrees_with_its_summary(saved: Path) -> None:
    path = saved / "a.csv"
    path.write_text("\n".join(path.read_text().splitlines()[:3]) + "\n")  # 2 of 3 rows
    out = _refused(loads("envelope", saved), "a.summary.json:", "rows", "says 3 rows", "has 2")
    assert ":0:0:" not in out


def test_a_text_cell_names_its_line_column_and_name(saved: Path) -> None:
    path = saved / "b.csv"
    _edit(path, "\n0.1,4.0,", "\n0.1,four,")
    _refused(loads("envelope", saved), f"{path}:3:2: error: pin.fx", "'four' is not a number")


def test_nan_in_an_ok_run_is_refused_and_kept_in_a_failed_one(tmp_path: Path) -> None:
    folder = tmp_path / "runs"
    write_results(_outcome("a", 1.0), folder, version="0")
    _edit(folder / "a.csv", "\n0.1,2.0,", "\n0.1,nan,")
    _refused(loads("envelope", folder), f"{folder / 'a.csv'}:3:2: error: pin.fx", "nan", "ok")
    # a failed run's own NaN (written by loads, its csv_sha256 matching) is no problem
    failed = _outcome("c", 1.0, status="failed")
    failed.solution.channels["pin.fx"][2] = np.nan
    write_results(failed, tmp_path / "other", version="0")
    write_results(_outcome("d", 1.0), tmp_path / "other", version="0")
    result = loads("envelope", tmp_path / "other")
    assert result.exit_code == 0, result.output
    assert "c failed; left out of the envelope" in result.output


def test_a_missing_column_is_named(saved: Path) -> None:
    path = saved / "a.csv"
    lines = [line.rsplit(",", 1)[0] for line in path.read_text().splitlines()]  # tz gone
    path.write_text("\n".join(lines) + "\n")
    _refused(loads("envelope", saved), f"{path}:1:1: error: pin.tz", "no such column")


@pytest.mark.parametrize(
    ("key", "old", "new", "expected"),
    [
        ("stats", '"stats": {', '"stats": "fast", "was": {', "must be an object of numbers"),
        ("status", '"status": "ok"', '"status": 5', "must be one of ok, failed"),
        ("parameters", '"parameters": {}', '"parameters": [1]', "must be an object of finite"),
        ("case", '"case": "a"', '"case": 7', "must be a text"),
        ("rows", '"rows": 3', '"rows": "3"', "must be a whole number"),
        ("case", '"case": "a"', '"case": " "', "empty run name"),
    ],
)
def test_a_summary_field_of_the_wrong_type_is_named(
    saved: Path, key: str, old: str, new: str, expected: str
) -> None:
    path = saved / "a.summary.json"
    _edit(path, old, new)
    line = next(n for n, text in enumerate(path.read_text().splitlines(), 1) if f'"{key}"' in text)
    _refused(loads("envelope", saved), f"{path}:{line}:", f"error: {key}: {expected}")


def test_a_summary_that_is_not_json_or_not_an_object(saved: Path) -> None:
    path = saved / "a.summary.json"
    path.write_text('{\n  "case": "a",\n  "status": ok\n}\n')
    _refused(loads("envelope", saved), f"{path}:3:13: error", "not JSON")
    path.write_text("[1, 2]\n")
    _refused(loads("envelope", saved), f"{path}:1:1: error", "not a run summary")


def test_huge_fields_are_refused_and_quoted_short(saved: Path) -> None:
    path = saved / "a.csv"
    _edit(path, "\n0.1,2.0,", "\n0.1," + "x" * 1_000_000 + ",")
    _refused(loads("envelope", saved), f"{path}:3:2: error: pin.fx", "is not a number")
    _edit(path, "x" * 1_000_000, "x" * 20_000_000)
    _refused(loads("envelope", saved), f"{path}:3:1: error", "line longer than")
    _edit(path, "x" * 20_000_000, "9" * 20_000_000)  # a number beyond float range: inf
    _refused(loads("envelope", saved), f"{path}:3:2: error: pin.fx", "inf in a run")
    path.write_text("time," + "y" * 5_000_000 + "\n0.0,1.0\n")
    _refused(loads("envelope", saved), f"{path}:1:1: error", "header longer than")


def test_a_csv_changed_since_its_summary_is_a_warning(saved: Path) -> None:
    """Finite numbers edited by hand: the envelope is made (exit 0) of what the file holds,
    with a warning naming the file; untouched files gave none (test above)."""
    _edit(saved / "a.csv", "\n0.1,2.0,", "\n0.1,7.5,")
    result = loads("envelope", saved)
    assert result.exit_code == 0, result.output
    assert f"{saved / 'a.csv'}:0:0: warning: changed since a.summary.json" in result.output
    assert "pin.fx,7.5,a,0.1," in result.output


def _envelope(tmp_path: Path, saved: Path) -> Path:
    result = loads("envelope", saved, "-o", tmp_path / "env.csv")
    assert result.exit_code == 0, result.output
    return tmp_path / "env.csv"


@pytest.mark.parametrize("peak", ["nan", "inf", "-inf"])
def test_compare_refuses_a_peak_edited_to_a_non_number(tmp_path, saved, peak) -> None:
    old = _envelope(tmp_path, saved)
    new = tmp_path / "new.csv"
    new.write_text(old.read_text().replace("pin.fx,6.0,", f"pin.fx,{peak},", 1))
    _refused(loads("compare", old, new), f"{new}:2:2: error: max", "not finite")


def test_compare_refuses_text_short_rows_and_bad_names(tmp_path: Path, saved: Path) -> None:
    old = _envelope(tmp_path, saved)
    new = tmp_path / "new.csv"
    lines = old.read_text().splitlines()
    new.write_text("\n".join([*lines, "pin.fy,abc,b,0.1,1.0,a,0.0"]) + "\n")
    _refused(loads("compare", old, new), f"{new}:4:2: error: max", "'abc' is not a number")
    new.write_text("\n".join([*lines, "pin.fy,1.0"]) + "\n")
    _refused(loads("compare", old, new), f"{new}:4:", "short or long row")
    new.write_text("\n".join([*lines, lines[1]]) + "\n")
    _refused(loads("compare", old, new), f"{new}:4:1: error: column", "given twice")
    new.write_text("\n".join([lines[0], "pin.\x1bfx" + lines[1][6:]]) + "\n")
    _refused(loads("compare", old, new), f"{new}:2:1: error: column", "(U+001B)")
    new.write_text("col,max\n" + "z" * 200_000 + ",1\n")
    _refused(loads("compare", old, new), f"{new}:1:", "not an envelope table")


def test_compare_of_result_folders_checks_their_runs(tmp_path: Path, saved: Path) -> None:
    """A folder of saved runs is read as `loads envelope` reads it."""
    _edit(saved / "b.summary.json", '"status": "ok"', '"status": "maybe"')
    _refused(loads("compare", saved, saved), f"{saved / 'b.summary.json'}:", "status")


def test_summary_extremes_of_null_and_numbers_are_read(saved: Path) -> None:
    """A column without finite values has null extremes (as `loads` writes them)."""
    path = saved / "a.summary.json"
    summary = json.loads(path.read_text())
    summary["extremes"]["pin.fx"] = dict.fromkeys(summary["extremes"]["pin.fx"])
    path.write_text(json.dumps(summary))
    assert loads("envelope", saved).exit_code == 0


def test_a_row_after_blank_lines_is_named_at_its_line(tmp_path: Path) -> None:
    from loadcases.results.reading import read_run_csv

    path = tmp_path / "r.csv"
    path.write_text("time,a.x\r\n0.0,1.0\r\n\r\n\r\n0.1,2.0\r\n0.2,3.0\r\n")
    table = read_run_csv(path)
    assert table.data.shape == (3, 2)
    assert [table.line_of(row) for row in range(3)] == [2, 5, 6]


@pytest.mark.parametrize(
    ("header", "column", "words"),
    [
        ("time,pin.f\x07x,pin.tz", 2, "control character (U+0007)"),
        ("time,pin.fx,pin.fx", 3, "given twice"),
        ("time,,pin.tz", 2, "empty column name"),
        ("t,pin.fx,pin.tz", 1, "not a results file"),
    ],
)
def test_a_bad_header_is_named(saved: Path, header: str, column: int, words: str) -> None:
    path = saved / "a.csv"
    lines = path.read_text().splitlines()
    path.write_text("\n".join([header, *lines[1:]]) + "\n")
    if header.startswith("t,"):  # no longer a results CSV: left out, as an envelope.csv
        result = loads("envelope", saved)
        assert result.exit_code == 0 and "pin.fx,6.0,b," in result.output
        return
    _refused(loads("envelope", saved), f"{path}:1:{column}: error", words)


def test_an_empty_cell_and_a_long_row_are_named(saved: Path) -> None:
    path = saved / "b.csv"
    _edit(path, "\n0.1,4.0,", "\n0.1,,")
    _refused(loads("envelope", saved), f"{path}:3:2: error: pin.fx", "'' is not a number")
    _edit(path, "\n0.1,,", "\n0.1,4.0,1.0,")
    _refused(loads("envelope", saved), f"{path}:3:1: error", "4 values for 3 columns")


def test_a_summary_level_that_is_neither_limit_nor_ultimate_is_named(saved: Path) -> None:
    path = saved / "a.summary.json"
    _edit(path, '"level": "limit"', '"level": "ultimat"')
    _refused(loads("envelope", saved), f"{path}:", "error: level: must be limit or ultimate")


def test_compare_of_folders_warns_of_a_csv_changed_since_its_summary(saved: Path) -> None:
    _edit(saved / "a.csv", "\n0.1,2.0,", "\n0.1,7.5,")
    result = loads("compare", saved, saved)
    assert result.exit_code == 0, result.output
    assert f"{saved / 'a.csv'}:0:0: warning: changed since a.summary.json" in result.output
    (saved / "b.csv").write_bytes((saved / "b.csv").read_bytes())  # touched, not changed
    _edit(saved / "a.csv", "\n0.1,7.5,", "\n0.1,2.0,")  # back as written
    assert "warning" not in loads("compare", saved, saved).output


def test_a_summary_s_request_kinds_are_read_back_and_checked(tmp_path: Path) -> None:
    """The `kinds` a run's summary records (the report charts by them) pass the reading
    checks, come back with the run's level, and are refused when not an object of texts."""
    from loadcases.results.saved import load_saved_run

    outcome = _outcome("a", 1.0)
    outcome.request_kinds, outcome.level = {"pin": "reaction"}, "ultimate"
    folder = tmp_path / "runs"
    write_results(outcome, folder, version="0")
    run = load_saved_run(folder / "a.csv")
    assert (run.kinds, run.level) == ({"pin": "reaction"}, "ultimate")
    assert loads("envelope", folder).exit_code == 0
    path = folder / "a.summary.json"
    summary = json.loads(path.read_text(encoding="utf-8"))
    summary["kinds"] = {"pin": 3}
    path.write_text(json.dumps(summary, indent=2), encoding="utf-8")
    _refused(loads("envelope", folder), f"{path}:", "error: kinds: must be an object of texts")
