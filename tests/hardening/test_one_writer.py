"""Issue 39 item 8: one writer per output folder.

While a set runs, `DIR/SET/.loads.lock` names its process (pid, host, boot, start time). A
second `loads run` into the same folder is refused at once (exit 1, the holder's pid and the
folder named) and touches nothing; a lock whose process is gone is taken over with a warning;
the lock is removed on every way out (normal end, failed runs, an error, an interrupt, with
or without a worker pool). The holders here are child processes that sleep (alive) or have
ended (stale): no timing races.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cli.app import app
from tests.loadcases.set_fixtures import write_inputs

runner = CliRunner()
LOCK = ".loads.lock"  # literal: the refusal test also runs (and fails) without the lock module


def _boot() -> str | None:
    try:
        return Path("/proc/sys/kernel/random/boot_id").read_text(encoding="ascii").strip()
    except OSError:
        return None


def _lock(folder: Path, pid: int, **fields: object) -> Path:
    """A lock file of process `pid` in `folder`, as `loads run` writes it."""
    folder.mkdir(parents=True, exist_ok=True)
    content = {
        "pid": pid,
        "host": socket.gethostname(),
        "boot": _boot(),
        "started": "2025-01-01T12:00:00+00:00",
        **fields,
    }
    lock = folder / LOCK
    lock.write_text(json.dumps(content), encoding="utf-8")
    return lock


@pytest.fixture()
def sleeper() -> Iterator[subprocess.Popen]:
    """A live process: the holder of a lock that is not stale."""
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(300)"])
    try:
        yield child
    finally:
        child.kill()
        child.wait()


def _ended_pid() -> int:
    """The pid of a process that has ended (and been reaped): a stale holder."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def _run(folder: Path, out: Path, *more: str) -> object:
    return runner.invoke(
        app, ["run", str(folder / "crank.set.yaml"), "-o", str(out), "--jobs", "1", *more]
    )


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def test_a_live_holder_refuses_a_second_run_which_touches_nothing(
    tmp_path: Path, sleeper: subprocess.Popen
) -> None:
    folder = write_inputs(tmp_path)
    out = tmp_path / "res"
    assert _run(folder, out).exit_code == 0  # the first version's files
    set_dir = out / "crank-set"
    lock = _lock(set_dir, sleeper.pid)
    before = _files(set_dir)
    text = (folder / "crank.set.yaml").read_text()  # a second version of the set
    (folder / "crank.set.yaml").write_text(text.replace("[1.0, 2.0, 3.0]", "[1.0, 2.5]"))
    second = _run(folder, out, "--force")
    assert second.exit_code == 1, second.output
    assert (
        f"loads: error: another loads run (pid {sleeper.pid}, started "
        f"2025-01-01T12:00:00+00:00) is writing {set_dir}; wait for it or choose another -o"
    ) in second.output
    assert _files(set_dir) == before  # the lock file too: still the first run's
    assert lock.is_file()


def test_a_stale_lock_is_taken_over_with_a_warning_and_removed(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    out = tmp_path / "res"
    pid = _ended_pid()
    _lock(out / "crank-set", pid)
    result = _run(folder, out)
    assert result.exit_code == 0, result.output
    assert f"loads: warning: took over the stale lock of {out / 'crank-set'} " in result.output
    assert f"(pid {pid} no longer runs)" in result.output
    assert "crank-set: 6 runs, 0 failed, 0 reused" in result.output
    assert not (out / "crank-set" / LOCK).exists()


@pytest.mark.skipif(_boot() is None, reason="no boot id on this host")
def test_a_lock_from_before_the_last_boot_is_stale_even_if_its_pid_runs(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    out = tmp_path / "res"
    _lock(out / "crank-set", os.getpid(), boot="another-boot")
    result = _run(folder, out)
    assert result.exit_code == 0, result.output
    assert "ran before this host's last start" in result.output
    assert not (out / "crank-set" / LOCK).exists()


def test_an_unreadable_lock_is_stale(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    out = tmp_path / "res"
    (out / "crank-set").mkdir(parents=True)
    (out / "crank-set" / LOCK).write_text("{not json", encoding="utf-8")
    result = _run(folder, out)
    assert result.exit_code == 0 and "its lock file is unreadable" in result.output
    assert not (out / "crank-set" / LOCK).exists()


def test_the_python_api_refuses_while_this_process_holds_the_folder(tmp_path: Path) -> None:
    from loadcases.foundation.folder_lock import FolderBusy, holding
    from loadcases.sets.campaign import run_set

    folder = write_inputs(tmp_path)
    set_dir = tmp_path / "res" / "crank-set"
    with holding(set_dir) as lock:
        held = lock.read_text()
        with pytest.raises(FolderBusy, match=f"pid {os.getpid()}, started"):
            run_set(folder / "crank.set.yaml", output_dir=tmp_path / "res")
        assert lock.read_text() == held
        assert [p.name for p in set_dir.iterdir()] == [LOCK]
    assert not lock.exists()


def test_the_lock_is_gone_after_failed_runs_and_after_an_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder = write_inputs(tmp_path)
    out = tmp_path / "res"
    failed = runner.invoke(app, ["run", str(folder / "slider.set.yaml"), "-o", str(out), "-j", "1"])
    assert failed.exit_code == 1, failed.output
    assert (out / "slider-set" / "envelope.csv").is_file()
    assert not (out / "slider-set" / LOCK).exists()

    from loadcases.sets import campaign

    def broken(*args: object, **kwargs: object) -> object:
        raise RuntimeError("a bug in the report")

    monkeypatch.setattr(campaign, "size_runs", broken)
    with pytest.raises(RuntimeError, match="a bug in the report"):
        campaign.run_set(folder / "crank.set.yaml", output_dir=out)
    assert (out / "crank-set" / "crank-turn[speed=1,load=10N].csv").is_file()
    assert not (out / "crank-set" / LOCK).exists()


@pytest.mark.parametrize("jobs", [1, 2])
def test_the_lock_is_gone_after_an_interrupt(tmp_path: Path, jobs: int) -> None:
    from loadcases.foundation.interrupts import Interrupted
    from loadcases.sets.campaign import run_set
    from loadcases.sets.executors import PoolExecutor, SerialExecutor

    folder = write_inputs(tmp_path)
    seen: list[bool] = []

    def interrupt(record: object, done: int, total: int) -> None:
        seen.append((tmp_path / "res" / "crank-set" / LOCK).is_file())  # held while solving
        if done == 2:
            raise Interrupted(signal.SIGINT)

    executor = SerialExecutor() if jobs == 1 else PoolExecutor(jobs)
    result = run_set(
        folder / "crank.set.yaml", output_dir=tmp_path / "res", executor=executor,
        on_record=interrupt,
    )  # fmt: skip
    assert result.interrupted and seen and all(seen)
    assert not (result.directory / "envelope.csv").exists()
    assert not (result.directory / LOCK).exists()
