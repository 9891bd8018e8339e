"""numba kernels, compiled (or loaded from numba's disk cache) on their first call.

`njit(**options)` marks a kernel as numba's decorator does, without importing numba, so
that `loads --help` and `loads validate` never load it (its import and the loading of the
cached kernels cost about a second). The first call of any kernel imports numba, turns every
kernel marked so far into a numba dispatcher at once and puts the dispatchers in place of the
marks in the namespaces of the mechlib modules: compiled kernels then call compiled kernels,
and Python callers in mechlib reach the dispatcher directly. Kernels marked after that are
compiled as they are marked.

Within `interpreted()` a kernel not yet compiled runs as plain Python: the checks of
`loads validate` (a few constraint Jacobians) need no compiler. The kernels are written in the
subset of Python numba compiles, which runs unchanged in the interpreter, only slower.

numba keys a kernel's disk cache on the kernel's own source file only: a kernel calling a
kernel of another module would keep the callee's old machine code after that module changed
(a crash or a wrong number after a partial update such as `git pull`). So before the first
compilation every mechlib kernel cache is dropped when any mechlib source file with kernels
changed since the caches were written (`drop_stale_caches`).

A call from one compiled kernel to another counts a reference (numba's NRT_incref, then
NRT_decref) to each array it hands on, every member of a tuple: the packed constraints are
27 arrays, the packed force elements 19, a dense row's work arrays 39. So the kernels that
take such tuples at every Newton iterate or dense row are marked `inline="always"` (numba
inlines their IR into the caller, where the counts within one function are pruned): the
campaign's `run_steps` calls 7-9 % faster (docs/performance.md). Each caller compiles an
inlined kernel again, so only those hot helpers are.
"""

from __future__ import annotations

import hashlib
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypedDict, TypeVar

__all__ = [
    "KERNEL",
    "JitOptions",
    "Kernel",
    "compile_all",
    "compile_seconds",
    "compiled",
    "drop_stale_caches",
    "interpreted",
    "njit",
    "on_compile",
]

F = TypeVar("F", bound=Callable[..., Any])


class JitOptions(TypedDict, total=False):
    """Options of `njit(**options)`, typed so that the call matches numba's stubs (a plain
    dict[str, bool] matches none of its overloads)."""

    cache: bool
    nogil: bool
    fastmath: bool


#: The options of every mechlib kernel: cached on disk, the GIL released (a set's threads),
#: IEEE arithmetic (no fastmath: results bit for bit those of the interpreted kernel).
KERNEL: JitOptions = {"cache": True, "nogil": True, "fastmath": False}

_marked: list[Kernel] = []
_lock = threading.Lock()
_compiled = False
_interpreting = 0  # depth of `interpreted()` blocks
_hooks: list[Callable[[], None]] = []
_making = [0.0]  # CPU s this process spent making kernels (`compile_seconds`)
_making_lock = threading.Lock()


class Kernel:
    """A function marked for numba: compiled with `options` on the first call of any kernel
    (outside `interpreted()`), run as Python before that within it."""

    __slots__ = ("__name__", "dispatcher", "options", "py_func")

    def __init__(self, py_func: Callable[..., Any], options: dict[str, Any]):
        self.py_func = py_func
        self.options = options
        self.dispatcher: Callable[..., Any] | None = None
        self.__name__ = py_func.__name__

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        dispatcher = self.dispatcher
        if dispatcher is None:
            if _interpreting:
                return self.py_func(*args, **kwargs)
            compile_all()
            dispatcher = self.dispatcher
            assert dispatcher is not None, "compile_all made every marked kernel's"
        return dispatcher(*args, **kwargs)

    def __repr__(self) -> str:
        return f"<kernel {self.py_func.__module__}.{self.__name__}>"


def njit(**options: Any) -> Callable[[F], F]:
    """numba's `njit(**options)`, applied on the first call (module docstring)."""

    def mark(py_func: F) -> F:
        with _lock:
            if _compiled:
                import numba

                return numba.njit(**options)(py_func)
            kernel = Kernel(py_func, dict(options))
            _marked.append(kernel)
        return kernel  # type: ignore[return-value]

    return mark


def on_compile(hook: Callable[[], None]) -> None:
    """Run `hook` once numba is imported, before any kernel compiles (at once if it already
    is): it binds what the kernels call that only exists with numba (mechlib.linalg.lapack)."""
    with _lock:
        if not _compiled:
            _hooks.append(hook)
            return
    hook()


def compile_all() -> None:
    """Import numba, run the `on_compile` hooks and make every marked kernel a dispatcher
    (each compiles, or loads from the disk cache, on its first call with new argument
    types)."""
    global _compiled
    with _lock:
        if _compiled:
            return
        started = time.process_time()
        drop_stale_caches(Path(__file__).resolve().parents[1])
        import numba

        for hook in _hooks:
            hook()

        for kernel in _marked:
            kernel.dispatcher = numba.njit(**kernel.options)(kernel.py_func)
        for name, module in list(sys.modules.items()):
            if module is not None and (name == "mechlib" or name.startswith("mechlib.")):
                namespace = vars(module)
                for key, value in list(namespace.items()):
                    if isinstance(value, Kernel):
                        namespace[key] = value.dispatcher
        _compiled = True
        _making[0] += time.process_time() - started
        from numba.core import event  # after the hooks: their compilations counted above

        event.register("numba:compiler_lock", _timer(event.Listener))


def compile_seconds() -> float:
    """CPU s this process has spent making kernels: importing numba, then compiling each
    kernel or loading it from the disk cache on its first call with new argument types (a
    cost paid once a process, which a run's cost leaves out when it predicts a tighter
    run's: loadcases.run.global_error.Spent; a first solve of the pendulum read 0.6 s
    of CPU for 0.01 s of steps)."""
    return _making[0]


def _timer(listener: type) -> Any:
    """A numba event listener adding the CPU time of each thread within the global compiler
    lock (compiling or loading a kernel; re-entered by the kernels it calls: the outermost
    counts; its events come before the lock is taken and after it is left, so each thread
    keeps its own depth and its own CPU clock: a wait for another thread's compilation
    costs none) to `_making`."""

    class CompilerLockTimer(listener):
        def __init__(self) -> None:
            self.local = threading.local()

        def on_start(self, event: Any) -> None:
            depth = getattr(self.local, "depth", 0)
            if depth == 0:
                self.local.started = time.thread_time()
            self.local.depth = depth + 1

        def on_end(self, event: Any) -> None:
            self.local.depth -= 1
            if self.local.depth == 0:
                with _making_lock:
                    _making[0] += time.thread_time() - self.local.started

    return CompilerLockTimer()


def drop_stale_caches(root: Path) -> bool:
    """Delete numba's cache files (*.nbi, *.nbc) in the __pycache__ folders under `root`
    when the names, sizes or modification times of its .py files with kernels (`@njit`)
    differ from those recorded with them (`root`/__pycache__/kernels.stamp, then written
    anew): a change to a module without kernels costs no compilation. True when they were
    dropped. A folder that cannot be written is left as it is (numba then caches
    elsewhere, and an installed package does not change in place)."""
    lines = []
    for path in sorted(root.rglob("*.py")):
        if b"@njit" in path.read_bytes():
            info = path.stat()
            lines.append(f"{path.relative_to(root)} {info.st_size} {info.st_mtime_ns}\n")
    stamp = hashlib.sha256("".join(lines).encode()).hexdigest()
    marker = root / "__pycache__" / "kernels.stamp"
    try:
        if marker.read_text(encoding="ascii") == stamp:
            return False
    except OSError:
        pass
    try:
        for cache in [*root.rglob("__pycache__/*.nbi"), *root.rglob("__pycache__/*.nbc")]:
            cache.unlink(missing_ok=True)
        marker.parent.mkdir(exist_ok=True)
        partial = marker.with_name(f"{marker.name}.{os.getpid()}")
        partial.write_text(stamp, encoding="ascii")
        partial.replace(marker)  # whole or not at all: other processes may read it
    except OSError:
        return False
    return True


def compiled() -> bool:
    """Whether the kernels are numba dispatchers (after the first call of any kernel
    outside `interpreted()`)."""
    return _compiled


@contextmanager
def interpreted() -> Iterator[None]:
    """Kernels not yet compiled run as plain Python within the block (compiled ones stay)."""
    global _interpreting
    _interpreting += 1
    try:
        yield
    finally:
        _interpreting -= 1
