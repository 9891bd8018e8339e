"""System torque margin of hinge lines synchronised by closed cable loops (issue 37; seed
003 section 2.1 applied to the whole wing).

Eq. 2.1 counts each hinge line's own torques, so a line driven through a cable loop by the
springs of the others (AMOS-3 HL1) fails it although the wing deploys. The system margin
reduces every line's torques to the first line listed by virtual work: an ideal loop's
forces are internal and do no work, so at each row
    D_sys = sum_j D_j |w_j / w_1|,  R_sys = sum_j R_j |w_j / w_1|,  TM_sys = D_sys / R_sys,
w_j the deployment rate of line j in the run (a quasi-static TM run: the rates its motions
impose, which the loops' ratios fix), D_j and R_j the line's driving and factored resistive
sums of eq. 2.1 (N*m); the restart sums likewise. Undefined (NaN) where the first line is at
rest. The loops' own losses are not counted: give them as contributors if they matter.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["SYSTEM_LINE", "reduced_to_first"]

SYSTEM_LINE = "system"  # the name of the system margin's columns and summary entry


def reduced_to_first(
    sums: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], rates: Sequence[np.ndarray]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(driving, resistive, restart resistive) of all lines about the first (N*m, per row):
    each line's (D, R, R_restart) weighted by |rate / rate of the first line|."""
    first = np.abs(rates[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        weights = [np.where(first > 0.0, np.abs(r) / first, np.nan) for r in rates]
    driving, resistive, restart = (
        sum((w * line[k] for w, line in zip(weights, sums, strict=True)), np.zeros_like(first))
        for k in range(3)
    )
    return driving, resistive, restart
