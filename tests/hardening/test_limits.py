"""Issue 15 item 6: documented limits give exit 2 with a message, not a hang or an
out-of-memory: output rows, runs of a set, YAML alias expansion and nesting, `cases:` globs
outside the set's folder; `--jobs` above the cores is capped with a warning."""

from __future__ import annotations

import os
import time
from pathlib import Path

from loadcases.foundation.limits import MAX_ROWS, MAX_RUNS
from tests.hardening.conftest import has_line, loads


def test_too_many_output_rows_is_an_input_error(crank, tmp_path: Path) -> None:
    case = crank(case=("end: 0.5, step: 0.05", "end: 1000, step: 1e-9"))
    result = loads("validate", case)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "crank.case.yaml:5:40: error: analysis.step: end / step "
        f"gives 1e+12 output rows; at most {MAX_ROWS:,} (take a longer step or a "
        "shorter end)",
    ), result.output


def test_too_many_runs_in_a_set_is_an_input_error(crank, tmp_path: Path) -> None:
    crank()
    values = "[" + ", ".join(str(v) for v in range(1, 401)) + "]"
    path = tmp_path / "s.set.yaml"
    path.write_text(
        f"set: s\ncases: [crank.case.yaml]\nsweep:\n  speed: {values}\n  load: {values}\n",
        encoding="utf-8",
    )
    started = time.perf_counter()
    result = loads("validate", path)
    assert time.perf_counter() - started < 30
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "s.set.yaml:3:1: error: sweep: the sweep gives 160,000 "
        f"runs; a set has at most {MAX_RUNS:,}",
    ), result.output


def test_yaml_alias_bomb_is_refused_quickly(tmp_path: Path) -> None:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 10) + "]" for k in range(1, 9)]
    path = tmp_path / "bomb.case.yaml"
    path.write_text("case: bomb\n" + "\n".join(lines) + "\n", encoding="utf-8")
    started = time.perf_counter()
    result = loads("validate", path)
    assert time.perf_counter() - started < 30
    assert result.exit_code == 2, result.output
    assert any(
        "YAML syntax error: more than 1,000,000 values once aliases are expanded" in line
        for line in result.output.splitlines()
    ), result.output


def test_deep_nesting_is_refused(tmp_path: Path) -> None:
    for depth in (150, 5000):
        path = tmp_path / "deep.case.yaml"
        path.write_text("case: deep\nx: " + "[" * depth + "]" * depth + "\n", encoding="utf-8")
        result = loads("validate", path)
        assert result.exit_code == 2, result.output
        assert any(
            "YAML syntax error: nested more than 100 levels deep" in line
            for line in result.output.splitlines()
        ), (depth, result.output)


def test_cases_glob_outside_the_set_folder_is_refused(crank, tmp_path: Path) -> None:
    crank()
    sub = tmp_path / "sets"
    sub.mkdir()
    path = sub / "s.set.yaml"
    path.write_text("set: s\ncases: ['../*.case.yaml']\n", encoding="utf-8")
    result = loads("validate", path)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "s.set.yaml:2:9: error: cases[0]: the pattern "
        "'../*.case.yaml' leaves the set file's folder; patterns stay inside it "
        "(name files outside it one by one)",
    ), result.output
    path.write_text("set: s\ncases: ['../crank.case.yaml']\n", encoding="utf-8")
    assert loads("validate", path).exit_code == 0


def test_jobs_above_the_cores_are_capped_with_a_warning(crank, tmp_path: Path) -> None:
    case = crank()
    cores = os.cpu_count() or 1
    result = loads("run", case, "-o", tmp_path / "out", "--jobs", cores + 5)
    assert result.exit_code == 0, result.output
    assert (
        f"loads: warning: --jobs {cores + 5} is more than the {cores} cores of this "
        f"machine: {cores} used"
    ) in result.output
