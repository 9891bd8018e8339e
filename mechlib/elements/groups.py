"""Force elements of one type evaluated in one compiled call (the design rule: elements grouped by
type and evaluated as arrays, so that cost grows with the work, not with Python overhead).

Linear springs and linear torsion springs of a system, when it has two or more of a type,
are packed into arrays at bind (a bound element's constants are fixed) and evaluated by one
kernel call per type, which loops over them: each flag `active`, each angle's unwrapping
reference and the elements a caller leaves out (`skip`) are read at every call. Every other
element is evaluated on its own (`System.wrenches`). Same formulas as the elements'
own kernels (kernels.spring_wrench, torsion_wrench), called per member.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Collection, Sequence

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.elements.forces import Spring, TorsionSpring
from mechlib.kinematics.kernels import spring_wrench, torsion_wrench

__all__ = ["SpringGroup", "TorsionSpringGroup", "grouped", "spring_rows", "torsion_rows"]

_MIN_MEMBERS = 2  # one element alone is as cheap on its own


class _Group(ABC):
    """Elements of one type in one call; `members` in the system's order."""

    def __init__(self, members: Sequence) -> None:
        self.members = list(members)
        self._ids = [id(e) for e in self.members]

    def _on(self, skip: Collection[int]) -> np.ndarray:
        """Per member: active and not left out."""
        if not skip:
            return np.array([e.active for e in self.members])
        return np.array([e.active and i not in skip for e, i in zip(self.members, self._ids)])

    @abstractmethod
    def apply(self, x: np.ndarray, xd: np.ndarray, skip, F: np.ndarray, N: np.ndarray) -> None:
        """Add the loads of the members that are active and not in `skip` (element ids) at
        the state x, xd (nb+1, 7) to F and N (nb+1, 3)."""


def spring_rows(springs: Sequence[Spring]) -> tuple[np.ndarray, np.ndarray]:
    """(ints (n, 3), floats (n, 10)) of bound linear springs, `springs_wrench`'s layout:
    bodies and wire (slack) flag; points (m), stiffness (N/m), damping (N*s/m), free length
    (m), preload (N): kernels.spring_wrench's arguments, taken at bind."""
    ints, floats = [], []
    for spring in springs:
        b1, s1, b2, s2, stiffness, damping, free_length, preload, slack = spring._compiled
        ints.append([b1, b2, int(slack)])
        floats.append([*s1, *s2, stiffness, damping, free_length, preload])
    return (
        np.array(ints, dtype=np.int64).reshape(-1, 3),
        np.array(floats, dtype=float).reshape(-1, 10),
    )


def torsion_rows(elements: Sequence, constants: Sequence) -> tuple[np.ndarray, np.ndarray]:
    """(ints (n, 2), floats (n, 13)) of bound angle elements, `torsion_springs_wrench`'s
    layout: their angle measure's bodies; its frames and axis, then each element's
    `constants` (kernels.torsion_wrench's: TorsionSpring.linear_constants)."""
    ints = [[e._m.bi, e._m.bj] for e in elements]
    floats = [[*e._m.f, *e._m.g, *e._m.axis_local, *c] for e, c in zip(elements, constants)]
    return (
        np.array(ints, dtype=np.int64).reshape(-1, 2),
        np.array(floats, dtype=float).reshape(-1, 13),
    )


class SpringGroup(_Group):
    """Linear springs (no table law): kernels.spring_wrench of each, in one call."""

    def __init__(self, members: Sequence[Spring]) -> None:
        super().__init__(members)
        self.ints, self.floats = spring_rows(members)

    def apply(self, x: np.ndarray, xd: np.ndarray, skip, F: np.ndarray, N: np.ndarray) -> None:
        springs_wrench(x, xd, self.ints, self.floats, self._on(skip), F, N)


class TorsionSpringGroup(_Group):
    """Linear torsion springs (no table law): kernels.torsion_wrench of each, in one call."""

    def __init__(self, members: Sequence[TorsionSpring]) -> None:
        super().__init__(members)
        self.ints, self.floats = torsion_rows(members, [s.linear_constants for s in members])

    def apply(self, x: np.ndarray, xd: np.ndarray, skip, F: np.ndarray, N: np.ndarray) -> None:
        references = np.array([s._m.reference for s in self.members])
        torsion_springs_wrench(x, xd, self.ints, self.floats, references, self._on(skip), N)


def grouped(elements: Sequence) -> tuple[list[_Group], list]:
    """(groups, the other elements) of a system's bound elements, each in the given order."""
    springs = [e for e in elements if type(e) is Spring and e.law is None]
    torsion = [e for e in elements if type(e) is TorsionSpring and e.law is None]
    groups: list[_Group] = []
    if len(springs) >= _MIN_MEMBERS:
        groups.append(SpringGroup(springs))
    if len(torsion) >= _MIN_MEMBERS:
        groups.append(TorsionSpringGroup(torsion))
    taken = {id(e) for g in groups for e in g.members}
    return groups, [e for e in elements if id(e) not in taken]


@njit(**KERNEL)
def springs_wrench(x, xd, ints, floats, on, F, N):
    """kernels.spring_wrench of each spring i with on[i]: bodies ints[i, :2], wire
    ints[i, 2]; points floats[i, :6], stiffness, damping, free length, preload."""
    for i in range(ints.shape[0]):
        if on[i]:
            f = floats[i]
            spring_wrench(
                x, xd, ints[i, 0], f[0:3], ints[i, 1], f[3:6], f[6], f[7], f[8], f[9],
                ints[i, 2] != 0, F, N,
            )  # fmt: skip


@njit(**KERNEL)
def torsion_springs_wrench(x, xd, ints, floats, references, on, N):
    """kernels.torsion_wrench of each torsion spring i with on[i]: the angle's bodies
    ints[i]; its triad f, g and axis floats[i, :9], stiffness, damping, angle0, preload;
    its unwrapping reference references[i] (rad)."""
    for i in range(ints.shape[0]):
        if on[i]:
            f = floats[i]
            torsion_wrench(
                x, xd, ints[i, 0], ints[i, 1], f[0:3], f[3:6], f[6:9], references[i],
                f[9], f[10], f[11], f[12], N,
            )  # fmt: skip
