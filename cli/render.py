"""Text the `loads` command prints: diagnostics, run status lines, a progress bar, errors."""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable
from pathlib import Path
from typing import TextIO

import typer

from loadcases.foundation.clip import visible
from loadcases.foundation.diagnostics import Diagnostic, sort_diagnostics

__all__ = [
    "ProgressBar",
    "TerminalLine",
    "error_line",
    "fail",
    "print_diagnostics",
    "status_line",
]

PROGRESS_WIDTH = 30  # characters of the bar itself
PROGRESS_INTERVAL = 0.1  # s between redraws: keeps a fast solver from waiting on the terminal


def error_line(message: str) -> str:
    """One-line error text, as every `loads` error starts (hidden characters of the input
    it quotes shown as escapes: `\\n`, `\\u202e`)."""
    return f"loads: error: {visible(message)}"


def fail(message: str, code: int = 2) -> typer.Exit:
    """Print a one-line error on stderr and return the `typer.Exit` to raise."""
    typer.echo(error_line(message), err=True)
    return typer.Exit(code)


def invalid_input(diagnostics: Iterable[Diagnostic]) -> typer.Exit:
    """Print the problems of the input (a saved file read back, too) on stderr; return the
    `typer.Exit` (status 2) to raise."""
    print_diagnostics(diagnostics, err=True)
    return typer.Exit(2)


def not_written(path: Path, error: OSError) -> typer.Exit:
    """Say that `path` could not be written (disk full, permissions) and is missing; return
    the `typer.Exit` (status 1) to raise."""
    typer.echo(
        error_line(f"{path}: not written ({error.strerror or error}); missing: {path}"), err=True
    )
    return typer.Exit(1)


def print_diagnostics(diagnostics: Iterable[Diagnostic], *, err: bool) -> None:
    """Print diagnostics gcc style, sorted by file, line and column, duplicates once."""
    for diagnostic in sort_diagnostics(list(dict.fromkeys(diagnostics))):
        typer.echo(diagnostic.format(), err=err)


def status_line(name: str, status: str, steps: int, cpu_seconds: float, where: Path) -> str:
    """`NAME: ok, 1001 steps, cpu 0.52 s -> results/NAME.csv`."""
    return f"{name}: {status}, {steps} steps, cpu {cpu_seconds:.3g} s -> {where}"


class TerminalLine:
    """One line on a terminal, redrawn in place: at most every PROGRESS_INTERVAL seconds
    (the final state always), erased by `close` before the lines that follow."""

    def __init__(self, stream: TextIO | None = None) -> None:
        self._stream = stream if stream is not None else sys.stderr
        self._last_draw = float("-inf")
        self._width_drawn = 0

    def due(self, final: bool) -> bool:
        """Whether to redraw now (keeps a fast solver from waiting on the terminal)."""
        now = time.monotonic()
        if now - self._last_draw < PROGRESS_INTERVAL and not final:
            return False
        self._last_draw = now
        return True

    def draw(self, text: str) -> None:
        self._stream.write("\r" + text.ljust(self._width_drawn))
        self._stream.flush()
        self._width_drawn = max(self._width_drawn, len(text))

    def close(self) -> None:
        """Erase the line so that the status lines that follow start on a clean line."""
        if self._width_drawn:
            self._stream.write("\r" + " " * self._width_drawn + "\r")
            self._stream.flush()
            self._width_drawn = 0


class ProgressBar(TerminalLine):
    """A one-line progress bar on a terminal, fed by `run_file(progress=...)` as (t, t_end):
    the run, then each further solve of its accuracy estimate as its stage (`staged`)."""

    def __init__(self, label: str, stream: TextIO | None = None) -> None:
        super().__init__(stream)
        self._label = label
        self._stage = ""

    def staged(self, stage: str) -> ProgressBar:
        """This bar, drawing the solves that follow as `stage` (the accuracy companion, a
        tighter run: loadcases.run.staged) after the file's name, the first at once."""
        self._stage = stage
        self._last_draw = float("-inf")
        return self

    def __call__(self, t_current: float, t_end: float) -> None:
        if not self.due(final=t_current >= t_end):
            return
        fraction = min(max(t_current / t_end, 0.0), 1.0) if t_end > 0 else 1.0
        filled = round(fraction * PROGRESS_WIDTH)
        bar = "#" * filled + "." * (PROGRESS_WIDTH - filled)
        label = f"{self._label} ({self._stage})" if self._stage else self._label
        self.draw(f"{label} [{bar}] {fraction:4.0%}  t = {t_current:.4g} / {t_end:.4g} s")
