"""A flexible component reduced to modes: what the equations of motion need (SI).

The component's reference frame has its origin at the undeformed centre of mass and the
axes of the FE model; positions below are from that origin. Modes are mass-normalised
(a modal coordinate in kg^0.5 m), orthogonal to the six rigid-body motions (so I3 = I4 = 0
up to round-off: a linearised mean-axis frame).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from mechlib.flexible.invariants import Invariants
from mechlib.flexible.stiffening import ModalGeometric

__all__ = ["ModalComponent", "default_damping"]


def default_damping(frequencies_hz: np.ndarray) -> np.ndarray:
    """Adams' default modal damping ratios: 1 % below 100 Hz, 10 % below 1 kHz, 100 %
    above (adams_solver FLEX_BODY, CRATIO omitted)."""
    f = np.asarray(frequencies_hz, dtype=float)
    return np.where(f < 100.0, 0.01, np.where(f < 1000.0, 0.1, 1.0))


def damping_ratios(
    frequencies_hz: np.ndarray, damping: float | Mapping[int, float] | None
) -> np.ndarray:
    """Per mode: `damping` for all modes (a number), or the default table with the ratios
    of a {mode number (1-based): ratio} mapping put over it."""
    if damping is None or isinstance(damping, Mapping):
        ratios = default_damping(frequencies_hz)
        for mode, ratio in (damping or {}).items():
            if not 1 <= mode <= len(ratios):
                raise ValueError(f"damping of mode {mode}: only {len(ratios)} modes are kept")
            ratios[mode - 1] = ratio
        return ratios
    return np.full(len(frequencies_hz), float(damping))


@dataclass(frozen=True)
class ModalComponent:
    """Mass (kg), centre of mass `origin` (3,) m in the FE model's coordinates, the nine
    invariants about it, and per kept node: `node_ids` (k,), `positions` (k, 3) m from the
    origin, `phi` (k, 3, n) translations and `phi_star` (k, 3, n) rotations (rad) per unit
    modal coordinate; `frequencies` (n,) rad/s, `damping` (n,) ratios of critical;
    `geometric` the modal geometric stiffness (geometric stiffening) or None (off);
    `held_frequency` (rad/s) the lowest frequency of the body held at one interface node
    (the softest single attachment: the spin guard's yardstick), None when unknown."""

    mass: float
    origin: np.ndarray
    invariants: Invariants
    node_ids: np.ndarray
    positions: np.ndarray
    phi: np.ndarray
    phi_star: np.ndarray
    frequencies: np.ndarray
    damping: np.ndarray
    geometric: ModalGeometric | None = None
    held_frequency: float | None = None

    @property
    def count(self) -> int:
        """Number of modes."""
        return len(self.frequencies)

    def node(self, node_id: int) -> int:
        """Row of the user's node number `node_id` among the kept nodes."""
        hits = np.flatnonzero(self.node_ids == node_id)
        if hits.size == 0:
            raise KeyError(f"node {node_id} is not kept in the modal component")
        return int(hits[0])

    @property
    def stiffness(self) -> np.ndarray:
        """Modal stiffness diag(omega^2) (n,)."""
        return self.frequencies**2

    @property
    def viscous(self) -> np.ndarray:
        """Modal damping diag(2 xi omega) (n,)."""
        return 2.0 * self.damping * self.frequencies
