"""The load-case functions the commands call, passed in rather than imported by name.

`loads` uses those of `loadcases`; a test gives its own:
`CliRunner().invoke(app, ["run", ...], obj=Engine(run_file=fake))`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import typer

__all__ = ["Engine", "engine_of"]

RunFile = Callable[..., list[Any]]  # (path, *, output_dir, xlsx, progress) -> [RunOutcome]
RunSet = Callable[..., Any]  # (path, *, output_dir, executor, ...) -> SetResult
CheckMechanism = Callable[[Path], list[str]]
CheckFile = Callable[..., list[Any]]  # (path, *, what_if) -> [Diagnostic]


# loadcases' functions, imported when first called: the solver stack is slow to import and
# `loads --help` needs none of it (module-level, so that an Engine pickles for `--jobs`).
def _run_file(path: Path, **options: Any) -> list[Any]:
    from loadcases.run import run_file

    return run_file(path, **options)


def _run_set(path: Path, **options: Any) -> Any:
    from loadcases.sets.campaign import run_set

    return run_set(path, **options)


def _check_mechanism_file(path: Path) -> list[str]:
    from loadcases.run import check_mechanism_file

    return check_mechanism_file(path)


def _check_file(path: Path, **options: Any) -> list[Any]:
    from loadcases.sets.precheck import file_problems

    return file_problems(path, **options)


@dataclass(frozen=True)
class Engine:
    """What `loads run` and `loads validate` call (loadcases' functions unless given)."""

    run_file: RunFile = _run_file
    run_set: RunSet = _run_set
    check_mechanism_file: CheckMechanism = _check_mechanism_file
    check_file: CheckFile = _check_file


def engine_of(ctx: typer.Context) -> Engine:
    """The engine a test passed as the context object, else loadcases'."""
    given = ctx.find_object(Engine)
    return given if given is not None else Engine()
