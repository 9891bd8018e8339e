"""`loads draw`: one run of a set (`--run`), the 3-D page (`--html`, `--forces`) and the
usage errors around them (exit 2, each with a message saying what to do)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cli.app import app

runner = CliRunner()
LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library"
PRESS_SET = str(LIBRARY / "examples" / "press_sizing.set.yaml")
FOURBAR = str(LIBRARY / "verification" / "fourbar_quasistatic.case.yaml")
MODES = str(LIBRARY / "verification" / "solar_array" / "rotor_modes.case.yaml")
RUN = "press-stroke[crank_speed=360deg_per_s,press_force=1500N]"


def draw(*args: str):
    return runner.invoke(app, ["draw", *args])


def test_a_set_without_run_lists_its_runs() -> None:
    result = draw(PRESS_SET)
    assert result.exit_code == 2
    assert "is a set: choose a run with --run; its runs are:" in result.output
    assert f"  {RUN}\n" in result.output and result.output.count("\n  press-") == 8


def test_a_wrong_run_lists_the_runs_and_the_closest(tmp_path: Path) -> None:
    result = draw(PRESS_SET, "--run", "press-stroke[crank_speed=360deg_per_s]", "-o", str(tmp_path))
    assert result.exit_code == 2
    assert "has no run 'press-stroke[crank_speed=360deg_per_s]'; its runs are:" in result.output
    assert "hint: did you mean 'press-stroke[crank_speed=360deg_per_s,press_force=" in result.output
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((FOURBAR, "--run", "x"), "is not a set file; --run picks a run of a set"),
        ((FOURBAR, "--forces", "pin_b"), "--forces draws arrows in the HTML page: add --html"),
        ((FOURBAR, "--html", "--at", "0.1"), "the HTML page has a time slider instead"),
        ((FOURBAR, "--html", "--forces", "pin_q"), "no joint 'pin_q' with a point (did you mean"),
        ((MODES, "--html", "--forces", "hinge"), "a modes analysis computes no reaction forces"),
    ],
)
def test_usage_errors_exit_2(args: tuple[str, ...], message: str, tmp_path: Path) -> None:
    result = draw(*args, "-o", str(tmp_path))
    assert result.exit_code == 2, result.output
    assert message in result.output
    assert not any(tmp_path.iterdir())


def test_html_without_plotly_says_how_to_install_it(monkeypatch, tmp_path: Path) -> None:
    monkeypatch.setitem(sys.modules, "plotly", None)  # as if it were not installed
    result = draw(FOURBAR, "--html", "-o", str(tmp_path))
    assert result.exit_code == 2
    assert "needs plotly" in result.output and "pip install 'loads[html]'" in result.output
    assert not any(tmp_path.iterdir())


def test_html_of_one_run_of_a_set(tmp_path: Path) -> None:
    pytest.importorskip("plotly", reason="the HTML page needs the optional extra loads[html]")
    result = draw(PRESS_SET, "--run", RUN, "--html", "--forces", "pivot,big", "-o", str(tmp_path))
    assert result.exit_code == 0, result.output
    page = tmp_path / "press-stroke_crank_speed=360deg_per_s_press_force=1500N_.html"
    assert result.output == f"wrote {page}\n"
    text = page.read_text(encoding="utf-8")
    assert f"<title>{RUN}</title>" in text
    assert "pivot" in text and "big" in text


def test_help_shows_the_install_command_and_a_run_name() -> None:
    """Square brackets survive typer's rich markup in the help."""
    result = runner.invoke(app, ["draw", "--help"], terminal_width=200)
    assert result.exit_code == 0
    text = " ".join(result.output.replace("│", " ").split())
    assert "pip install 'loads[html]'" in text and "opening[angle=1.2]" in text


def test_a_static_case_is_drawn_once(tmp_path: Path) -> None:
    """A static run has one row: one picture and one `wrote` line, not the first, middle
    and last row of the same instant three times."""
    result = draw(str(LIBRARY / "examples" / "press_hold.case.yaml"), "-o", str(tmp_path))
    assert result.exit_code == 0, result.output
    assert result.output.count("wrote ") == 1, result.output
    assert len(list(tmp_path.glob("*.png"))) == 1
