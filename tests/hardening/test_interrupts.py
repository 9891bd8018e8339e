"""Issue 15 item 7: SIGINT and SIGTERM stop `loads run` cleanly.

The runs finished before stay valid, a run stopped while solving is written with status
`interrupted` and its rows so far, no further run starts, the command says so and exits
130 (SIGINT) or 143 (SIGTERM), and no worker process outlives it. The signal is sent once
the process (or each worker) has spent enough CPU time to be inside its solve: CPU time,
not wall time, so that a loaded machine only makes the test slower.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import mechlib as ml
from loadcases.foundation.interrupts import exit_code
from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH
from tests.mechlib._models import hinged_bar

PENDULUM = """\
name: pend
gravity: [0, -9.81, 0]
parameters: {swing: 1.0}
bodies:
  arm: {mass: 1.0, cm: [0.5, 0, 0], inertia: [0.001, 0.08, 0.08]}
joints:
  pivot: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
forces:  # a force element keeps the solve in Python steps (minutes of them over 200 s)
  return: {type: torsion_spring, joint: pivot, stiffness: 0.5 N*m/rad}
"""

SLOW_CASE = """\
case: NAME
mechanism: pend.mech.yaml
initial:
  pivot: {value: "swing"}
analysis: {type: dynamic, end: 200, step: 0.01}
requests:
  pivot_force: {joint: pivot, quantity: force, frame: ground}
"""  # minutes of solving: it is always interrupted

SOLVING_CPU = 4.0  # s of CPU: past loading, building and compiling, inside the solve
LOADS = [sys.executable, "-c", "from cli.app import main; main()"]


def _write(folder: Path) -> None:
    (folder / "crank.mech.yaml").write_text(CRANK_MECH)
    (folder / "crank.case.yaml").write_text(CRANK_CASE)
    (folder / "pend.mech.yaml").write_text(PENDULUM)
    for name in ("slow-a", "slow-b"):
        (folder / f"{name}.case.yaml").write_text(SLOW_CASE.replace("NAME", name))


def _start(folder: Path, *args: str) -> subprocess.Popen:
    """`loads ARGS` in its own session (a process group, as a terminal makes)."""
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])}
    return subprocess.Popen(
        [*LOADS, *args],
        cwd=folder,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )


def _cpu_seconds(pid: int) -> float:
    """User + system CPU time of a live process (0 once it is gone)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (FileNotFoundError, ProcessLookupError):
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _children(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(c) for c in path.read_text().split()] if path.exists() else []


def _wait_for(condition, process: subprocess.Popen, timeout: float = 240.0) -> None:
    """Poll `condition()` until true; fail if the process ends or the time runs out."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "timed out waiting"
        time.sleep(0.1)


def _solving_workers(process: subprocess.Popen) -> list[int]:
    """The two pool workers of `process`, once both are inside their solves."""
    _wait_for(lambda: len(_children(process.pid)) == 2, process)
    workers = _children(process.pid)
    _wait_for(lambda: all(_cpu_seconds(w) > SOLVING_CPU for w in workers), process)
    return workers


def _summary(folder: Path, name: str) -> dict:
    return json.loads((folder / f"{name}.summary.json").read_text())


def _assert_interrupted(folder: Path, name: str, signal_name: str) -> None:
    """Status interrupted, the signal and the time named, the rows so far in the CSV."""
    summary = _summary(folder, name)
    assert summary["status"] == "interrupted"
    assert f"interrupted by {signal_name} at t = " in summary["message"]
    table = np.loadtxt(folder / f"{name}.csv", delimiter=",", skiprows=1, ndmin=2)
    assert len(table) >= 2 and np.all(np.isfinite(table))
    assert np.allclose(np.diff(table[:, 0]), 0.01)  # whole rows at the output times
    assert table[-1, 0] < 200.0
    assert f"t = {table[-1, 0]:.6g} s" in summary["message"]


def _gone(pids: list[int], timeout: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout
    while any(Path(f"/proc/{p}").exists() for p in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    return not any(Path(f"/proc/{p}").exists() for p in pids)


def test_sigint_of_a_serial_set_keeps_the_finished_run_and_saves_the_one_under_way(
    tmp_path: Path,
) -> None:
    _write(tmp_path)
    (tmp_path / "mix.set.yaml").write_text(
        "set: mix\ncases: [crank.case.yaml, slow-a.case.yaml, slow-b.case.yaml]\n"
    )
    process = _start(tmp_path, "run", "mix.set.yaml", "-j", "1", "-o", "out")
    out = tmp_path / "out" / "mix"
    _wait_for(lambda: (out / "crank-turn.summary.json").exists(), process)
    cpu = _cpu_seconds(process.pid)
    _wait_for(lambda: _cpu_seconds(process.pid) > cpu + SOLVING_CPU, process)
    os.killpg(process.pid, signal.SIGINT)  # as Ctrl-C in a terminal
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == exit_code(signal.SIGINT) == 130, stderr
    assert "loads: interrupted by SIGINT" in stderr
    assert "1 of 3 runs finished, 1 stopped while solving" in stdout
    assert "1 not started; envelope and workbook not written" in stdout
    assert _summary(out, "crank-turn")["status"] == "ok"
    _assert_interrupted(out, "slow-a", "SIGINT")
    assert not (out / "slow-b.summary.json").exists()
    assert not (out / "envelope.csv").exists()


def test_sigterm_of_a_parallel_set_stops_its_workers_and_saves_their_rows(
    tmp_path: Path,
) -> None:
    _write(tmp_path)
    (tmp_path / "two.set.yaml").write_text(
        "set: two\ncases: [slow-a.case.yaml]\nsweep: {swing: [0.5, 1.0]}\n"
    )
    process = _start(tmp_path, "run", "two.set.yaml", "-j", "2", "-o", "out")
    workers = _solving_workers(process)
    process.send_signal(signal.SIGTERM)  # the parent alone: it stops its workers
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == exit_code(signal.SIGTERM) == 143, stderr
    assert "loads: interrupted by SIGTERM" in stderr
    assert "0 of 2 runs finished, 2 stopped while solving" in stdout
    for swing in ("0.5", "1"):
        _assert_interrupted(tmp_path / "out" / "two", f"slow-a[swing={swing}]", "SIGTERM")
    assert _gone(workers), "a worker outlived loads"


def test_sigint_of_case_files_run_in_parallel(tmp_path: Path) -> None:
    _write(tmp_path)
    process = _start(tmp_path, "run", "slow-a.case.yaml", "slow-b.case.yaml", "-j", "2")
    workers = _solving_workers(process)
    os.killpg(process.pid, signal.SIGINT)  # workers and parent alike, as a terminal does
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 130, stderr
    assert "slow-a: interrupted" in stdout and "slow-b: interrupted" in stdout
    for name in ("slow-a", "slow-b"):
        _assert_interrupted(tmp_path / "results", name, "SIGINT")
    assert _gone(workers), "a worker outlived loads"


def test_unreachable_scheduler_is_an_input_error_within_its_timeout(tmp_path: Path) -> None:
    from loadcases.sets.executors import SCHEDULER_TIMEOUT

    _write(tmp_path)
    (tmp_path / "one.set.yaml").write_text("set: one\ncases: [crank.case.yaml]\n")
    started = time.monotonic()
    process = _start(tmp_path, "run", "one.set.yaml", "--scheduler", "tcp://127.0.0.1:9")
    _, stderr = process.communicate(timeout=120)
    assert process.returncode == 2
    assert "cannot reach a Dask scheduler at 'tcp://127.0.0.1:9' within 10 s" in stderr
    assert time.monotonic() - started < SCHEDULER_TIMEOUT + 20.0  # start-up on a busy machine
    assert not (tmp_path / "results").exists()  # nothing solved, nothing written


def test_solve_keeps_the_rows_before_an_interrupt() -> None:
    """mechlib: a KeyboardInterrupt inside the solve (here from the progress callback at
    t = 0.3 s) gives status `interrupted` and the rows 0..0.3 s, equal to those of the
    whole run; with `throw=True` it propagates."""
    mech = hinged_bar()
    analysis = ml.Dynamic(end=1.0, step=0.1)
    requests = [ml.JointReaction("f", "hinge")]
    initial = [ml.InitialValue("hinge", 1.0)]

    def stop_at(t: float, end: float) -> None:
        if t >= 0.3 - 1e-12:
            raise KeyboardInterrupt("SIGINT")

    whole = ml.solve(mech, analysis, requests=requests, initial=initial, throw=False)
    cut = ml.solve(
        mech, analysis, requests=requests, initial=initial, throw=False, progress=stop_at
    )
    assert whole.status == "ok" and cut.status == "interrupted"
    assert cut.result is ml.Status.INTERRUPTED
    assert cut.message.startswith("dynamic analysis interrupted by SIGINT at t = 0.3 s of 1 s")
    assert np.allclose(cut.time, [0.0, 0.1, 0.2, 0.3], atol=1e-12)
    for column, values in cut.channels.items():
        assert np.array_equal(values, whole.channels[column][:4]), column
    with pytest.raises(KeyboardInterrupt):
        ml.solve(mech, analysis, requests=requests, initial=initial, progress=stop_at)


def test_interrupt_met_inside_a_compiled_kernel_is_an_interrupt() -> None:
    """A signal that lands while numba's dispatcher runs comes back as SystemError
    ("returned a result with an exception set") with the interrupt as its context (seen
    under load in the SIGTERM test above): still status `interrupted` with the rows so far;
    any other SystemError propagates."""
    mech = hinged_bar()
    analysis = ml.Dynamic(end=1.0, step=0.1)
    initial = [ml.InitialValue("hinge", 1.0)]

    def kernel_stop(t: float, end: float) -> None:
        if t >= 0.2 - 1e-12:
            try:
                raise KeyboardInterrupt("SIGTERM")
            except KeyboardInterrupt:  # as numba's dispatcher: the context only, no cause
                raise SystemError(  # noqa: B904
                    "CPUDispatcher(<function predict>) returned a result with an exception set"
                )

    cut = ml.solve(mech, analysis, initial=initial, throw=False, progress=kernel_stop)
    assert cut.result is ml.Status.INTERRUPTED
    assert cut.message.startswith("dynamic analysis interrupted by SIGTERM at t = 0.2 s of 1 s")
    assert np.allclose(cut.time, [0.0, 0.1, 0.2], atol=1e-12)

    def kernel_fault(t: float, end: float) -> None:
        raise SystemError("a fault of a compiled kernel, no signal")

    with pytest.raises(SystemError):
        ml.solve(mech, analysis, initial=initial, throw=False, progress=kernel_fault)
