"""Speed and accuracy benchmarks of `loads` against Exudyn (see README.md).

Importing `cli` first keeps BLAS single-threaded, as `loads` runs (cli/__init__.py): run
directly (`python -m benchmarks.planar`), numpy would otherwise start a BLAS thread per core,
which on a loaded machine made a 240-row least squares take 1 s instead of 10 ms.
"""

import cli  # noqa: F401
