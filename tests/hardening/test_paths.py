"""Issue 15 item 4: results stay inside the output folder; names that cannot be file names,
an unusable `-o`, duplicate case names and long inputs are input errors (exit 2) before
anything is solved."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from tests.hardening.conftest import has_line, loads

SET = "set: s\ncases: [crank.case.yaml]\nsweep: {speed: [1.0, 2.0]}\n"


def _set(folder: Path, text: str) -> Path:
    path = folder / "s.set.yaml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "output,reason",
    [
        ("../../evil.xlsx", "it leaves the output folder ('..')"),
        ("/tmp/evil.xlsx", "an absolute path; give a name relative to the output folder"),
        ("sub//x.xlsx", "an empty folder name ('//')"),
        ("C:/evil.xlsx", "an absolute path; give a name relative to the output folder"),
    ],
)
@pytest.mark.parametrize("command", ["validate", "run"])
def test_report_output_outside_the_output_folder_is_refused(
    crank, tmp_path: Path, command: str, output: str, reason: str
) -> None:
    crank()
    path = _set(tmp_path, SET + f"report: {{output: '{output}'}}\n")
    extra = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, path, *extra)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        f"s.set.yaml:4:10: error: report.output: '{output}' "
        f"cannot be the workbook's name: {reason}",
    ), result.output
    assert not (tmp_path / "out").exists()


def test_report_template_missing_or_absolute_is_refused(crank, tmp_path: Path) -> None:
    crank()
    path = _set(tmp_path, SET + "report: {output: x.xlsx, template: nothere.xlsx}\n")
    result = loads("validate", path)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "s.set.yaml:4:26: error: report.template: no such file "
        "'nothere.xlsx' (relative to the set file)",
    ), result.output
    path = _set(tmp_path, SET + "report: {output: x.xlsx, template: /etc/passwd}\n")
    result = loads("validate", path)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "s.set.yaml:4:26: error: report.template: '/etc/passwd' "
        "is an absolute path; give it relative to the set file",
    ), result.output


@pytest.mark.parametrize(
    "name,reason",
    [
        ("..", "it leaves the output folder ('..')"),
        ("a/../../b", "it leaves the output folder ('..')"),
        ("/etc/x", "an absolute path"),
        ("a//b", "an empty folder name ('//')"),
        ('"a\\tb"', "a tab (U+0009)"),  # other hidden characters: test_clean_text.py
        ('"a\\nb"', "a line break (U+000A)"),
        ("a\\b", "a backslash (use '/' for sub-folders)"),
        ("x" * 201, "longer than 200 bytes (201)"),
        ("'=1+2'", "it starts with '=' (a formula in a spreadsheet)"),
        ("'@x'", "it starts with '@' (a formula in a spreadsheet)"),
        ("'-x'", "it starts with '-' (a formula in a spreadsheet)"),
    ],
)
@pytest.mark.parametrize("command", ["validate", "run"])
def test_case_name_that_cannot_be_a_file_name_is_refused(
    crank, tmp_path: Path, command: str, name: str, reason: str
) -> None:
    case = crank(case=("case: crank-turn", f"case: {name}"))
    extra = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, case, *extra)
    assert result.exit_code == 2, result.output
    line = next(line for line in result.output.splitlines() if ": error: case: " in line)
    assert line.endswith(
        f"crank.case.yaml:1:1: error: case: cannot be a result file name: {reason}"
    ), line
    assert not (tmp_path / "out").exists()


def test_set_name_that_cannot_be_a_file_name_is_refused(crank, tmp_path: Path) -> None:
    crank()
    result = loads("validate", _set(tmp_path, SET.replace("set: s", "set: ../up")))
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "s.set.yaml:1:1: error: set: cannot be a result file "
        "name: it leaves the output folder ('..')",
    ), result.output


def test_output_folder_that_is_a_file_is_reported_before_solving(crank, tmp_path: Path) -> None:
    case = crank()
    (tmp_path / "afile").write_text("x")
    result = loads("run", case, "-o", tmp_path / "afile")
    assert result.exit_code == 2, result.output
    assert f"loads: error: -o {tmp_path / 'afile'}: is a file, not a folder" in result.output
    result = loads("run", case, "-o", tmp_path / "afile" / "sub")
    assert result.exit_code == 2, result.output
    assert (
        f"loads: error: -o {tmp_path / 'afile' / 'sub'}: {tmp_path / 'afile'} is a file, "
        "not a folder"
    ) in result.output


@pytest.mark.skipif(
    os.name != "posix" or os.geteuid() == 0, reason="root writes into read-only folders"
)
def test_read_only_output_folder_is_reported_before_solving(crank, tmp_path: Path) -> None:
    case = crank()
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    try:
        result = loads("run", case, "-o", locked / "out")
    finally:
        locked.chmod(0o755)
    assert result.exit_code == 2, result.output
    assert f"loads: error: -o {locked / 'out'}: {locked} is not writable" in result.output


def test_read_only_check_uses_access_rights(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The same check as above where the tests run as root: os.access says no."""
    from loadcases.inputs import preflight

    monkeypatch.setattr(preflight.os, "access", lambda path, mode: False)
    assert preflight.output_folder_problem(tmp_path / "out") == f"{tmp_path} is not writable"


def test_two_case_files_with_one_case_name_are_refused_before_solving(
    crank, tmp_path: Path
) -> None:
    case = crank()
    other = tmp_path / "other.case.yaml"
    other.write_text(case.read_text(encoding="utf-8"), encoding="utf-8")
    result = loads("run", case, other, "-o", tmp_path / "out")
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output,
        "other.case.yaml:1:7: error: case: case name 'crank-turn' "
        "is also the name in crank.case.yaml (both would write "
        "crank-turn.csv)",
    ), result.output
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("text", ["- [1, 2]\n", "hello\n", "", "42\n"])
def test_file_that_is_not_a_mapping_gives_one_error(tmp_path: Path, text: str) -> None:
    path = tmp_path / "x.case.yaml"
    path.write_text(text, encoding="utf-8")
    result = loads("validate", path)
    assert result.exit_code == 2, result.output
    assert result.output.splitlines() == [
        f"{path}:1:1: error: expected a mapping of keys at the top of the file"
    ]


def test_no_message_quotes_more_than_80_characters_of_input(crank, tmp_path: Path) -> None:
    long_key, long_unit = "k" * 300, "1 " + "u" * 300
    case = crank(
        mech=("crank: {mass: 1.0,", f'crank: {{mass: "{long_unit}",'),
        case=("analysis:", f"{long_key}: 1\nanalysis:"),
    )
    result = loads("validate", case)
    assert result.exit_code == 2, result.output
    for line in result.output.splitlines():
        for run in re.findall(r"[ku]{20,}", line):
            assert len(run) <= 80, line
    assert any("kkk..." in line for line in result.output.splitlines()), result.output
