"""One writer per output folder: a lock file `FOLDER/.loads.lock` while a run writes there.

The lock file appears whole or not at all (`atomic_path(overwrite=False)`: written under a
temporary name, then hard-linked to its final name, which fails if the name is taken, like
O_CREAT|O_EXCL). It holds the holder's pid, host, boot and start time (JSON). A second writer
finds it and is refused (`FolderBusy`), unless the lock is stale: made on this host by a
process that no longer runs, or before this host's last boot, or unreadable. A stale lock is
taken over with a warning (`on_warning`). The lock is removed when the `with` block is left
in any way (normal end, exception, `KeyboardInterrupt` from SIGINT/SIGTERM), and only by the
process that made it (a forked worker leaving the block removes nothing).
"""

from __future__ import annotations

import datetime
import json
import os
import socket
import uuid
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

from loadcases.foundation.atomic import atomic_path

__all__ = ["LOCK_FILE", "FolderBusy", "holding", "stale_reason"]

LOCK_FILE = ".loads.lock"
_TAKE_OVER_TRIES = 3


class FolderBusy(RuntimeError):
    """Another live process holds the lock of `folder` (`holder`: its lock file's content)."""

    def __init__(self, folder: Path, holder: dict[str, object]) -> None:
        self.folder = folder
        self.holder = holder
        pid = holder.get("pid", "?")
        host = holder.get("host")
        where = "" if host in (None, socket.gethostname()) else f" on {host}"
        started = holder.get("started", "?")
        super().__init__(
            f"another loads run (pid {pid}{where}, started {started}) is writing {folder}; "
            "wait for it or choose another -o"
        )


def _boot_id() -> str | None:
    """This boot of the host (Linux), None where it cannot be told."""
    try:
        return Path("/proc/sys/kernel/random/boot_id").read_text(encoding="ascii").strip()
    except OSError:
        return None


def _alive(pid: int) -> bool:
    """Whether process `pid` exists on this host (one of another user counts as alive)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _read(lock: Path) -> dict[str, object] | None:
    """The lock file's content; {} when unreadable; None when there is no lock file."""
    try:
        text = lock.read_text(encoding="utf-8")
    except FileNotFoundError:
        return None
    except OSError:
        return {}
    try:
        content = json.loads(text)
    except ValueError:
        return {}
    return content if isinstance(content, dict) else {}


def stale_reason(holder: dict[str, object]) -> str | None:
    """Why a lock with this content is stale (None: its holder may still be writing)."""
    pid = holder.get("pid")
    if not isinstance(pid, int) or not holder.get("host"):
        return "its lock file is unreadable"
    if holder["host"] != socket.gethostname():
        return None  # another host's process: cannot be told from here
    boot = _boot_id()
    if boot is not None and holder.get("boot") not in (None, boot):
        return f"pid {pid} ran before this host's last start"
    if not _alive(pid):
        return f"pid {pid} no longer runs"
    return None


def _create(lock: Path, content: dict[str, object]) -> bool:
    """Make the lock file with `content`; False if one exists already."""
    try:
        with atomic_path(lock, overwrite=False) as tmp:
            tmp.write_text(json.dumps(content), encoding="utf-8")
    except FileExistsError:
        return False
    return True


def _remove_stale(lock: Path, holder: dict[str, object]) -> bool:
    """Remove the stale lock file whose content is `holder`: moved aside first under a
    name of this process, then removed if it is still the one judged stale (another writer
    may have taken it over meanwhile: then it is put back). False if it was put back."""
    aside = lock.with_name(f"{lock.name}.{os.getpid()}.{uuid.uuid4().hex}.stale")
    try:
        os.rename(lock, aside)
    except FileNotFoundError:
        return True  # gone already: try to create it
    if _read(aside) == holder:
        aside.unlink(missing_ok=True)
        return True
    with suppress(FileExistsError):
        os.link(aside, lock)  # a live lock taken in between: back under its name
    aside.unlink(missing_ok=True)
    return False


@contextmanager
def holding(folder: Path, on_warning: Callable[[str], None] | None = None) -> Iterator[Path]:
    """Within: this process alone writes into `folder` (created); yields the lock file.

    FolderBusy if another live process holds it; a stale lock is taken over and
    `on_warning` told why.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    lock = folder / LOCK_FILE
    mine: dict[str, object] = {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "boot": _boot_id(),
        "started": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
    }
    for _ in range(_TAKE_OVER_TRIES):
        if _create(lock, mine):
            break
        holder = _read(lock)
        if holder is None:
            continue  # released meanwhile
        reason = stale_reason(holder)
        if reason is None:
            raise FolderBusy(folder, holder)
        if _remove_stale(lock, holder) and on_warning is not None:
            on_warning(f"took over the stale lock of {folder} ({reason})")
    else:
        raise FolderBusy(folder, _read(lock) or {})
    try:
        yield lock
    finally:
        if os.getpid() == mine["pid"] and _read(lock) == mine:
            lock.unlink(missing_ok=True)
