"""A request that fails at some row (an expression dividing by zero) loses only its own
column from that row on: the other columns and the rows before stay in the solution."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from mechlib.core.outcome import SolverFailure

__all__ = ["RequestFailure", "partial_columns"]


class RequestFailure(SolverFailure):
    """Some request columns failed; `channels` holds every column, NaN where one failed."""

    def __init__(
        self,
        message: str,
        channels: dict[str, np.ndarray],
        *,
        time: float | None = None,
        where: tuple[str, ...] = (),
    ) -> None:
        super().__init__(message, time=time, where=where)
        self.channels = channels


def partial_columns(
    channels: dict[str, np.ndarray],
    failed: dict[str, SolverFailure],
    per_request: Mapping[str, Mapping[str, Sequence[float] | np.ndarray]],
    rows: int,
) -> RequestFailure:
    """The failure of the requests in `failed` (name -> failure), their columns padded
    with NaN to `rows` values, every column in request order."""
    padded: dict[str, np.ndarray] = {}
    for name, comps in per_request.items():
        if name not in failed:
            padded |= {f"{name}.{comp}": channels[f"{name}.{comp}"] for comp in comps}
            continue
        for comp, values in (comps or {"value": []}).items():
            column = np.full(rows, np.nan)
            column[: len(values)] = values
            padded[f"{name}.{comp}"] = column
    notes = []
    for name, failure in failed.items():
        columns = ", ".join(c for c in padded if c.split(".")[0] == name)
        notes.append(
            f"{failure} (column {columns} is empty from there on; the other columns are whole)"
        )
    first = min(failed.values(), key=lambda f: f.time if f.time is not None else np.inf)
    return RequestFailure(
        "; ".join(notes),
        padded,
        time=first.time,
        where=tuple(w for f in failed.values() for w in f.where),
    )
