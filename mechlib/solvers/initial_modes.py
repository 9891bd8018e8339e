"""Given modal coordinates and rates of flexible bodies (`InitialModes`) as rows of the
assembly: each names one column of q (the body's modal coordinates follow all the bodies'
coordinates, mechlib.flexible.attached), so its row is a unit row on that column."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mechlib.model.analysis import InitialModes
from mechlib.system.system import System

__all__ = ["ModalTarget", "modal_columns", "modal_notes", "modal_rate_rows", "modal_targets"]

_REPORT_CHANGE = 1e-8  # relative to the body's largest given value (its own scale)


@dataclass(frozen=True)
class ModalTarget:
    """Modal coordinate `mode` (0-based) of flexible body `body`: column `column` of q,
    the given value `value` (kg^0.5 m, or kg^0.5 m/s for a rate); `scale` the body's largest
    given value, the yardstick of a change worth reporting."""

    body: str
    mode: int
    column: int
    value: float
    scale: float


def modal_columns(system: System, body: str) -> tuple[np.ndarray, np.ndarray]:
    """(q columns (n,), modal stiffness omega^2 (n,) 1/s^2) of flexible body `body`'s modal
    coordinates; ValueError when it is no flexible body of the system."""
    for attached in getattr(system, "flexible", ()):
        if attached.name == body:
            columns = 7 * system.nb + attached.offset + np.arange(attached.body.n)
            return columns, attached.body.component.stiffness
    raise ValueError(f"initial modes: '{body}' is no flexible body of the mechanism")


def _columns(system: System, item: InitialModes, values: Sequence[float]) -> np.ndarray:
    """The q columns of the body's modal coordinates; ValueError when the body is no
    flexible body of the system or `values` does not give one per mode."""
    columns, _ = modal_columns(system, item.body)
    if len(values) != len(columns):
        raise ValueError(
            f"initial modes of body '{item.body}': {len(values)} values given, "
            f"the body has {len(columns)} modes"
        )
    return columns


def _targets(system: System, initial: Sequence, key: str) -> list[ModalTarget]:
    out = []
    for item in initial:
        values = getattr(item, key, None) if isinstance(item, InitialModes) else None
        if values is None:
            continue
        columns = _columns(system, item, values)
        scale = max(float(np.abs(values).max(initial=0.0)), 1e-300)
        out += [
            ModalTarget(item.body, j, int(c), float(v), scale)
            for j, (c, v) in enumerate(zip(columns, values))
        ]
    return out


def modal_targets(system: System, initial: Sequence) -> list[ModalTarget]:
    """The given modal coordinates (kg^0.5 m), one target per mode."""
    return _targets(system, initial, "modes")


def modal_rate_rows(system: System, initial: Sequence) -> tuple[np.ndarray, np.ndarray, list]:
    """(rows (r, nq), right sides (r,) kg^0.5 m/s, targets) of the given modal rates."""
    targets = _targets(system, initial, "rates")
    rows = np.zeros((len(targets), system.nq))
    rows[np.arange(len(targets)), [t.column for t in targets]] = 1.0
    return rows, np.array([t.value for t in targets]), targets


def modal_notes(targets: list[ModalTarget], actual: np.ndarray, what: str) -> list[str]:
    """The given modal values (`what`: 'modal coordinate' or 'modal rate') that the
    constraints changed, with the values reached (`actual`, by target)."""
    notes = []
    for target, value in zip(targets, actual):
        if abs(value - target.value) > _REPORT_CHANGE * target.scale:
            notes.append(
                f"initial {what} q{target.mode + 1} of body '{target.body}' changed from "
                f"{target.value:.6g} to {value:.6g} to satisfy the constraints"
            )
    return notes
