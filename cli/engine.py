"""The load-case functions the commands call, passed in rather than imported by name.

`loads` uses those of `loadcases`; a test gives its own:
`CliRunner().invoke(app, ["run", ...], obj=Engine(run_file=fake))`.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import typer

__all__ = ["Engine", "engine_of"]

RunFile = Callable[..., list[Any]]         # (path, *, output_dir, xlsx, progress) -> [RunOutcome]
RunSet = Callable[..., Any]                # (path, *, output_dir, executor, ...) -> SetResult
CheckMechanism = Callable[[Path], list[str]]
CheckFile = Callable[[Path], list[Any]]    # (path) -> [Diagnostic]


@dataclass(frozen=True)
class Engine:
    """What `loads run` and `loads validate` call; a field left None is loadcases' own
    function of that name (imported when resolved: the solver stack is slow to import).
    Picklable when its functions are module-level (`--jobs` sends it to worker processes)."""

    run_file: RunFile | None = None
    run_set: RunSet | None = None
    check_mechanism_file: CheckMechanism | None = None
    check_file: CheckFile | None = None

    def resolved(self, *names: str) -> Engine:
        """This engine with loadcases' functions in the named fields left None."""
        import loadcases

        return replace(self, **{name: getattr(loadcases, name) for name in names
                                if getattr(self, name) is None})


def engine_of(ctx: typer.Context, *names: str) -> Engine:
    """The engine a test passed as the context object, else loadcases', with `names` resolved."""
    given = ctx.find_object(Engine)
    return (given if given is not None else Engine()).resolved(*names)
