"""The `loads` console script: the cyclic garbage collector paused from the first import,
and the interpreter's teardown skipped once the command is over.

Start-up imports build about 80,000 long-lived objects (typer, pydantic's schema models,
numpy); the collector's passes over them while they are built cost `loads validate` about
0.05-0.1 s of its 0.5 s (2-core VM, 2026-11-28) and free nothing. Commands that solve,
read results or write reports turn it back on as they start (`cli.app.guarded`); the
short read-only ones (`validate`, `schema`, `--help`, `--version`) end without it.

pydantic's plugins (observability hooks found through the installed packages' entry
points) are off unless the environment says otherwise (`PYDANTIC_DISABLE_PLUGINS=0`):
looking for them reads every installed package's metadata, about 15 ms of each command,
and no plugin has a part in checking a case file.

When the console script itself runs `main` (its `__main__` module is pip's script file
`loads`, which calls this `main`: nothing of that process runs after it), the process
ends with `os._exit` as soon as the interpreter's exit hooks registered since `main` began
have run (the pools' and multiprocessing's, logging's): every file is closed by then
(`with`), the workers are gone, stdout and stderr are flushed here. What is skipped is the
teardown that frees every object and LLVM module the command loaded: 0.09-0.16 s of wall
after a 200-run set (2026-11-30, `loads run SET -j 2`), in which nothing is written.
Called any other way (`python -c`, another script, a test that catches the SystemExit and
goes on), the interpreter ends as usual, with every exit hook.
"""

from __future__ import annotations

import atexit
import gc
import os
import sys

__all__ = ["main"]

_CONSOLE_SCRIPTS = ("loads", "loads-script")  # the names pip gives the console script
_status: list[int] = []  # the command's exit status, once main has it


def main() -> None:
    """Entry point `loads` (pyproject's [project.scripts])."""
    gc.disable()
    os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")
    if _run_by_console_script():
        atexit.register(_leave)  # first: runs after the hooks the command registers
    from cli.app import main as run

    try:
        run()
    except SystemExit as stop:
        if stop.code is None or isinstance(stop.code, int):  # other codes: Python prints them
            _status.append(stop.code or 0)
        raise


def _run_by_console_script() -> bool:
    """Whether `__main__` is the console script pip wrote (a file named `loads`, or
    `loads-script.py` on Windows, whose `main` is this function: `from cli.entry import
    main; sys.exit(main())`), after which nothing runs."""
    script = sys.modules.get("__main__")
    file = getattr(script, "__file__", None)
    if file is None or getattr(script, "main", None) is not main:
        return False
    return os.path.basename(file).removesuffix(".py") in _CONSOLE_SCRIPTS


def _leave() -> None:
    """End the process with the command's status, without the interpreter's teardown (an
    exit hook, run after the others: module docstring). Without a status (main ended by
    another exception, or a code Python prints) the interpreter ends as usual."""
    if not _status:
        return
    for stream in (sys.stdout, sys.stderr):
        try:
            if stream is not None:
                stream.flush()
        except (OSError, ValueError):  # closed, or a reader gone: nothing more to say there
            pass
    os._exit(_status[-1])
