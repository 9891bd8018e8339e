"""Polar data of clearance joints and their wear maps (seed 004 ch. 5, figures 5.4-5.5).

A clearance joint's `polar` request (loadcases.build.contacts) gives the columns
`REQ.radial` (m, eccentricity normal to the polar axis), `REQ.axial` (m), `REQ.angle`
(rad, polar angle of the eccentricity: where the ball presses on the socket),
`REQ.clearance` (m), `REQ.normal` (N), `REQ.wear` (W: the wear indicator F_N * v_rel) and
`REQ.wear_work` (J: its time integral, computed by the engine). The wear map is the wear
work accumulated per angular sector: each output interval's increment of `wear_work` goes
to the sector of the interval's mean polar angle, so the sectors add up to the run's wear
work exactly. `wear_map_sheet` writes the maps of a set's runs as a workbook sheet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from loadcases.foundation.units import UnitError, to_si
from loadcases.results.saved import SavedRun

__all__ = [
    "POLAR_COMPONENTS",
    "SECTORS",
    "WEAR_SHEET",
    "PolarData",
    "polar_data",
    "polar_requests",
    "wear_map_sheet",
    "wear_sectors",
]

POLAR_COMPONENTS = ("radial", "axial", "angle", "clearance", "normal", "wear", "wear_work")
"""Components of a `polar` request, in column order."""
SECTORS = 36
"""Sectors of a wear map (10 deg each), the first centred on polar angle 0."""
WEAR_SHEET = "Wear map"


@dataclass(frozen=True)
class PolarData:
    """One run's polar columns (SI: m, rad, N, W, J), each (n,), and its time (s)."""

    run: str
    request: str
    time: np.ndarray
    radial: np.ndarray
    axial: np.ndarray
    angle: np.ndarray
    clearance: float
    normal: np.ndarray
    wear: np.ndarray
    wear_work: np.ndarray

    def sectors(self, count: int = SECTORS) -> np.ndarray:
        """Wear work (J) per angular sector (count,), see `wear_sectors`."""
        return wear_sectors(self.angle, self.wear_work, count)


def polar_requests(run: SavedRun) -> list[str]:
    """Names of the run's `polar` requests (every component column present)."""
    names = {c.rsplit(".", 1)[0] for c in run.channels if c.endswith(".wear_work")}
    return sorted(n for n in names if all(f"{n}.{c}" in run.channels for c in POLAR_COMPONENTS))


def _si(run: SavedRun, column: str) -> np.ndarray:
    """A column in SI (a set's report units may have converted it, e.g. rad -> deg)."""
    values = np.asarray(run.channels[column], float)
    unit = run.units.get(column, "")
    try:
        factor = to_si(f"1 {unit}", "any") if unit else 1.0
    except UnitError:
        factor = 1.0
    return values * factor


def polar_data(run: SavedRun, request: str) -> PolarData:
    """The polar columns of `request` in `run` (ValueError if it has none)."""
    if request not in polar_requests(run):
        found = ", ".join(polar_requests(run)) or "none"
        raise ValueError(
            f"run {run.name}: no polar request '{request}' (columns {request}.radial ... "
            f"{request}.wear_work; polar requests found: {found})"
        )
    col = {c: _si(run, f"{request}.{c}") for c in POLAR_COMPONENTS}
    return PolarData(
        run.name,
        request,
        np.asarray(run.time, float),
        col["radial"],
        col["axial"],
        col["angle"],
        float(col["clearance"][0]),
        col["normal"],
        col["wear"],
        col["wear_work"],
    )


def wear_sectors(angle: np.ndarray, work: np.ndarray, count: int = SECTORS) -> np.ndarray:
    """Wear work (J) per sector (count,): sector k spans polar angles (k - 1/2, k + 1/2) *
    360 / count deg; the increment of `work` over each output interval goes to the sector
    of the interval's mean angle (the mean of the two unit vectors: angles wrap)."""
    angle, work = np.asarray(angle, float), np.asarray(work, float)
    if angle.size < 2:
        return np.zeros(count)
    mean = np.arctan2(
        np.sin(angle[:-1]) + np.sin(angle[1:]), np.cos(angle[:-1]) + np.cos(angle[1:])
    )
    width = 2.0 * math.pi / count
    index = np.floor(np.mod(mean + 0.5 * width, 2.0 * math.pi) / width).astype(int) % count
    return np.bincount(index, weights=np.diff(work), minlength=count)


def sector_titles(count: int = SECTORS) -> list[str]:
    """Column titles of the sectors: their centre angle in deg."""
    return [f"{k * 360 / count:g} deg [J]" for k in range(count)]


def wear_map_sheet(sheet: Any, runs: list[SavedRun]) -> int:
    """Fill `sheet` with one row per run and polar request: total wear work (J), peak
    normal force (N), peak wear indicator (W), the sector of most wear and the wear work
    per sector (J). Returns the number of rows written."""
    head = ["run", "request", "wear work [J]", "peak normal [N]", "peak wear [W]"]
    head += ["most wear at [deg]", *sector_titles()]
    for column, title in enumerate(head, start=1):
        sheet.cell(row=1, column=column, value=title).style = "loads header"
    row = 1
    for run in runs:
        for request in polar_requests(run):
            data = polar_data(run, request)
            sectors = data.sectors()
            values = [
                run.name,
                request,
                float(data.wear_work[-1] - data.wear_work[0]),
                float(data.normal.max()),
                float(data.wear.max()),
                float(np.argmax(sectors) * 360 / SECTORS),
                *map(float, sectors),
            ]
            row += 1
            for column, value in enumerate(values, start=1):
                sheet.cell(row=row, column=column, value=value)
    sheet.freeze_panes = "C2"
    sheet.column_dimensions["A"].width = 40
    return row - 1
