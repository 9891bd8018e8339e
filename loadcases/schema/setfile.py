"""Pydantic models of a load-case set (`*.set.yaml`, SPEC 1.4): values in SI floats."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BeforeValidator, Field

from loadcases.schema.mechanism import FileUnits, unit_name
from loadcases.schema.types import AnySI, Dimensionless, Strict
from loadcases.units import REPORT_KINDS

__all__ = ["Allowable", "Report", "ReportUnits", "SetModel"]


def _as_list(value: Any) -> Any:
    return [value] if isinstance(value, str) else value


class Allowable(Strict):
    """Limits of a result column [SI, same unit as the column]."""

    max: AnySI | None = None
    min: AnySI | None = None


def _report_unit(kind: str) -> Any:
    return unit_name(
        kind,
        f"unit in which the report shows {kind.replace('_', ' ')} values "
        f"(SI unit {REPORT_KINDS[kind]}), e.g. {_EXAMPLES.get(kind, '')}",
    )


_EXAMPLES = {
    "force": "kN",
    "torque": "N*m",
    "angle": "deg",
    "length": "mm",
    "angular_velocity": "deg/s",
    "velocity": "mm/s",
    "pressure": "bar",
}


class ReportUnits(Strict):
    """`report.units` (SPEC 1.4): the units in which the workbook, the plots and the envelope
    tables show each physical kind; CSV and summary files stay SI."""

    force: _report_unit("force") = None
    torque: _report_unit("torque") = None
    angle: _report_unit("angle") = None
    length: _report_unit("length") = None
    velocity: _report_unit("velocity") = None
    angular_velocity: _report_unit("angular_velocity") = None
    acceleration: _report_unit("acceleration") = None
    angular_acceleration: _report_unit("angular_acceleration") = None
    time: _report_unit("time") = None
    mass: _report_unit("mass") = None
    pressure: _report_unit("pressure") = None
    stiffness: _report_unit("stiffness") = None
    torsional_stiffness: _report_unit("torsional_stiffness") = None
    frequency: _report_unit("frequency") = None

    def given(self) -> dict[str, str]:
        """{kind: unit} of the kinds given."""
        return {k: v for k, v in self.model_dump().items() if v is not None}


class Report(Strict):
    """Workbook report: `template` and `output` relative to the set file; `units` of the
    report (workbook, plots, envelope tables)."""

    template: str | None = None
    output: str = Field(min_length=1)
    units: ReportUnits = Field(default_factory=ReportUnits)


class SetModel(Strict):
    """A load-case set: cases, sweeps, factors, allowables and report."""

    set: str = Field(min_length=1, description="set name (results go to DIR/SET/)")
    units: FileUnits = Field(default_factory=FileUnits)
    cases: Annotated[list[str], BeforeValidator(_as_list)] = Field(
        min_length=1, description="case files or glob patterns relative to this file"
    )
    parameters: dict[str, AnySI] = Field(default_factory=dict, description="overrides [SI]")
    sweep: dict[str, list[AnySI]] = Field(
        default_factory=dict, description="cartesian product over parameters [SI]"
    )
    zip: dict[str, list[AnySI]] = Field(
        default_factory=dict, description="parameters varied together (lists of equal length) [SI]"
    )
    factors: dict[str, Dimensionless] = Field(
        default_factory=dict,
        description="ultimate: factor on every load column (N, N*m); "
        "any other key: fitting factor of a request "
        "REQ or a column REQ.COMP, multiplied in; "
        "e.g. {ultimate: 1.5, rod_end: 1.15}",
    )
    allowables: dict[str, Allowable] = Field(
        default_factory=dict, description="by result column REQUEST.COMPONENT"
    )
    report: Report | None = None
