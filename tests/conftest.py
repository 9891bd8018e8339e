"""Keep BLAS single-threaded: the engine's matrices are small (tens to hundreds of rows),
where BLAS threads cost more than they give and fight with process-level parallelism
(`--jobs`, pytest-xdist) for the cores. Tests marked `long` (minutes of CPU: the published
benchmarks over their full length) run only with `pytest --long`."""

import os

import pytest

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--long", action="store_true", help="also run the tests marked long (minutes each)"
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if config.getoption("--long"):
        return
    skip = pytest.mark.skip(reason="a long benchmark run: give --long to run it")
    for item in items:
        if "long" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(autouse=True)
def _reduction_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    """Flexible-body reductions cached in one temporary folder per session, never in the
    working folder (loadcases.flexible.cache); the caches' seal key in another, never in
    the user's data folder (loadcases.foundation.cache_seal)."""
    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "loads-cache"))
    monkeypatch.setenv("LOADS_SEAL_KEY", str(tmp_path_factory.getbasetemp() / "seal" / "key"))
