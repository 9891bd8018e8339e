"""`loads --help` and `loads COMMAND --help` (issue 16 item 9): domain names instead of
Python types, and the schema's help says how to point an editor at it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cli.app import app

runner = CliRunner()
COMMANDS = sorted(c.name or c.callback.__name__ for c in app.registered_commands if c.callback)
PYTHON_TYPE = re.compile(
    r"<(bool|str|int|float|path|list\[[^\]]*\]|int range)>|\b(TEXT|INTEGER|FLOAT)\b"
)


def _help(*args: str) -> str:
    result = runner.invoke(app, [*args, "--help"], terminal_width=200)
    assert result.exit_code == 0, result.output
    return result.output


@pytest.mark.parametrize("command", ["", *COMMANDS])
def test_help_shows_no_python_types(command: str) -> None:
    text = _help(*([command] if command else []))
    assert PYTHON_TYPE.search(text) is None, text


def test_every_command_is_listed_with_a_sentence() -> None:
    text = _help()
    for command in (
        "run",
        "validate",
        "envelope",
        "schema",
        "compare",
        "accuracy",
        "plot",
        "draw",
        "new",
        "tune",
    ):
        assert re.search(rf"│ {command} +[A-Z]", text), command


def test_options_are_named_by_what_they_take() -> None:
    text = _help("run")
    for shown in ("FILE", "DIR", "N", "ADDRESS", "NAME=VALUE"):
        assert re.search(rf"\b{re.escape(shown)}\b", text), shown


def test_schema_help_gives_the_editor_modeline() -> None:
    text = _help("schema")
    assert "loads schema > loads.schema.json" in text
    assert "# yaml-language-server: $schema=loads.schema.json" in text


def test_new_help_offers_blank() -> None:
    assert "blank" in _help("new")


def test_docs_name_no_files_outside_the_repository() -> None:
    """README.md and docs/*.md point only at files of the repository."""
    root = Path(__file__).resolve().parents[2]
    outside = re.compile(r"\.\./shared|/work/|\.\./\.\./|SPEC\.md|DESIGN\.md")
    for path in [root / "README.md", *sorted((root / "docs").glob("*.md"))]:
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            assert outside.search(line) is None, f"{path.name}:{number}: {line}"
