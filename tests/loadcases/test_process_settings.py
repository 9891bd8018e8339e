"""A solving process runs its BLAS on one thread (loadcases.process_settings): the limit is
set through threadpoolctl on the BLAS numpy loaded, and a user's own thread setting in the
environment is kept."""

from __future__ import annotations

import json
import os
import subprocess
import sys

_PROBE = (
    "import json, numpy, threadpoolctl\n"
    "from loadcases.process_settings import one_blas_thread\n"
    "set_now = one_blas_thread()\n"
    "blas = [i['num_threads'] for i in threadpoolctl.threadpool_info() "
    "if i['user_api'] == 'blas']\n"
    "print(json.dumps([set_now, blas]))\n"
)


def _probe(**env: str) -> tuple[bool, list[int]]:
    clean = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    done = subprocess.run(
        [sys.executable, "-c", _PROBE],
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
    assert blas and all(n == 1 for n in blas)


def test_a_users_setting_is_kept() -> None:
    set_now, blas = _probe(OPENBLAS_NUM_THREADS="2")
    assert set_now is False
    assert blas and all(n == min(2, os.cpu_count() or 1) for n in blas)
