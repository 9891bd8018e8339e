"""The full FE model's frequencies beside its Craig-Bampton reductions' (`loads flex check`;
seed 003 Tables 3-2 and 3-3): free-free elastic modes and fixed-interface modes (interface
nodes held), per fixed-interface mode count, with relative differences."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from loadcases.flexible.summary import free_free_frequencies, rigid_modes
from mechlib.flexible.fe_model import FEModel
from mechlib.flexible.frequencies import held_frequencies, reduced_frequencies

__all__ = ["ReductionFrequencies", "reduction_frequencies"]


@dataclass(frozen=True)
class ReductionFrequencies:
    """Frequencies (Hz, ascending): `full_free` the full model's lowest elastic free-free
    modes, `full_held` its lowest held ones; per count of `counts`, the reduced model's
    (`reduced_free[j]`, `reduced_held[j]`, at most as many as the full model's rows)."""

    counts: tuple[int, ...]
    rigid: int
    full_free: np.ndarray
    full_held: np.ndarray
    reduced_free: tuple[np.ndarray, ...]
    reduced_held: tuple[np.ndarray, ...]


def reduction_frequencies(model: FEModel, counts: Sequence[int], rows: int) -> ReductionFrequencies:
    """The comparison for `rows` modes of each kind and the fixed-interface mode `counts`."""
    rigid = rigid_modes(model)
    hertz, _ = free_free_frequencies(model, rows + rigid)
    full_free = hertz[rigid:]
    free, held = zip(*(reduced_frequencies(model, count) for count in counts), strict=True)
    return ReductionFrequencies(
        tuple(counts),
        rigid,
        full_free,
        held_frequencies(model, rows),
        tuple(f[:rows] for f in free),
        tuple(h[:rows] for h in held),
    )
