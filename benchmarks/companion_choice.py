"""The measurement scripts' `--companion` option: the accuracy companion an estimate is
made with (loadcases.run.companion) -- `grid` (the run's own steps two at a time, where
they are known: the engine's default) or `adaptive` (an error-controlled run of steps twice
as long), to measure one against the other."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from loadcases.run import global_error

__all__ = ["KINDS", "add_companion_option", "companion_kind", "use_companion"]

KINDS = ("grid", "adaptive")


def add_companion_option(parser: argparse.ArgumentParser) -> None:
    """`--companion grid|adaptive` on `parser` (default grid, the engine's)."""
    parser.add_argument(
        "--companion", choices=KINDS, default="grid", help="the accuracy companion to use"
    )


def use_companion(kind: str) -> None:
    """Make this process's estimates with the `kind` companion: `adaptive` turns the grid
    companion off (loadcases.run.global_error.on_grid then finds none)."""
    if kind == "adaptive":
        global_error.on_grid = _none  # type: ignore[assignment]


@contextmanager
def companion_kind(kind: str) -> Iterator[None]:
    """Estimates made with the `kind` companion within the block only (the two measured
    in one process)."""
    saved = global_error.on_grid
    use_companion(kind)
    try:
        yield
    finally:
        global_error.on_grid = saved


def _none(*_: Any) -> None:
    return None
