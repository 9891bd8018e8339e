"""The `loads` console script: the cyclic garbage collector paused from the first import.

Start-up imports build about 80,000 long-lived objects (typer, pydantic's schema models,
numpy); the collector's passes over them while they are built cost `loads validate` about
0.05-0.1 s of its 0.5 s (2-core VM, 2026-11-28) and free nothing. Commands that solve,
read results or write reports turn it back on as they start (`cli.app.guarded`); the
short read-only ones (`validate`, `schema`, `--help`, `--version`) end without it.

pydantic's plugins (observability hooks found through the installed packages' entry
points) are off unless the environment says otherwise (`PYDANTIC_DISABLE_PLUGINS=0`):
looking for them reads every installed package's metadata, about 15 ms of each command,
and no plugin has a part in checking a case file.
"""

from __future__ import annotations

import gc
import os


def main() -> None:
    """Entry point `loads` (pyproject's [project.scripts])."""
    gc.disable()
    os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")
    from cli.app import main as run

    run()
