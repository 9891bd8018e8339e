"""Issue 15 item 2: a saved run is reused only when its summary is ok, of the same input
and of the same engine (hash of the installed source), and its CSV is the one it wrote."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

import loadcases.foundation.engine_hash as engine_hash
from loadcases.sets.campaign import run_set
from tests.loadcases.set_fixtures import write_inputs

FIRST = "crank-turn[speed=1,load=10N]"


@pytest.fixture()
def inputs(tmp_path: Path) -> Path:
    return write_inputs(tmp_path)


def _reused(result) -> list[bool]:
    return [record.reused for record in result.records]


def test_summary_records_engine_and_csv_hashes(inputs: Path) -> None:
    result = run_set(inputs / "crank.set.yaml", output_dir=inputs / "out")
    csv_path = result.directory / f"{FIRST}.csv"
    summary = json.loads((result.directory / f"{FIRST}.summary.json").read_text())
    assert summary["csv_sha256"] == hashlib.sha256(csv_path.read_bytes()).hexdigest()
    assert summary["engine_sha256"] == engine_hash.engine_sha256()
    assert len(summary["engine_sha256"]) == 64


def test_truncated_or_foreign_csv_is_solved_again(inputs: Path) -> None:
    out = inputs / "out"
    first = run_set(inputs / "crank.set.yaml", output_dir=out)
    csv_path = first.directory / f"{FIRST}.csv"
    whole = csv_path.read_bytes()
    csv_path.write_bytes(whole[: len(whole) // 2])  # truncated
    other = first.directory / "crank-turn[speed=3,load=20N].csv"
    other.write_bytes(csv_path.with_name("crank-turn[speed=2,load=10N].csv").read_bytes())
    again = run_set(inputs / "crank.set.yaml", output_dir=out)
    assert _reused(again) == [False, True, True, True, True, False]
    assert csv_path.read_bytes() == whole
    assert all(_reused(run_set(inputs / "crank.set.yaml", output_dir=out)))


def test_interrupted_after_csv_then_input_reverted_is_solved_again(inputs: Path) -> None:
    """Run; change the input and run again but 'killed' between CSV and summary (the old
    summary stays); revert the input: the old summary matches the input, not the CSV."""
    out = inputs / "out"
    case = inputs / "crank.case.yaml"
    original = case.read_text()
    first = run_set(inputs / "crank.set.yaml", output_dir=out)
    summary_path = first.directory / f"{FIRST}.summary.json"
    old_summary = summary_path.read_bytes()
    case.write_text(original.replace("end: 0.5", "end: 0.4"))
    run_set(inputs / "crank.set.yaml", output_dir=out)
    summary_path.write_bytes(old_summary)  # the summary of the killed run
    case.write_text(original)
    again = run_set(inputs / "crank.set.yaml", output_dir=out)
    assert _reused(again)[0] is False
    assert again.records[0].ok


def test_other_engine_source_is_solved_again(inputs: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = inputs / "out"
    run_set(inputs / "crank.set.yaml", output_dir=out)
    monkeypatch.setattr(engine_hash, "engine_sha256", lambda: "0" * 64)
    again = run_set(inputs / "crank.set.yaml", output_dir=out)
    assert not any(_reused(again))
    assert all(_reused(run_set(inputs / "crank.set.yaml", output_dir=out)))


def test_engine_hash_covers_every_source_file(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """The hash changes with one byte of one .py file of a package, and not otherwise."""
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "a.py").write_text("x = 1\n")
    (package / "sub" / "b.py").write_text("y = 2\n")
    (package / "data.txt").write_text("not source\n")
    before = engine_hash.source_sha256([package])
    (package / "data.txt").write_text("changed\n")
    assert engine_hash.source_sha256([package]) == before
    (package / "sub" / "b.py").write_text("y = 3\n")
    assert engine_hash.source_sha256([package]) != before
