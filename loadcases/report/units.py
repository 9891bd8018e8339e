"""Report units (SPEC 1.4 `report.units`): the set's workbook, envelope plots and envelope
tables show each physical kind in the unit the set names (`{force: kN, torque: N*m,
angle: deg, length: mm}`); CSV and summary files stay SI.

The report's data are converted copies, made once after the envelope, factors and margins are
computed in SI (factors and margins are ratios: they do not change; times of extremes stay in
s unless `time` is named). A column's kind comes from its SI unit text (`N` force, `N*m`
torque, `rad` angle ...; `loadcases.foundation.units.REPORT_KINDS`); a column of a kind the
report does not name, or of no known kind, stays SI.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from loadcases.foundation.number_text import SIGNED_NUMBER
from loadcases.foundation.units import REPORT_KINDS, to_si
from loadcases.report.curves import EnvelopeCurve
from loadcases.report.envelope import EnvelopeRow
from loadcases.report.loads_matrix import LoadsMatrix
from loadcases.report.peaks import RunPeak
from loadcases.results.files import TIME_COLUMN
from loadcases.results.saved import SavedRun

if TYPE_CHECKING:
    from loadcases.report.workbook import WorkbookData

__all__ = ["ReportUnits"]

_VALUE_FIELDS = (
    "max",
    "min",
    "abs_max",
    "ultimate_max",
    "ultimate_min",
    "allowable_max",
    "allowable_min",
    "limit_allowable_max",
    "limit_allowable_min",
)
_CONCURRENT = re.compile(rf"([A-Za-z_]\w*)=({SIGNED_NUMBER}|nan|-?inf)")


@dataclasses.dataclass(frozen=True)
class ReportUnits:
    """Per SI unit text: (report unit text, SI value of one report unit)."""

    table: dict[str, tuple[str, float]] = dataclasses.field(default_factory=dict)

    @classmethod
    def of(cls, units: Mapping[str, str] | None) -> ReportUnits:
        """From a checked `report.units` mapping {kind: unit} (SI when empty)."""
        si_of = REPORT_KINDS
        return cls({si_of[k]: (u, to_si(f"1 {u}", k)) for k, u in (units or {}).items()})

    @classmethod
    def parse(cls, texts: list[str]) -> ReportUnits:
        """From `KIND=UNIT` texts (`force=kN`, `angle=deg`; `loads plot --units`); ValueError
        naming the first text that is not a known kind with a unit of its dimension."""
        units = {}
        for text in texts:
            kind, equals, unit = (part.strip() for part in text.partition("="))
            if not equals or kind not in REPORT_KINDS or not unit:
                raise ValueError(
                    f"--units {text!r}: expected KIND=UNIT with KIND one of "
                    + ", ".join(REPORT_KINDS)
                )
            try:
                to_si(f"1 {unit}", kind)
            except ValueError as error:
                raise ValueError(f"--units {text!r}: {error}") from None
            units[kind] = unit
        return cls.of(units)

    def __bool__(self) -> bool:
        return bool(self.table)

    def unit(self, si_unit: str | None) -> str | None:
        """The unit the report shows a column of SI unit `si_unit` in."""
        return self.table[si_unit][0] if si_unit in self.table else si_unit

    def scale(self, si_unit: str | None) -> float:
        """SI value of one report unit (divide an SI value by it)."""
        return self.table[si_unit][1] if si_unit in self.table else 1.0

    def value(self, value: float | None, si_unit: str | None) -> float | None:
        return None if value is None else value / self.scale(si_unit)

    def array(self, values: np.ndarray, si_unit: str | None) -> np.ndarray:
        return np.asarray(values, dtype=float) / self.scale(si_unit)

    def concurrent(self, text: str | None, request: str, units: Mapping[str, str]) -> str | None:
        """`fy=1234; fz=-5` with each number in its component's report unit (%g)."""
        if not text or not self:
            return text

        def convert(match: re.Match[str]) -> str:
            si_unit = units.get(f"{request}.{match.group(1)}")
            return f"{match.group(1)}={float(match.group(2)) / self.scale(si_unit):g}"

        return _CONCURRENT.sub(convert, text)

    def row(
        self, row: EnvelopeRow, units: Mapping[str, str], abscissa_units: Mapping[str, str]
    ) -> EnvelopeRow:
        """An envelope row in report units; `units` {column: SI unit}, `abscissa_units`
        {run: SI unit of its abscissa}."""
        si_unit = row.unit
        changes: dict[str, Any] = {f: self.value(getattr(row, f), si_unit) for f in _VALUE_FIELDS}
        changes["unit"] = self.unit(si_unit)
        request = row.column.rsplit(".", 1)[0]
        for side in ("max", "min"):
            run = getattr(row, f"{side}_run") or ""
            changes[f"{side}_abscissa"] = self.value(
                getattr(row, f"{side}_abscissa"), abscissa_units.get(run)
            )
            changes[f"{side}_time"] = self.value(getattr(row, f"{side}_time"), "s")
            changes[f"{side}_concurrent"] = self.concurrent(
                getattr(row, f"{side}_concurrent"), request, units
            )
        return dataclasses.replace(row, **changes)

    def run(self, run: SavedRun) -> SavedRun:
        """A run's time histories in report units (the time column too if `time` is named)."""
        channels = {c: self.array(v, run.units.get(c)) for c, v in run.channels.items()}
        units = {c: self.unit(u) or "" for c, u in run.units.items()}
        units[TIME_COLUMN] = self.unit("s") or "s"
        return dataclasses.replace(
            run, time=self.array(run.time, "s"), channels=channels, units=units
        )

    def curve(self, curve: EnvelopeCurve) -> EnvelopeCurve:
        """A family's envelope curves in report units (abscissa included)."""
        units = curve.units
        return dataclasses.replace(
            curve,
            x=self.array(curve.x, curve.abscissa_unit),
            abscissa_unit=self.unit(curve.abscissa_unit) or "",
            upper={c: self.array(v, units.get(c)) for c, v in curve.upper.items()},
            lower={c: self.array(v, units.get(c)) for c, v in curve.lower.items()},
            units={c: self.unit(u) or "" for c, u in units.items()},
        )

    def peak(self, peak: RunPeak | None, unit: str, at_unit: str) -> RunPeak | None:
        """A run's peak in report units: values in `unit`'s, abscissae in `at_unit`'s."""
        if peak is None:
            return None
        changes: dict[str, Any] = {}
        for side in ("max", "min"):
            changes[side] = self.value(getattr(peak, side), unit)
            changes[f"{side}_time"] = self.value(getattr(peak, f"{side}_time"), "s")
            changes[f"{side}_abscissa"] = self.value(getattr(peak, f"{side}_abscissa"), at_unit)
        return dataclasses.replace(peak, **changes)

    def matrix(self, matrix: LoadsMatrix) -> LoadsMatrix:
        """The loads matrix in report units (where peaks are: abscissa or time too)."""
        at_units = [unit for _, unit in matrix.at]
        rows = [
            dataclasses.replace(
                row,
                unit=self.unit(row.unit) or "",
                cells=[self.peak(c, row.unit, u) for c, u in zip(row.cells, at_units)],
            )
            for row in matrix.rows
        ]
        at = [(name, self.unit(unit) or "") for name, unit in matrix.at]
        return dataclasses.replace(matrix, rows=rows, at=at)

    def workbook_data(self, data: WorkbookData) -> WorkbookData:
        """The workbook's rows, runs and curves in report units, the units on Provenance."""
        if not self:
            return data
        units = {c: u for run in data.runs for c, u in run.units.items()}
        abscissa = {run.name: run.units.get("abscissa.value", "") for run in data.runs}
        shown = ", ".join(f"{si} -> {unit}" for si, (unit, _) in self.table.items())
        return dataclasses.replace(
            data,
            rows=[self.row(r, units, abscissa) for r in data.rows],
            runs=[self.run(r) for r in data.runs],
            curves=[self.curve(c) for c in data.curves],
            matrix=None if data.matrix is None else self.matrix(data.matrix),
            settings=[*data.settings, ("report units", shown)],
        )
