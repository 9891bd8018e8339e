"""Result files (SPEC section 3): CSV by value, summary.json, workbook, atomic writes."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import openpyxl
import pandas as pd
import pytest

import loadcases.foundation.atomic as atomic
from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.report.envelope import (
    ENVELOPE_COLUMNS,
    envelope_csv_text,
    extract_envelope,
    find_result_files,
    load_saved_runs,
)
from loadcases.results.files import read_results, result_base, write_results
from loadcases.results.outcome import RunOutcome
from mechlib.core.outcome import EventRecord, Solution, SolverStats

TIME = np.array([0.0, 0.1, 0.2, 0.3, 0.4])
# Values chosen to need all 17 significant digits, plus a NaN and a negative extreme.
FX = np.array([1.0 / 3.0, 2.5e-17, -7.123456789012345e5, np.nan, 12.0])
TZ = np.array([0.1, 0.2, 0.30000000000000004, -0.4, 0.4])


def make_outcome(
    name: str = "slider/crank[w=6.28319]", status: str = "ok", fx: np.ndarray = FX
) -> RunOutcome:
    """A hand-made outcome with two channels, one event, one warning."""
    solution = Solution(
        status=status,
        message="done" if status == "ok" else "Newton failed at t = 0.3 s: hinge",
        analysis="dynamic",
        time=TIME.copy(),
        channels={"pivot_force.fx": fx.copy(), "pivot_force.tz": TZ.copy()},
        stats=SolverStats(steps=42, rejected_steps=3, newton_iterations=97, cpu_seconds=0.25),
        warnings=["tolerance loose"],
        events=[EventRecord("lock", 0.2, ("activate latch",))],
    )
    return RunOutcome(
        name=name,
        case_file=Path("slider.case.yaml"),
        analysis="dynamic",
        solution=solution,
        input_sha256="ab" * 32,
        column_units={"pivot_force.fx": "N", "pivot_force.tz": "N*m"},
        warnings=[
            Diagnostic(
                "slider.case.yaml", 7, 3, "initial.pivot", "initial pivot rate changed", "warning"
            )
        ],
        parameters={"w": 6.28319},
    )


def leftovers(directory: Path) -> list[str]:
    """Temporary files left behind by atomic writes."""
    return [p.name for p in directory.rglob("*") if p.name.endswith(".tmp")]


def test_csv_reads_back_by_value(tmp_path: Path) -> None:
    paths = write_results(make_outcome(), tmp_path, version="1.2.3")
    csv_path = tmp_path / "slider" / "crank[w=6.28319].csv"
    assert paths == [csv_path, tmp_path / "slider" / "crank[w=6.28319].summary.json"]
    frame = pd.read_csv(csv_path)
    assert list(frame.columns) == ["time", "pivot_force.fx", "pivot_force.tz"]
    np.testing.assert_array_equal(frame["time"].to_numpy(), TIME)
    np.testing.assert_array_equal(frame["pivot_force.fx"].to_numpy(), FX)  # NaN == NaN here
    np.testing.assert_array_equal(frame["pivot_force.tz"].to_numpy(), TZ)
    time, channels = read_results(csv_path)
    np.testing.assert_array_equal(time, TIME)
    assert list(channels) == ["pivot_force.fx", "pivot_force.tz"]
    assert channels["pivot_force.fx"][2] == FX[2] and math.isnan(channels["pivot_force.fx"][3])


def test_csv_cells_read_back_to_the_same_doubles(tmp_path: Path) -> None:
    """Each cell is the shortest decimal of its double (1/3 -> 0.3333333333333333, 17
    significant digits at most) and reads back to it bit for bit; not-finite values are
    `nan`, `inf`, `-inf`, and a row with one is written like the others otherwise."""
    rng = np.random.default_rng(7)
    fx = np.concatenate(
        [[1.0 / 3.0, np.inf, -np.inf, np.nan, 1e16, 1.5e-5, -0.0, 5e-324], rng.normal(size=6)]
    )
    tz = np.concatenate([[1e-29, 2.5, 0.1, 1e300, 7.0, 2.0**60, -1.0, 3.0], rng.normal(size=6)])
    time = np.linspace(0.0, 1.3, fx.size)
    outcome = make_outcome()
    outcome.solution.time = time
    outcome.solution.channels = {"pivot_force.fx": fx, "pivot_force.tz": tz}
    write_results(outcome, tmp_path, version="1.2.3")
    lines = (tmp_path / "slider" / "crank[w=6.28319].csv").read_text().splitlines()
    assert lines[0] == "time,pivot_force.fx,pivot_force.tz"
    cells = [line.split(",") for line in lines[1:]]
    assert [row[1] for row in cells[:5]] == ["0.3333333333333333", "inf", "-inf", "nan", "1e+16"]
    assert [row[2] for row in cells[:4]] == ["1e-29", "2.5", "0.1", "1e+300"]
    for row, values in zip(cells, np.column_stack([time, fx, tz])):
        for cell, value in zip(row, values):
            read = float(cell)
            assert read == value or (math.isnan(read) and math.isnan(value))
            assert math.copysign(1.0, read) == math.copysign(1.0, value)
            assert len(cell.lstrip("-").replace(".", "").split("e")[0].strip("0")) <= 17
    # the finite rows of a run without NaN are the same text (one orjson call, no per row)
    finite = np.isfinite(fx)
    outcome.solution.time = time[finite]
    outcome.solution.channels = {"pivot_force.fx": fx[finite], "pivot_force.tz": tz[finite]}
    write_results(outcome, tmp_path, version="1.2.3")
    again = (tmp_path / "slider" / "crank[w=6.28319].csv").read_text().splitlines()
    assert again[1:] == [line for line, keep in zip(lines[1:], finite) if keep]


def test_a_solved_run_in_memory_equals_its_files_read_back(tmp_path: Path) -> None:
    """A set's report takes the runs it has just solved from memory (saved_run_of): the
    same names, units, status and numbers as load_saved_run reads from their files."""
    from loadcases.results.saved import load_saved_run, saved_run_of

    outcome = make_outcome()
    write_results(outcome, tmp_path, version="1.2.3")
    read = load_saved_run(tmp_path / "slider" / "crank[w=6.28319].csv")
    held = saved_run_of(outcome)
    assert (held.name, held.family, held.status, held.units) == (
        read.name,
        read.family,
        read.status,
        read.units,
    )
    np.testing.assert_array_equal(held.time, read.time)
    assert list(held.channels) == list(read.channels)
    for name, values in read.channels.items():
        np.testing.assert_array_equal(held.channels[name], values)  # NaN == NaN here


def test_summary_json(tmp_path: Path) -> None:
    write_results(make_outcome(), tmp_path, version="1.2.3")
    text = (tmp_path / "slider" / "crank[w=6.28319].summary.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    summary = json.loads(text)
    assert {
        "case",
        "status",
        "analysis",
        "message",
        "stats",
        "extremes",
        "input_sha256",
        "version",
    } <= summary.keys()
    assert summary["case"] == "slider/crank[w=6.28319]"
    assert (summary["status"], summary["analysis"], summary["version"]) == (
        "ok",
        "dynamic",
        "1.2.3",
    )
    assert summary["stats"] == {
        "steps": 42,
        "rejected_steps": 3,
        "newton_iterations": 97,
        "factorizations": 0,
        "jacobian_evaluations": 0,
        "cpu_seconds": 0.25,
    }
    assert summary["input_sha256"] == "ab" * 32
    assert summary["extremes"]["pivot_force.fx"] == {
        "max": 12.0,
        "time_of_max": 0.4,
        "min": FX[2],
        "time_of_min": 0.2,
    }
    assert summary["extremes"]["pivot_force.tz"] == {
        "max": 0.4,
        "time_of_max": 0.4,
        "min": -0.4,
        "time_of_min": 0.3,
    }
    assert "time" not in summary["extremes"]
    assert summary["events"] == [{"name": "lock", "time": 0.2, "actions": ["activate latch"]}]
    assert summary["warnings"] == ["initial.pivot: initial pivot rate changed", "tolerance loose"]
    assert summary["parameters"] == {"w": 6.28319}


def test_all_nan_column_gives_nulls_and_valid_json(tmp_path: Path) -> None:
    write_results(make_outcome(name="c", fx=np.full(5, np.nan)), tmp_path, version="0")
    summary = json.loads((tmp_path / "c.summary.json").read_text())
    assert summary["extremes"]["pivot_force.fx"] == {
        "max": None,
        "time_of_max": None,
        "min": None,
        "time_of_min": None,
    }


def test_failed_run_is_written_with_status_and_message(tmp_path: Path) -> None:
    write_results(make_outcome(name="c", status="failed"), tmp_path, version="0")
    summary = json.loads((tmp_path / "c.summary.json").read_text())
    assert summary["status"] == "failed"
    assert summary["message"] == "Newton failed at t = 0.3 s: hinge"
    assert len(pd.read_csv(tmp_path / "c.csv")) == len(TIME)


def test_empty_solution_writes_header_only(tmp_path: Path) -> None:
    outcome = make_outcome(name="c", status="failed")
    outcome.solution.time = np.empty(0)
    outcome.solution.channels = {k: np.empty(0) for k in outcome.solution.channels}
    write_results(outcome, tmp_path, version="0")
    assert (tmp_path / "c.csv").read_text() == "time,pivot_force.fx,pivot_force.tz\n"
    time, channels = read_results(tmp_path / "c.csv")
    assert time.shape == (0,) and channels["pivot_force.fx"].shape == (0,)


def test_workbook_has_units_frozen_header_and_summary(tmp_path: Path) -> None:
    paths = write_results(make_outcome(name="c"), tmp_path, xlsx=True, version="0")
    assert tmp_path / "c.xlsx" in paths
    book = openpyxl.load_workbook(tmp_path / "c.xlsx")
    assert book.sheetnames == ["Time histories", "Summary"]
    sheet = book["Time histories"]
    assert sheet.freeze_panes == "A2"
    rows = list(sheet.iter_rows(values_only=True))
    assert rows[0] == ("time [s]", "pivot_force.fx [N]", "pivot_force.tz [N*m]")
    assert [r[0] for r in rows[1:]] == list(TIME)
    assert [r[1] for r in rows[1:]] == [FX[0], FX[1], FX[2], None, FX[4]]
    assert [r[2] for r in rows[1:]] == list(TZ)  # 0.30000000000000004: 17 digits, exactly
    summary = {r[0]: r[1] for r in book["Summary"].iter_rows(values_only=True) if r}
    assert summary["status"] == "ok" and summary["steps"] == 42


def test_bad_names_and_shapes_are_refused(tmp_path: Path) -> None:
    assert result_base(tmp_path, "a/b") == tmp_path / "a" / "b"
    for name in ("", "../x", "/abs"):
        with pytest.raises(ValueError):
            result_base(tmp_path, name)
    outcome = make_outcome(name="c")
    outcome.solution.channels["short.value"] = np.zeros(2)
    with pytest.raises(ValueError, match=r"short\.value"):
        write_results(outcome, tmp_path, version="0")
    assert list(tmp_path.iterdir()) == []


def test_atomic_write_failure_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "sub" / "x.csv"

    def broken_fsync(fd: int) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "fsync", broken_fsync)
    with pytest.raises(OSError):
        atomic_write_text(target, "time\n" * 1000)
    assert not target.exists() and leftovers(tmp_path) == []


def test_atomic_write_failure_keeps_previous_file(tmp_path: Path) -> None:
    target = tmp_path / "x.xlsx"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half a work")
        raise RuntimeError("crash while saving")
    assert target.read_text() == "old" and leftovers(tmp_path) == []
    atomic_write_text(target, "new")
    assert target.read_text() == "new"
    umask = os.umask(0o022)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's private 0o600


def test_atomic_write_without_overwrite_keeps_a_file_made_meanwhile(tmp_path: Path) -> None:
    """`overwrite=False` (new case skeletons): a file that appears while the new one is
    written is kept, the write fails and leaves no temporary file."""
    target = tmp_path / "a.case.yaml"
    with pytest.raises(FileExistsError), atomic_path(target, overwrite=False) as tmp:
        tmp.write_text("new\n")
        target.write_text("made meanwhile\n")
    assert target.read_text() == "made meanwhile\n" and leftovers(tmp_path) == []
    atomic_write_text(tmp_path / "b.txt", "b\n", overwrite=False)
    assert (tmp_path / "b.txt").read_text() == "b\n" and leftovers(tmp_path) == []


def test_write_results_failure_midway(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The CSV is complete, the summary (written last) fails: no partial summary remains,
    and the CSV is removed too (a run's files are all written or none: a CSV without its
    summary would read back as an ok run)."""
    calls = []
    real_fsync = os.fsync

    def fsync_failing_second(fd: int) -> None:
        calls.append(fd)
        if len(calls) == 2:
            raise OSError(5, "I/O error")
        real_fsync(fd)

    monkeypatch.setattr(atomic.os, "fsync", fsync_failing_second)
    with pytest.raises(OSError, match=r"missing: .*c\.csv, .*c\.summary\.json"):
        write_results(make_outcome(name="c"), tmp_path, version="0")
    assert not (tmp_path / "c.csv").exists()
    assert not (tmp_path / "c.summary.json").exists() and leftovers(tmp_path) == []


def test_workbook_save_failure_leaves_no_workbook(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    real_save = openpyxl.Workbook.save

    def broken_save(self: openpyxl.Workbook, filename: str) -> None:
        real_save(self, filename)
        with open(filename, "r+b") as stream:  # the disk filled up half way
            stream.truncate(os.path.getsize(filename) // 2)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(openpyxl.Workbook, "save", broken_save)
    with pytest.raises(OSError):
        write_results(make_outcome(name="c"), tmp_path, xlsx=True, version="0")
    assert not (tmp_path / "c.xlsx").exists() and leftovers(tmp_path) == []


def test_envelope_across_saved_runs(tmp_path: Path) -> None:
    write_results(make_outcome(name="a"), tmp_path, version="0")
    write_results(make_outcome(name="b", fx=FX * 2.0), tmp_path / "more", version="0")
    (tmp_path / "envelope.csv").write_text("column,max\nx,1\n")  # not a result: skipped
    files = find_result_files([tmp_path])
    assert [p.name for _, p in files] == ["a.csv", "b.csv"]
    rows = {row.column: row for row in extract_envelope(load_saved_runs(files))}
    fx = rows["pivot_force.fx"]
    assert (fx.max, fx.max_run, fx.max_time) == (24.0, "b", 0.4)
    assert (fx.min, fx.min_run, fx.min_time) == (2.0 * FX[2], "b", 0.2)
    tz = rows["pivot_force.tz"]  # equal in both runs: the first run is kept
    assert (tz.max_run, tz.min_run, tz.min_time) == ("a", "a", 0.3)
    lines = envelope_csv_text(list(rows.values())).splitlines()
    assert lines[0] == ",".join(ENVELOPE_COLUMNS)
    assert lines[1].startswith(f"pivot_force.fx,24.0,b,0.4,{float(2.0 * FX[2])!r},b,0.2,")


def test_read_results_parses_as_float_does(tmp_path: Path) -> None:
    """read_results (numpy's C text reader) gives each value exactly as Python's float()
    parses its text: 3000 random doubles over the whole exponent range, subnormals, the
    largest double, -0.0, nan and infinities; CRLF line ends and blank lines are read too."""
    rng = np.random.default_rng(3)
    values = rng.normal(size=3000) * 10.0 ** rng.integers(-300, 300, 3000)
    values[:6] = [5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, -0.0, np.nan, -np.inf]
    texts = [repr(float(v)) for v in values]
    texts[7] = "0.000015"  # as orjson writes 1.5e-05
    lines = [f"{k * 1e-3!r},{text}" for k, text in enumerate(texts)]
    path = tmp_path / "r.csv"
    path.write_bytes(
        (
            "time,a.x\r\n" + "\r\n".join(lines[:10]) + "\r\n\r\n" + "\r\n".join(lines[10:]) + "\r\n"
        ).encode()
    )
    time, channels = read_results(path)
    expected = np.array([float(text) for text in texts])
    np.testing.assert_array_equal(channels["a.x"], expected)  # NaN where NaN
    assert np.signbit(channels["a.x"][3]) and channels["a.x"][7] == 1.5e-5
    np.testing.assert_array_equal(time, [k * 1e-3 for k in range(len(texts))])


def test_read_results_of_no_rows_and_of_a_short_row(tmp_path: Path) -> None:
    empty = tmp_path / "e.csv"
    empty.write_text("time,a.x,a.y\n")
    time, channels = read_results(empty)
    assert time.shape == (0,) and [c.shape for c in channels.values()] == [(0,), (0,)]
    short = tmp_path / "s.csv"
    short.write_text("time,a.x,a.y\n0.0,1.0\n")
    with pytest.raises(ValueError):
        read_results(short)
