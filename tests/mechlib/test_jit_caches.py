"""numba's kernel caches are dropped when a kernel source changes (mechlib.core.jit).

numba keys each kernel's disk cache on that kernel's own file: a caller in another module
would keep a changed callee's old code. `drop_stale_caches` drops every cache of the tree
when any of its kernel sources changed, and only then.
"""

from __future__ import annotations

import os
from pathlib import Path

from mechlib.core.jit import drop_stale_caches


def _caches(root: Path) -> list[Path]:
    folder = root / "__pycache__"
    folder.mkdir(exist_ok=True)
    files = [folder / "caller.run-1.py311.nbi", folder / "caller.run-1.py311.1.nbc"]
    for f in files:
        f.write_bytes(b"cache")
    return files


def test_caches_kept_while_the_sources_stay_and_dropped_when_one_changes(tmp_path) -> None:
    (tmp_path / "caller.py").write_text("@njit\ndef run(): return callee()\n")
    (tmp_path / "sub").mkdir()
    callee = tmp_path / "sub" / "callee.py"
    callee.write_text("@njit\ndef callee(): return 1\n")
    pyc = tmp_path / "__pycache__" / "caller.cpython-311.pyc"

    assert drop_stale_caches(tmp_path)  # no stamp yet
    files = _caches(tmp_path)
    pyc.write_bytes(b"bytecode")
    assert not drop_stale_caches(tmp_path)
    assert all(f.exists() for f in files)

    callee.write_text("@njit\ndef callee(): return 2\n")
    info = callee.stat()
    os.utime(callee, ns=(info.st_atime_ns, info.st_mtime_ns + 1_000_000))
    assert drop_stale_caches(tmp_path)
    assert not any(f.exists() for f in files)
    assert pyc.exists()  # only numba's files go
    assert not drop_stale_caches(tmp_path)


def test_a_new_kernel_file_drops_them_and_a_plain_module_does_not(tmp_path) -> None:
    (tmp_path / "a.py").write_text("@njit\ndef f(): return 1\n")
    drop_stale_caches(tmp_path)
    files = _caches(tmp_path)
    (tmp_path / "plain.py").write_text("y = 2\n")  # no kernel: no cache can depend on it
    assert not drop_stale_caches(tmp_path)
    assert all(f.exists() for f in files)
    (tmp_path / "b.py").write_text("@njit\ndef g(): return 2\n")
    assert drop_stale_caches(tmp_path)
    assert not any(f.exists() for f in files)
