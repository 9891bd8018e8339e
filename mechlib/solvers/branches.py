"""Assembly branches: which of a closed loop's assemblies a run is on, and where it changes.

A loop closed through joint values has several assemblies (a four-bar open or crossed, a
knee folded one way or the other). Two measures tell them apart:

- the orientation: the sign of det [phi_q; dc/dq], the constraint Jacobian (motions and
  locks included) completed by the gradients of the given joint coordinates c, each row
  scaled to unit length. Where that matrix is square (the given values fix every degree of
  freedom) the sign changes only where it is singular: a toggle, where the given joints
  can no longer drive the loop and it can fold either way, or a bifurcation (a
  parallelogram four-bar with its links aligned, free to go on as an antiparallelogram);
- a jump: a joint angle that changes by more than the branch angle within a step that
  small continuous motions take (an assembly stage), or far more than in the steps on
  either side of it (a row of a quasi-static or kinematic run): a snap-through.

The assembly follows the drawn geometry to the given values in stages kept on the drawn
branch by these measures (mechlib.solvers.assembly); what it cannot keep, and what a run
passes, is a `BranchChange`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import lu_factor

from mechlib.kinematics.kin import Kin
from mechlib.model.analysis import BranchCheck
from mechlib.system.system import System

__all__ = [
    "BranchChange",
    "angle_values",
    "guess_changes",
    "orientation",
    "orientation_changes",
    "row_changes",
    "stage_jumps",
]

_PIVOT_FLOOR = 1e-10  # pivots below this share of the largest: singular, orientation unknown
_SNAP_RATIO = 10.0  # a row's change this many times its neighbours' is a jump
_SNAP_FLOOR = math.radians(1.0)  # rad: smaller changes are never jumps (round-off, creep)
_NAMED = 5  # joints named per change at most


@dataclass(frozen=True)
class BranchChange:
    """Joints that left their branch at `time` (s): (joint, from, to) in rad, and what
    `from` is (`drawn`: the drawn geometry; `guess`: the case's guess; `previous row`)."""

    time: float
    joints: tuple[tuple[str, float, float], ...]
    reference: str
    why: str

    def message(self) -> str:
        def deg(x: float) -> str:
            return f"{round(math.degrees(x), 3) + 0.0:g} deg"  # + 0.0: no '-0'

        now = "now" if self.reference == "previous row" else "assembled"
        shown = "; ".join(
            f"joint '{j}' {self.reference} {deg(a)}, {now} {deg(b)}"
            for j, a, b in self.joints[:_NAMED]
        )
        more = len(self.joints) - _NAMED
        if more > 0:
            shown += f" (and {more} more)"
        return f"assembly branch changed at t = {self.time:.6g} s: {shown}: {self.why}"


def orientation(system: System, k: Kin, given) -> int:
    """+1 or -1: the sign of det [phi_q; dc/dq] (rows of unit length) at `k` for the given
    coordinate measures `given`; 0 where that matrix is not square or nearly singular."""
    rows = [system.phi_q(k)] + [system.coordinate_gradient(m, k)[None, :] for m in given]
    matrix = np.vstack(rows)
    if matrix.shape[0] != matrix.shape[1] or matrix.shape[0] == 0:
        return 0
    norms = np.linalg.norm(matrix, axis=1)
    if not np.all(norms > 0.0) or not np.all(np.isfinite(matrix)):
        return 0
    lu, pivots = lu_factor(matrix / norms[:, None], check_finite=False)
    diagonal = np.diag(lu)
    size = np.abs(diagonal)
    if size.min() <= _PIVOT_FLOOR * size.max():
        return 0
    swaps = int(np.count_nonzero(pivots != np.arange(len(pivots))))
    negative = int(np.count_nonzero(diagonal < 0.0))
    return -1 if (swaps + negative) % 2 else 1


def angle_values(system: System, k: Kin) -> dict[str, float]:
    """Every joint angle (rad) at `k`, unwrapped against the committed references."""
    return {
        joint: float(m.value(k)) for (joint, kind), m in system.measures.items() if kind == "angle"
    }


def stage_jumps(
    before: dict[str, float], after: dict[str, float], limit: float, skip=()
) -> list[tuple[str, float, float]]:
    """Joints (not in `skip`) whose angle changed by more than `limit` (rad) over a stage,
    as (joint, before, after), the largest change first."""
    moved = [
        (j, before[j], after[j])
        for j in before
        if j not in skip and abs(after[j] - before[j]) > limit
    ]
    return sorted(moved, key=lambda m: -abs(m[2] - m[1]))


def guess_changes(
    system: System, k: Kin, guesses: dict[str, float], check: BranchCheck
) -> list[BranchChange]:
    """The guessed joint angles assembled more than `check.angle` from their guess (a
    guessed travel steers the assembly but has no angle to be judged by)."""
    far = []
    for joint, guess in guesses.items():
        measure = system.coordinate_of(joint)
        value = float(measure.value(k))
        if measure.kind == "angle" and abs(value - guess) > check.angle:
            far.append((joint, guess, value))
    if not far:
        return []
    why = (
        f"more than {math.degrees(check.angle):g} deg from the guess (`branches.angle`): "
        "no assembly near it meets the constraints and the given values"
    )
    return [BranchChange(k.t, tuple(far), "guess", why)]


def row_changes(
    times: np.ndarray, angles: dict[str, np.ndarray], check: BranchCheck, event_times=()
) -> list[BranchChange]:
    """Snap-throughs between recorded rows: a joint angle whose change between two rows
    exceeds _SNAP_FLOOR and _SNAP_RATIO times its changes over the intervals beside it (an
    interval of no time, or one starting at an event, is left out: a model change)."""
    if len(times) < 2 or not angles:
        return []
    dt = np.diff(times)
    skip = dt <= 0.0
    for te in event_times:
        skip |= np.isclose(times[:-1], te, rtol=0.0, atol=1e-12)
    jumps: dict[int, list[tuple[str, float, float]]] = {}
    for joint, column in angles.items():
        change = np.abs(np.diff(column))
        change[skip] = 0.0
        before = np.r_[0.0, change[:-1]]
        after = np.r_[change[1:], 0.0]
        beside = np.maximum(before, after)
        for i in np.flatnonzero((change > _SNAP_FLOOR) & (change > _SNAP_RATIO * beside)):
            jumps.setdefault(int(i), []).append((joint, float(column[i]), float(column[i + 1])))
    why = (
        "a snap-through between two rows (a joint angle jumped, far more than in the rows "
        "beside): the loop passed a toggle onto another assembly; reactions after it belong "
        "to that branch"
    )
    return [
        BranchChange(float(times[i + 1]), tuple(jumps[i]), "previous row", why)
        for i in sorted(jumps)
    ]


def orientation_changes(
    system: System, times: np.ndarray, qs: np.ndarray, angles: dict[str, np.ndarray]
) -> list[BranchChange]:
    """Where the orientation of a run's constraints (square: motions drive every degree of
    freedom) changes sign between two rows, with the joints that moved most
    over that interval (a snap-through of any size, even one taken in a single step)."""
    flips, last = [], 0
    for i, (t, q) in enumerate(zip(times, qs)):
        sign = orientation(system, system.kin(q, None, float(t)), [])
        if sign and last and sign != last:
            flips.append(i)
        last = sign or last
    why = (
        "the constraints' orientation changed sign between two rows (the run passed a "
        "toggle onto another assembly, or jumped to it in one step); reactions after it "
        "belong to that branch"
    )
    changes = []
    for i in flips:
        moved = sorted(angles, key=lambda j: -abs(angles[j][i] - angles[j][i - 1]))
        far = [j for j in moved if abs(angles[j][i] - angles[j][i - 1]) > _SNAP_FLOOR]
        # a toggle passed slowly moves the joints little: then those that moved most
        joints = tuple((j, float(angles[j][i - 1]), float(angles[j][i])) for j in far or moved[:3])
        changes.append(BranchChange(float(times[i]), joints, "previous row", why))
    return changes
