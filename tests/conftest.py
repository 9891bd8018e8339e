"""Keep BLAS single-threaded: the engine's matrices are small (tens to hundreds of rows),
where BLAS threads cost more than they give and fight with process-level parallelism
(`--jobs`, pytest-xdist) for the cores."""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
