"""Frequencies of a full FE model beside those of its Craig-Bampton reduction (seed 003
Tables 3-2 and 3-3): free-free, and with the interface nodes held (fixed-interface).

Held, the reduced model keeps only its fixed-interface modes, so its frequencies are those
of the full model's lowest n_q held modes (up to the eigen-solver's rounding); free-free,
they are Rayleigh-Ritz upper bounds that approach the full model's as n_q grows.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from mechlib.flexible.craig_bampton import _split, basis, free_modes
from mechlib.flexible.fe_model import FEModel

__all__ = ["held_frequencies", "reduced_frequencies"]

_DENSE_LIMIT = 600  # internal DOF up to which the held modes come from a dense eigh


def _hertz(w2: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(np.sort(w2), 0.0)) / (2.0 * np.pi)


def held_frequencies(model: FEModel, count: int) -> np.ndarray:
    """The lowest `count` frequencies (Hz) of the full model with every DOF of its interface
    nodes held (fewer when it has fewer internal DOF)."""
    _, i = _split(model)
    count = min(count, len(i))
    if count == 0:
        return np.zeros(0)
    k = model.stiffness.tocsr()[i][:, i]
    m = model.mass.tocsr()[i][:, i]
    if len(i) <= _DENSE_LIMIT or count >= len(i) - 1:
        w2 = sla.eigh(k.toarray(), m.toarray(), eigvals_only=True, subset_by_index=[0, count - 1])
    else:
        start = np.full(len(i), 1.0 / np.sqrt(len(i)))  # reproducible (see craig_bampton)
        w2 = spla.eigsh(
            k.tocsc(), k=count, M=m.tocsc(), sigma=0.0, v0=start, return_eigenvectors=False
        )
    return _hertz(w2)


def reduced_frequencies(
    model: FEModel, fixed_interface_modes: int
) -> tuple[np.ndarray, np.ndarray]:
    """(free-free, held) frequencies (Hz, ascending) of the reduced model with
    `fixed_interface_modes`: every elastic mode of the reduced model (its six rigid-body
    modes removed), and those of its K^, M^ with the interface coordinates held."""
    omega, _ = free_modes(model, fixed_interface_modes)
    t = basis(model, fixed_interface_modes)
    b, _ = _split(model)
    normal = t[:, len(b) :]
    if normal.shape[1] == 0:
        return omega / (2.0 * np.pi), np.zeros(0)
    k_hat = normal.T @ (model.stiffness @ normal)
    m_hat = normal.T @ (model.mass @ normal)
    return omega / (2.0 * np.pi), _hertz(sla.eigh(k_hat, m_hat, eigvals_only=True))
