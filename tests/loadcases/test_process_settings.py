"""A solving process runs its BLAS on one thread (loadcases.foundation.process_settings):
the limit is set through threadpoolctl on the BLAS numpy loaded, and a user's own thread
setting in the environment is kept."""

from __future__ import annotations

import json
import os
import subprocess
import sys

_PROBE = (
    "import json, {before}threadpoolctl\n"
    "from loadcases.foundation.process_settings import one_blas_thread\n"
    "set_now = one_blas_thread()\n"
    "import numpy, scipy.linalg\n"
    "blas = [i['num_threads'] for i in threadpoolctl.threadpool_info() "
    "if i['user_api'] == 'blas']\n"
    "print(json.dumps([set_now, blas]))\n"
)


def _probe(before: str = "numpy, ", **env: str) -> tuple[bool, list[int]]:
    """(what one_blas_thread returned, the threads of each BLAS loaded) in a new process
    that imports `before`, limits, then imports numpy and scipy.linalg (scipy's OpenBLAS,
    a second library)."""
    clean = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    done = subprocess.run(
        [sys.executable, "-c", _PROBE.format(before=before)],
        env={**clean, **env},
        capture_output=True,
        text=True,
        check=True,
    )
    set_now, blas = json.loads(done.stdout)
    return set_now, blas


def test_one_blas_thread() -> None:
    set_now, blas = _probe()
    assert set_now is True
    assert len(blas) == 2 and all(n == 1 for n in blas)  # numpy's and scipy's OpenBLAS


def test_blas_loaded_after_the_limit_keeps_it() -> None:
    """Limited before numpy and scipy load their BLAS: both still run one thread (each
    reads the environment as it loads; threadpoolctl only reaches those loaded)."""
    set_now, blas = _probe(before="")
    assert set_now is True
    assert len(blas) == 2 and all(n == 1 for n in blas)


def test_a_users_setting_is_kept() -> None:
    set_now, blas = _probe(OPENBLAS_NUM_THREADS="2")
    assert set_now is False
    assert blas and all(n == min(2, os.cpu_count() or 1) for n in blas)
