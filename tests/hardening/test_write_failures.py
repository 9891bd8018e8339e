"""Writes that fail (issue 39 item 6): a disk that fills up or a folder that refuses files
fails the run or the set (exit 1) with a message naming the files that are missing; no
file is left half-written, none of a run is left without the others, and a set's envelope
is never computed from a run whose files could not be written.

The disk is simulated full (OSError ENOSPC) or the folder refusing (EACCES) by patching the
writes: the tests run as root here, which no folder permission stops.

The crank (tests/loadcases/set_fixtures.py) turns at 1 rad/s holding a load P at its 0.1 m
tip: drive torque (0.1 P + m g 0.05) cos(angle), largest at t = 0: 1.4905 N*m for P = 10 N
and 2.4905 N*m for P = 20 N (statics of the crank, closed form).
"""

from __future__ import annotations

import csv
import errno
import os
from pathlib import Path

import pytest

from loadcases.foundation import atomic
from loadcases.results import files
from tests.hardening.conftest import loads
from tests.loadcases.set_fixtures import write_inputs


def _no_space(*_args, **_kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def _folder(path: Path) -> Path:
    path.mkdir(parents=True)
    return path


def _leftovers(folder: Path) -> list[str]:
    """Temporary files of atomic writes left behind."""
    return [p.name for p in folder.rglob("*") if p.name.endswith(".tmp")]


def test_a_case_whose_summary_does_not_fit_fails_and_leaves_no_file(
    tmp_path: Path, monkeypatch
) -> None:
    """The CSV fits, the summary does not: the CSV is removed (a CSV without its summary
    would read as an ok run), exit 1 naming both files."""
    folder = write_inputs(_folder(tmp_path / "in"))
    monkeypatch.setattr(files, "atomic_write_text", _no_space)
    out = tmp_path / "out"
    result = loads("run", folder / "crank.case.yaml", "-o", out)
    assert result.exit_code == 1, result.output
    assert "internal error" not in result.output and "Traceback" not in result.output
    assert "crank-turn: failed" in result.output
    assert "results not written (No space left on device); missing: " in result.output
    assert str(out / "crank-turn.csv") in result.output
    assert str(out / "crank-turn.summary.json") in result.output
    assert sorted(p.name for p in out.rglob("*") if p.is_file() and p.suffix != ".npz") == []


def test_a_disk_full_mid_file_leaves_neither_the_file_nor_its_temporary(
    tmp_path: Path, monkeypatch
) -> None:
    """The data written, the flush to disk failing: the temporary file is removed and the
    previous content of the target is untouched."""
    target = tmp_path / "r.csv"
    target.write_text("old\n")
    monkeypatch.setattr(atomic.os, "fsync", _no_space)
    with pytest.raises(OSError, match="No space left"):
        atomic.atomic_write_bytes(target, b"time\n" + b"0.0\n" * 1000)
    assert target.read_text() == "old\n"
    assert _leftovers(tmp_path) == []


def test_a_folder_refusing_files_fails_the_case(tmp_path: Path, monkeypatch) -> None:
    folder = write_inputs(_folder(tmp_path / "in"))

    def refused(*_args, **_kwargs):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))

    monkeypatch.setattr(atomic.tempfile, "mkstemp", refused)
    result = loads("run", folder / "crank.case.yaml", "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    assert "results not written (Permission denied)" in result.output
    assert "internal error" not in result.output


def _two_run_set(tmp_path: Path) -> Path:
    folder = write_inputs(_folder(tmp_path / "in"))
    path = folder / "two.set.yaml"
    path.write_text(
        "set: two\ncases: [crank.case.yaml]\nparameters: {speed: 1.0}\nsweep: {load: [10, 20]}\n",
        encoding="utf-8",
    )
    return path


def test_a_set_run_that_does_not_fit_fails_and_stays_out_of_the_envelope(
    tmp_path: Path, monkeypatch
) -> None:
    """The P = 20 N run's CSV does not fit: exit 1, that run failed naming its missing
    files, and the envelope is the P = 10 N run's alone (1.4905 N*m, not 2.4905)."""
    write = files.atomic_write_bytes

    def full_for_20(target, data, **kwargs):
        if "load=20" in Path(target).name:
            _no_space()
        return write(target, data, **kwargs)

    monkeypatch.setattr(files, "atomic_write_bytes", full_for_20)
    out = tmp_path / "out"
    result = loads("run", _two_run_set(tmp_path), "-o", out, "--jobs", "1")
    assert result.exit_code == 1, result.output
    assert "internal error" not in result.output
    assert "crank-turn[load=20]: failed" in result.output
    assert f"missing: {out / 'two' / 'crank-turn[load=20].csv'}" in result.output
    assert "two: 2 runs, 1 failed, 0 reused" in result.output
    names = sorted(p.name for p in (out / "two").iterdir() if "load=" in p.name)
    assert names == ["crank-turn[load=10].csv", "crank-turn[load=10].summary.json"]
    with open(out / "two" / "envelope.csv", newline="", encoding="utf-8") as handle:
        row = next(r for r in csv.DictReader(handle) if r["column"] == "drive_torque.value")
    assert row["max_run"] == "crank-turn[load=10]"
    assert float(row["max"]) == pytest.approx(0.1 * 10 + 1.0 * 9.81 * 0.05, rel=1e-12)
    assert _leftovers(out) == []


def test_a_set_whose_report_does_not_fit_fails_naming_its_files(
    tmp_path: Path, monkeypatch
) -> None:
    from loadcases.report import envelope

    monkeypatch.setattr(envelope, "atomic_write_text", _no_space)
    out = tmp_path / "out"
    result = loads("run", _two_run_set(tmp_path), "-o", out, "--jobs", "1")
    assert result.exit_code == 1, result.output
    assert "internal error" not in result.output
    assert "two: 2 runs, 0 failed, 0 reused" in result.output
    assert "two: report not written (No space left on device); missing: " in result.output
    assert str(out / "two" / "envelope.csv") in result.output
    assert str(out / "two" / "envelope.xlsx") in result.output
    assert not (out / "two" / "envelope.csv").exists()
    assert _leftovers(out) == []


def test_envelope_and_compare_outputs_that_do_not_fit(tmp_path: Path, monkeypatch) -> None:
    """`loads envelope -o` and `loads compare -o` on a full disk: exit 1 naming the file,
    which is not there (nor its temporary)."""
    from loadcases.report import compare, envelope

    out = tmp_path / "out"
    assert loads("run", _two_run_set(tmp_path), "-o", out, "--jobs", "1").exit_code == 0
    monkeypatch.setattr(envelope, "atomic_write_text", _no_space)
    monkeypatch.setattr(compare, "atomic_write_text", _no_space)
    for args in (("envelope", out / "two", "-o"), ("compare", out / "two", out / "two", "-o")):
        target = tmp_path / f"{args[0]}.csv"
        result = loads(*args, target)
        assert result.exit_code == 1, result.output
        assert f"{target}: not written (No space left on device); missing: {target}" in (
            result.output
        )
        assert not target.exists() and "internal error" not in result.output
    assert _leftovers(tmp_path) == []
