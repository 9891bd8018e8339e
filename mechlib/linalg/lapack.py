"""LAPACK's LU routines called from compiled kernels.

numba's own LAPACK bindings (np.linalg) have no condition estimate and no banded LU. These
kernels call dgetrf, dgecon, dgbtrf and dgbtrs of scipy.linalg.cython_lapack: the
library scipy.linalg.lapack calls, so a kernel's factors equal the Python path's bit for bit.
The routines are bound by symbol name once numba is imported (mechlib.core.jit.on_compile), which
keeps the kernels that call them in numba's disk cache. Matrices are column-major and flat
(a[i + j * lda]); pivots are LAPACK's, 1-based int32.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mechlib.core.jit import KERNEL, njit, on_compile

__all__ = ["gbtrf", "gbtrs", "gecon", "getrf"]

# each routine's number of arguments (all pointers: Fortran passes by reference)
_ROUTINES = {"dgetrf": 6, "dgecon": 9, "dgbtrf": 8, "dgbtrs": 11}
_dgetrf: Any = None  # each bound by _bind
_dgecon: Any = None
_dgbtrf: Any = None
_dgbtrs: Any = None
_ONE_NORM, _NO_TRANSPOSE = ord("1"), ord("N")


def _bind() -> None:
    """Each routine as a numba external function of its cython_lapack address."""
    import llvmlite.binding as ll
    from numba import types
    from numba.extending import get_cython_function_address

    for name, arguments in _ROUTINES.items():
        symbol = f"loads_{name}"
        ll.add_symbol(symbol, get_cython_function_address("scipy.linalg.cython_lapack", name))
        signature = types.void(*([types.voidptr] * arguments))
        globals()[f"_{name}"] = types.ExternalFunction(symbol, signature)


on_compile(_bind)


@njit(**KERNEL)
def getrf(a, n, piv):
    """LU with partial pivoting of the n x n matrix a[:n*n], in place (dgetrf); `piv` (n,
    int32) its pivots. Returns LAPACK's info (> 0: an exactly zero pivot)."""
    dims = np.array([n, n, n, 0], dtype=np.int32)
    _dgetrf(
        dims[0:].ctypes, dims[1:].ctypes, a.ctypes, dims[2:].ctypes, piv.ctypes, dims[3:].ctypes
    )
    return dims[3]


@njit(**KERNEL)
def gecon(a, n, anorm):
    """Reciprocal condition number (1-norm, LAPACK's estimate: dgecon) of the matrix of
    1-norm `anorm` whose getrf factors are a[:n*n]."""
    norm = np.array([_ONE_NORM], dtype=np.uint8)
    dims = np.array([n, n, 0], dtype=np.int32)
    values = np.array([anorm, 0.0])
    work, iwork = np.empty(4 * n), np.empty(n, dtype=np.int32)
    _dgecon(
        norm.ctypes, dims[0:].ctypes, a.ctypes, dims[1:].ctypes, values[0:].ctypes,
        values[1:].ctypes, work.ctypes, iwork.ctypes, dims[2:].ctypes,
    )  # fmt: skip
    return values[1]


@njit(**KERNEL)
def gbtrf(ab, n, kl, ku, piv):
    """LU with partial pivoting of the n x n band matrix of kl sub- and ku superdiagonals
    in LAPACK's band storage ab[:(2 kl + ku + 1) n] (entry (i, j) at kl + ku + i - j +
    j (2 kl + ku + 1)), in place (dgbtrf). Returns LAPACK's info."""
    dims = np.array([n, n, kl, ku, 2 * kl + ku + 1, 0], dtype=np.int32)
    _dgbtrf(
        dims[0:].ctypes, dims[1:].ctypes, dims[2:].ctypes, dims[3:].ctypes, ab.ctypes,
        dims[4:].ctypes, piv.ctypes, dims[5:].ctypes,
    )  # fmt: skip
    return dims[5]


@njit(**KERNEL)
def gbtrs(ab, n, kl, ku, piv, b):
    """b (n) overwritten with the solution of A x = b from A's gbtrf factors (dgbtrs)."""
    trans = np.array([_NO_TRANSPOSE], dtype=np.uint8)
    dims = np.array([n, kl, ku, 1, 2 * kl + ku + 1, n, 0], dtype=np.int32)
    _dgbtrs(
        trans.ctypes, dims[0:].ctypes, dims[1:].ctypes, dims[2:].ctypes, dims[3:].ctypes,
        ab.ctypes, dims[4:].ctypes, piv.ctypes, b.ctypes, dims[5:].ctypes, dims[6:].ctypes,
    )  # fmt: skip
