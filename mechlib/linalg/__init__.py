"""Linear algebra that reports singularity by name: dense and sparse factors of saddle
matrices, LU as flat arrays for the compiled kernels, LAPACK bindings, rank and redundancy."""
