"""Issue 39 item 3: text that reaches files is clean. Names and values holding control,
bidirectional or zero-width characters are refused at their key; YAML 1.1 readings that
differ from ours (`1:30`, `010`, plain `on`) are refused with a hint to quote; `--set`
values are read as files are; messages written to the terminal, workbooks, HTML pages,
CSV files and plots show hidden characters as escapes and never break the file."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.foundation.clip import hidden_character
from tests.hardening.conftest import has_line, loads

KEY_HINT = (
    "hint: retype the key: keys and names hold no control, bidirectional or zero-width characters"
)
VALUE_HINT = (
    "hint: retype the value: text holds no control, bidirectional or zero-width characters "
    "(line breaks and tabs aside)"
)
NOT_SHOWN = "a character not shown as written"


def _refused(result, *lines: str) -> None:
    assert result.exit_code == 2, result.output
    assert "internal error" not in result.output and "Traceback" not in result.output
    for line in lines:
        assert has_line(result.output, line), (line, result.output)
    # whatever the input held, what is printed shows it as escapes
    assert not [line for line in result.output.splitlines() if hidden_character(line)]


@pytest.mark.parametrize(
    ("change", "where", "shown", "holds"),
    [
        (
            {"mech": ("  crank: {mass", '  "cr\\u202eank": {mass')},
            "crank.mech.yaml:5:3",
            "bodies.cr\\u202eank",
            "a right-to-left override (U+202E)",
        ),
        (
            {"mech": ("  pivot: {type", '  "piv\\aot": {type')},
            "crank.mech.yaml:9:3",
            "joints.piv\\x07ot",
            "a control character (U+0007)",
        ),
        (
            {"mech": ("{speed: 1.0", '{"sp\\u2066eed": 1.0')},
            "crank.mech.yaml:3:14",
            "parameters.sp\\u2066eed",
            "a left-to-right isolate (U+2066)",
        ),
        (
            {"mech": ("  tip: {", '  "t\\u200bip": {')},
            "crank.mech.yaml:7:3",
            "points.t\\u200bip",
            "a zero width space (U+200B)",
        ),
        (
            {"mech": ("  push: {", '  "pu\\u202dsh": {')},
            "crank.mech.yaml:11:3",
            "forces.pu\\u202dsh",
            "a left-to-right override (U+202D)",
        ),
        (
            {"case": ("  pivot_force: {", '  "pivot\\tforce": {')},
            "crank.case.yaml:7:3",
            "requests.pivot\\tforce",
            "a tab (U+0009)",
        ),
        (
            {"case": ("  drive: {", '  "dri\\nve": {')},
            "crank.case.yaml:4:3",
            "motions.dri\\nve",
            "a line break (U+000A)",
        ),
    ],
)
def test_a_name_holding_a_hidden_character_is_refused_at_its_key(
    crank, change, where, shown, holds
) -> None:
    result = loads("validate", crank(**change))
    _refused(
        result,
        f"{where}: error: {shown}: the key holds {holds}, {NOT_SHOWN}",
        f"{where}: {KEY_HINT}",
    )


@pytest.mark.parametrize(
    ("change", "where", "key", "holds"),
    [
        (("case: crank-turn", 'case: "crank\\u202e-turn"'), "1:1", "case", "a right-to-left "
         "override (U+202E)"),
        (("case: crank-turn", 'case: "crank\\0turn"'), "1:1", "case", "a control character "
         "(U+0000)"),
        (("joint: pivot, value", 'joint: "piv\\aot", value'), "4:11", "motions.drive.joint",
         "a control character (U+0007)"),
        (("joint: pivot, value", 'joint: "piv\\u2067ot", value'), "4:11", "motions.drive.joint",
         "a right-to-left isolate (U+2067)"),
    ],
)  # fmt: skip
def test_a_value_holding_a_hidden_character_is_refused_at_its_key(
    crank, change, where, key, holds
) -> None:
    result = loads("validate", crank(case=change))
    _refused(
        result,
        f"crank.case.yaml:{where}: error: {key}: the value holds {holds}, {NOT_SHOWN}",
        f"crank.case.yaml:{where}: {VALUE_HINT}",
    )


def test_a_line_break_in_a_value_is_shown_as_an_escape(crank) -> None:
    """Line breaks may be in a value (an expression over lines); one in a name is refused
    as the name's own problem, and the message shows it as `\\n`."""
    result = loads("validate", crank(case=("joint: pivot, value", 'joint: "piv\\not", value')))
    _refused(result, "crank.case.yaml:4:11: error: motions.drive.joint: unknown joint 'piv\\not'")
    result = loads("validate", crank(case=("case: crank-turn", 'case: "crank\\nturn"')))
    _refused(
        result,
        "crank.case.yaml:1:1: error: case: cannot be a result file name: a line break (U+000A)",
    )


@pytest.mark.parametrize(
    ("change", "expected", "hint"),
    [
        (
            {"mech": ("mass: 1.0", "mass: 1:30")},
            "crank.mech.yaml:5:11: error: bodies.crank.mass: YAML 1.1 reads the plain 1:30 as "
            "the number 90",
            "crank.mech.yaml:5:11: hint: quote it ('1:30') if it is text, or write the number "
            "you mean",
        ),
        (
            {"mech": ("name: crank", "name: 1:30:00")},
            "crank.mech.yaml:1:1: error: name: YAML 1.1 reads the plain 1:30:00 as the number 5400",
            "crank.mech.yaml:1:1: hint: quote it ('1:30:00') if it is text, or write the number "
            "you mean",
        ),
        (
            {"mech": ("mass: 1.0", "mass: 010")},
            "crank.mech.yaml:5:11: error: bodies.crank.mass: YAML 1.1 reads the plain 010 as "
            "the number 8",
            "crank.mech.yaml:5:11: hint: quote it ('010') if it is text, or write the number "
            "you mean",
        ),
        (
            {"case": ("end: 0.5", "end: 1_000")},
            "crank.case.yaml:5:29: error: analysis.end: YAML 1.1 reads the plain 1_000 as the "
            "number 1000",
            "crank.case.yaml:5:29: hint: quote it ('1_000') if it is text, or write the number "
            "you mean",
        ),
        (
            {"case": ("  pivot_force:", "  1:30:")},
            "crank.case.yaml:7:3: error: requests.1:30: YAML 1.1 reads the plain key 1:30 as "
            "the number 90",
            "crank.case.yaml:7:3: hint: quote it ('1:30')",
        ),
        (
            {"mech": ("{speed: 1.0", "{on: 1.0")},
            "crank.mech.yaml:3:14: error: parameters.on: YAML 1.1 reads the plain key on as "
            "the boolean true",
            "crank.mech.yaml:3:14: hint: quote it ('on')",
        ),
        (
            {"case": ("case: crank-turn", "case: yes")},
            "crank.case.yaml:1:1: error: case: YAML 1.1 reads the plain yes as the boolean true",
            "crank.case.yaml:1:1: hint: quote it ('yes') if it is text",
        ),
        (
            {"case": ("joint: pivot", "joint: Off")},
            "crank.case.yaml:4:11: error: motions.drive.joint: YAML 1.1 reads the plain Off as "
            "the boolean false",
            "crank.case.yaml:4:11: hint: quote it ('Off') if it is text",
        ),
        (
            {"mech": ("mass: 1.0", "mass: on")},
            "crank.mech.yaml:5:11: error: bodies.crank.mass: cannot read 'on': expected a "
            "number with a unit, like '110 mm'",
            "crank.mech.yaml:5:11: hint: YAML 1.1 reads the plain on as the boolean true: "
            "write the value you mean",
        ),
    ],
)
def test_a_plain_scalar_yaml_1_1_reads_otherwise_is_refused_with_a_hint(
    crank, change, expected, hint
) -> None:
    _refused(loads("validate", crank(**change)), expected, hint)


def test_quoted_it_is_text_and_a_plain_boolean_word_is_a_switch(crank) -> None:
    """Quoted, `'1:30'` and `'yes'` are text; plain `yes`/`off` where a key takes true or
    false are read as YAML 1.1 reads them; `0x10` and `1e3` mean the same to both."""
    case = crank(
        case=("case: crank-turn", "case: 'yes'"),
        mech=("frame: ground}", "frame: ground, active: yes}"),
    )
    assert loads("validate", case).exit_code == 0
    case = crank(mech=("frame: ground}", "frame: ground, active: Off}"))
    assert loads("validate", case).exit_code == 0
    result = loads("validate", crank(mech=("mass: 1.0", "mass: '1:30'")))
    _refused(
        result,
        "crank.mech.yaml:5:11: error: bodies.crank.mass: cannot read '1:30': ':' is not "
        "part of a quantity",
    )
    for mass in ("0x10", "1e3", "12", "+1.5"):
        assert loads("validate", crank(mech=("mass: 1.0", f"mass: {mass}"))).exit_code == 0


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (
            "١٢",
            "--set speed: cannot read '١٢': an arabic-indic digit one (U+0661): write numbers "
            "with the digits 0-9",
        ),
        (
            "12\u00a0rad/s",
            "--set speed: cannot read '12\u00a0rad/s': a no-break space (U+00A0): write a plain "
            "space or nothing",
        ),
        (
            "12\nrad/s",
            "--set speed: cannot read '12\\nrad/s': a line break (U+000A): write a plain space "
            "or nothing",
        ),
        (
            "12\n",
            "--set speed: cannot read '12\\n': a line break (U+000A): write a plain space or "
            "nothing",
        ),
        ("1_000", "--set speed: cannot read '1_000': '1_000' is not a decimal number"),
        ("2(50 rad/s", "--set speed: cannot read '2(50 rad/s': unbalanced parentheses"),
        ("10**10**10 rad/s", "--set speed: cannot read '10**10**10 rad/s': a number out of range"),
        (
            "1 " + "m" * 200,
            f"--set speed: cannot read '1 {'m' * 75}...': longer than 100 characters",
        ),
    ],
)
def test_a_set_value_is_read_as_files_are_and_quoted_once(crank, value, message) -> None:
    case = crank()
    result = loads("run", case, "-o", case.parent / "out", "--set", f"speed={value}")
    assert result.exit_code == 2, result.output
    assert f"loads: error: {message}" in result.output.splitlines(), result.output
    assert not (case.parent / "out").exists()


def test_a_malformed_set_option_is_quoted_clipped(crank) -> None:
    result = loads("run", crank(), "--set", "x" * 300)
    assert result.exit_code == 2, result.output
    assert (
        f"loads: error: --set '{'x' * 77}...': expected NAME=VALUE, e.g. --set length=1.5 or "
        "--set 'length=1500 mm' (a parameter name, '=', a number with an optional unit)"
    ) in result.output.splitlines(), result.output


def test_a_name_with_a_dollar_sign_is_plotted_as_written(crank, tmp_path: Path) -> None:
    """matplotlib reads `$...$` as math text and fails on `$^$`: the set's plots show it."""
    crank(case=("case: crank-turn", "case: 'crank$^$'"))
    (tmp_path / "s.set.yaml").write_text(
        "set: s\ncases: [crank.case.yaml]\nsweep: {speed: [1.0, 2.0]}\n", encoding="utf-8"
    )
    result = loads("run", tmp_path / "s.set.yaml", "-o", tmp_path / "out", "--jobs", "1")
    assert result.exit_code == 0, result.output
    assert list((tmp_path / "out" / "s").glob("envelope-*.png"))


def test_a_failed_runs_message_is_printed_as_escapes(crank) -> None:
    """A solver's message or warning may quote anything: the status lines show hidden
    characters as escapes."""
    from typer.testing import CliRunner

    from cli.app import app
    from cli.engine import Engine
    from tests.hardening.test_workbook_text import HIDDEN, SHOWN, _outcome

    def run_file(path, **options):
        outcome = _outcome("crank-turn", HIDDEN)
        outcome.solution.status = "failed"
        outcome.solution.warnings = [HIDDEN]
        return [outcome]

    case = crank()
    result = CliRunner().invoke(
        app, ["run", str(case), "-o", str(case.parent / "out")], obj=Engine(run_file=run_file)
    )
    assert result.exit_code == 1, result.output
    assert f"  {SHOWN}" in result.output.splitlines()
    assert f"  warning: {SHOWN}" in result.output.splitlines()
    assert not [line for line in result.output.splitlines() if hidden_character(line)]
