"""A system with modal bodies packed for the compiled Newton loop
(mechlib.solvers.genalpha.modal_newton): its rigid constraint equations as
mechlib.kinematics.constraint_arrays packs them (every geometric and coordinate row, in the
system's order), the weld rows' place among them, and each modal body's invariants, shapes
and scratch arrays in one tuple (the arguments of mechlib.flexible.kernels and
mechlib.flexible.weld_kernels, their one definition).

Rows of the working Jacobian, in the system's order: the rigid geometric rows [0, first),
the welds [first, first + welds), the coordinate rows after them; columns 7 (nb + 1) + nz:
the bodies', ground's (dropped from phi_q) and the modal coordinates'.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from mechlib.core import jit
from mechlib.flexible.attached import Attached, NodeWelds
from mechlib.kinematics.constraint_arrays import ConstraintArrays, pack_rows
from mechlib.kinematics.constraints import Dot1, Dot2, Normalization, Spherical

__all__ = ["ModalArrays", "modal_arrays"]


def modal_arrays(system) -> ModalArrays | None:
    """The system packed (`ModalArrays`) when the compiled loop serves it: modal bodies,
    rigid bodies of 7 coordinates joined by primitive equations and welds, no point-on-curve
    rows, no force elements and no element states (their loads and tangents are
    Python's), the kernels compiled; else None."""
    return ModalArrays(system) if _servable(system) else None


def _servable(system) -> bool:
    """What `modal_arrays` asks of a system."""
    if not system.flexible or getattr(system, "per_body", 0) != 7 or not jit.compiled():
        return False
    if system.elements or system.states:
        return False
    kinds = (Normalization, Spherical, Dot1, Dot2, NodeWelds)
    if not all(type(g) in kinds for g in system.groups):
        return False
    return not system.coordinate_rows().own


def _body_args(a: Attached, first: int) -> tuple:
    """The arrays of modal body `a` whose welds start at row `first` (of all rows): ints
    (frame, first modal coordinate, modes, first weld row, stiffened), node bodies, I1,
    I2 ... I9 (I8, I9 symmetrised), stiffness, viscous, spin and node stiffening cases, kept
    nodes' positions and shapes, and scratch: M_w, f_w, M_q and Q_q (mechlib.flexible.kernels),
    node loads and their maps, and no node loads (an empty array)."""
    body = a.body
    i1, i2, i3, i4, i5, i6, i7, i8s, i9s = body.arrays
    n, nodes = body.n, np.asarray(a.nodes, dtype=np.int64)
    stiffened = int(body.component.geometric is not None and len(body.nodal) > 0)
    ints = np.array([a.frame, a.offset, n, first, stiffened], dtype=np.int64)
    return (
        ints, nodes, np.array([i1]), i2, i3, i4, i5, i6, i7, i8s, i9s, body.stiffness,
        body.viscous, body.spin, body.nodal, body.positions, body.phi, body.phi_star,
        np.empty((6 + n, 6 + n)), np.empty(6 + n), np.empty((7 + n, 7 + n)), np.empty(7 + n),
        np.zeros((len(nodes), 6)), np.empty((len(nodes), 6, 6)), np.zeros((0, 6)),
    )  # fmt: skip


class ModalArrays(ConstraintArrays):
    """The packed constraints of a system with modal bodies (module docstring): `packed()`
    the rigid rows (all of them active in the pack: the system's active rows are selected
    by `active()` over all rows), `welds()` (first weld row, weld rows), `modal()` the
    modal bodies' tuples; `functions`, `references` and `bodies` as ConstraintArrays'."""

    def __init__(self, system):
        super().__init__(system)
        welds, first = system._welds
        self._welds = np.array([first, welds.size], dtype=np.int64)
        self._modal = tuple(_body_args(a, first + row) for a, row, _ in welds.bodies)

    @staticmethod
    def eligible(system) -> bool:
        return _servable(system)

    def packed(self) -> tuple[np.ndarray, np.ndarray]:
        """(ints, floats) of the rigid rows, every one active (the welds are not among
        them: `welds`), rebuilt when the coordinate block changes."""
        system = self.system
        block = system.coordinate_rows()
        key = self._key
        if not key or key[0] is not block or key[1] != block.size:
            rigid = len(system._all_labels) - self._welds[1]
            proxy = SimpleNamespace(groups=system.groups, nb=system.nb, active=np.arange(rigid))
            self._packed, self._key = pack_rows(proxy, block), (block, block.size)
        return self._packed

    def active(self) -> np.ndarray:
        """The system's active rows (indices into all rows, welds among them)."""
        return np.asarray(self.system.active, dtype=np.int64)

    def welds(self) -> np.ndarray:
        """(first weld row, number of weld rows) (2,)."""
        return self._welds

    def modal(self) -> tuple:
        """The modal bodies' argument tuples (`_body_args`)."""
        return self._modal
