"""The seed's spreadsheet method (thesis seed 000: the MS Excel "analytical" calculation) for
the door library's reference curves: lever-ratio statics of the handles, rods and lift
links by hand, without the engine. Run it from anywhere:

    python loadcases/library/door/reference/spreadsheet.py

It writes, next to itself, the CSV files door_reference.set.yaml and door.set.yaml overlay:
- jam_outer_handle.csv: jam at the outer handle, 1334 N on the inner handle grip (200 mm),
  no gravity (the spreadsheet neglected the weight, thesis 5.1.2): P2P6 = F r / (arm of the
  rod line about the inner handle pivot); P7P10 by the spreadsheet chain P7P10 = P2P6 x
  (P6 arm / P10 arm about the latch axis), which is 1 here (P6 and P10 at one height);
- lifting_outer.csv: lifting with the outer handle, no pressure: the latch shaft torque that
  lifts the door's weight through the lift links (virtual work, T = m g dh/dlatch), through
  the gearbox (ratio 2) to the handle, and rod P7P10 = T / (arm of P7P10 about the gearbox
  output axis). Seal, Stop1 and guide friction and the CB spring are not in it.

Geometry (door.mech.yaml, door axes, mm): every handle and shaft turns about -x; a crank
from its pivot to its rod end is (dy, dz) = (34.4, 49.2) at latch 0 (60 mm, 55 deg from
normal to the rods, which are vertical, 400 mm long, and stay so: the cranks are
parallel); lower lift links 30 mm at 55 deg above horizontal at latch 0, the door hanging
from them; the latch turns them by its own angle.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

HERE = Path(__file__).resolve().parent
CRANK = (34.4, 49.2)  # mm (dy, dz) of every crank at latch 0 (door.mech.yaml p2, p6, p7, p10)
GRIP_INNER = 200.0  # mm, inner handle grip radius (lever_inner)
JAM_LOAD = 1334.0  # N, ultimate handle load, normal to the handle arm (thesis 4.2)
LINK = 30.0  # mm, lower lift link length (door.mech.yaml: pivot to pin)
LINK_ANGLE = 55.0  # deg above horizontal at latch 0
LIFTED_MASS = 124.0  # kg: door 120 + the latch shaft, handles, rods and gearbox on it
G = 9.81  # m/s^2
GEAR = 2.0  # gearbox: output (latch) angle / input (outer handle) angle


def crank_arm(latch_deg: float) -> float:
    """Arm (mm) of a vertical rod line about its crank's pivot, the crank turned by the
    latch angle about -x: |dy| of the turned crank."""
    a = math.radians(latch_deg)
    return abs(CRANK[0] * math.cos(a) + CRANK[1] * math.sin(a))


def jam_rows(angles: list[float]) -> list[tuple[float, float, float]]:
    """(latch deg, P2P6 N, P7P10 N) of the outer-handle jam, no gravity."""
    rows = []
    for angle in angles:
        p2p6 = JAM_LOAD * GRIP_INNER / crank_arm(angle)
        p7p10 = p2p6 * crank_arm(angle) / crank_arm(angle)  # P6 arm / P10 arm = 1
        rows.append((angle, p2p6, p7p10))
    return rows


def lifting_rows(angles: list[float]) -> list[tuple[float, float, float]]:
    """(latch deg, outer handle torque N*m, P7P10 N) lifting the door's weight only."""
    rows = []
    for angle in angles:
        dh = LINK * math.cos(math.radians(LINK_ANGLE - angle)) / 1000.0  # m per rad of latch
        latch_torque = LIFTED_MASS * G * dh  # N*m
        handle_torque = GEAR * latch_torque  # the handle turns half as far
        rows.append((angle, handle_torque, latch_torque / (crank_arm(angle) / 1000.0)))
    return rows


def write(name: str, header: list[str], rows: Sequence[tuple[float, ...]]) -> Path:
    path = HERE / name
    with open(path, "w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(header)
        writer.writerows([[f"{v:.6g}" for v in row] for row in rows])
    return path


def main() -> None:
    angles = [float(a) for a in range(0, 111, 5)]
    write("jam_outer_handle.csv", ["latch angle [deg]", "P2P6 [N]", "P7P10 [N]"], jam_rows(angles))
    write(
        "lifting_outer.csv",
        ["latch angle [deg]", "outer handle torque [N*m]", "P7P10 [N]"],
        lifting_rows(angles),
    )


if __name__ == "__main__":
    main()
