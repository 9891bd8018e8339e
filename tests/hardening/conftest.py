"""Shared helpers of the hardening tests (issue 15): tiny crank inputs with one change."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any
from unittest import mock

import pytest
import typer.testing
from typer.main import get_command
from typer.testing import CliRunner

from cli.app import app
from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH

_runner = CliRunner()
# a case's inline mechanism (lines 2-12): a 1 kg mass on a slide, a 1000 N/m spring
SPRING_MASS = """\
mechanism:
  name: sm
  bodies:
    mass: {mass: 1.0, cm: [0, 0, 0], inertia: [0.01, 0.01, 0.01]}
  points:
    m_eye: {body: mass, at: [0, 0, 0]}
    anchor: {body: ground, at: [-1, 0, 0]}
  joints:
    slide: {type: prismatic, bodies: [mass, ground], at: [0, 0, 0], axis: [1, 0, 0]}
  forces:
    spring: {type: spring, points: [m_eye, anchor], stiffness: 1000, free_length: 1.0}
"""


def loads(*args: object) -> Any:
    """Run the `loads` command line; returns the click Result (exit_code, output)."""
    # typer's CliRunner builds the click command from `app` on every call (0.13 s, most of
    # a fuzz example); `loads` builds it once per process, and so do these tests
    with mock.patch.object(typer.testing, "_get_command", _command):
        return _runner.invoke(app, [str(a) for a in args])


@functools.cache
def _command(typer_app: Any) -> Any:
    """The click command of `typer_app`, built once."""
    return get_command(typer_app)


@pytest.fixture
def crank(tmp_path: Path):
    """`crank(mech=(old, new), case=(old, new))` writes crank.mech.yaml and crank.case.yaml
    with each `old` text replaced by `new` (it must occur) and returns the case path."""

    def write(
        mech: tuple[str, str] | None = None,
        case: tuple[str, str] | None = None,
        folder: Path = tmp_path,
    ) -> Path:
        texts = {"crank.mech.yaml": (CRANK_MECH, mech), "crank.case.yaml": (CRANK_CASE, case)}
        for name, (text, change) in texts.items():
            if change is not None:
                assert change[0] in text, change[0]
                text = text.replace(*change)
            (folder / name).write_text(text, encoding="utf-8")
        return folder / "crank.case.yaml"

    return write


def has_line(output: str, expected: str) -> bool:
    """Whether a line of `output` is `expected`, or ends with `/expected` (a file path
    printed in full)."""
    return any(line == expected or line.endswith("/" + expected) for line in output.splitlines())
