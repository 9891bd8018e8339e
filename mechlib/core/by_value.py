"""Results kept per process by the values they were computed from (a sweep's runs in a worker).

The runs of a sweep solved in one process share much of their input: a campaign varying an
initial rate has the same constraint Jacobian at the start in every run. `ByValue` keeps a
pure function's last few results keyed by the values it reads (`value_key`: arrays by
dtype, shape and bytes, never by name or identity), so a run given those same values gets
the same (bit-identical) result, and a run given any other value computes its own. Memory
is bounded: the least recently used result goes first.
"""

from __future__ import annotations

import dataclasses
import struct
from collections import OrderedDict
from collections.abc import Callable, Hashable
from enum import Enum
from typing import Generic, TypeVar

import numpy as np

__all__ = ["ByValue", "value_key"]

T = TypeVar("T")


def value_key(*parts: object) -> tuple:
    """A hashable key of `parts` by value: arrays as (dtype, shape, bytes); tuples, lists
    and dicts item by item in their order; sets sorted; dataclasses by class and every
    attribute the instance holds (private ones too); floats by their bits (-0.0 is not
    0.0); integers, strings, enums and None as they are. Anything else (a function, an
    object of unknown state) raises TypeError: a key that cannot see every value read is
    no key."""
    return tuple(_part(part, set()) for part in parts)


def _part(part: object, path: set[int]) -> Hashable:
    """The key of `part`; `path`: the ids of the containers it is inside (a cycle is
    refused: it has no finite key)."""
    if isinstance(part, np.ndarray):
        return ("array", part.dtype.str, part.shape, part.tobytes())
    if isinstance(part, np.generic):  # before float: numpy's float64 is one
        return ("scalar", part.dtype.str, part.tobytes())
    if isinstance(part, float):  # by its bits: -0.0 is not 0.0 (atan2 tells them apart)
        return ("float", struct.pack("<d", part))
    if isinstance(part, Enum):
        return (type(part).__qualname__, part.name)
    if isinstance(part, int | str | bool) or part is None:
        return (type(part).__name__, part)
    if id(part) in path:
        raise TypeError(f"value_key: a {type(part).__name__} inside itself")
    path.add(id(part))
    try:
        return _container(part, path)
    finally:
        path.discard(id(part))


def _container(part: object, path: set[int]) -> Hashable:
    """The key of a tuple, list, dict, set or dataclass instance, item by item."""
    if isinstance(part, tuple | list):
        return (type(part).__name__, *(_part(p, path) for p in part))
    if isinstance(part, dict):
        return ("dict", *((_part(k, path), _part(v, path)) for k, v in part.items()))
    if isinstance(part, set | frozenset):
        return ("set", *sorted((_part(p, path) for p in part), key=repr))
    if dataclasses.is_dataclass(part) and not isinstance(part, type):
        kind = type(part)
        declared = [f.name for f in dataclasses.fields(part)]
        # every attribute the instance holds, declared or set later (a cache, a memory)
        names = list(vars(part)) if hasattr(part, "__dict__") else declared
        fields = ((name, _part(getattr(part, name), path)) for name in names)
        return (kind.__module__, kind.__qualname__, *fields)
    raise TypeError(f"value_key: {type(part).__name__} is not keyed by value")


class ByValue(Generic[T]):
    """The last `size` results of one function, by `value_key` of its inputs."""

    def __init__(self, size: int) -> None:
        self.size = size
        self._kept: OrderedDict[tuple, T] = OrderedDict()
        self.hits = 0  # results served from memory (tests, profiling)

    def get(self, key: tuple, compute: Callable[[], T]) -> T:
        """The result kept for `key`, else `compute()`, kept (the oldest dropped beyond
        `size`)."""
        if key in self._kept:
            self._kept.move_to_end(key)
            self.hits += 1
            return self._kept[key]
        result = compute()
        self._kept[key] = result
        if len(self._kept) > self.size:
            self._kept.popitem(last=False)
        return result

    def clear(self) -> None:
        """Forget every result."""
        self._kept.clear()
        self.hits = 0

    def __len__(self) -> int:
        return len(self._kept)
