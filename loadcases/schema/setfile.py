"""Pydantic models of a load-case set (`*.set.yaml`, SPEC 1.4): values in SI floats."""

from __future__ import annotations

from fnmatch import fnmatchcase
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.foundation.noise_floor import NOISE_FLOOR
from loadcases.foundation.units import REPORT_KINDS
from loadcases.schema.mechanism import FileUnits, unit_name
from loadcases.schema.types import AnySI, Dimensionless, Direction, Position, Strict, Time

__all__ = [
    "Allowable",
    "Limits",
    "MassProperties",
    "NamedAxis",
    "ReferenceCurve",
    "Report",
    "ReportUnits",
    "SetModel",
    "matches",
]


def matches(name: str, pattern: str) -> bool:
    """A `case_factors` glob: `*` and `?` are the wildcards, brackets are literal (run
    names hold `[p=v]`)."""
    return fnmatchcase(name, pattern.replace("[", "[[]"))


def _as_list(value: Any) -> Any:
    return [value] if isinstance(value, str) else value


def _symmetric(value: Any) -> Any:
    """`limit: 20 kN` -> {max: 20 kN, min: -20 kN} (a magnitude, both ways)."""
    if isinstance(value, (str, int, float)) and not isinstance(value, bool):
        text = str(value).strip()
        return {"max": value, "min": text[1:] if text.startswith("-") else f"-{text}"}
    return value


class Limits(Strict):
    """Allowable loads of a result column on each side [SI, unit of the column]; `min` is
    given negative (compression -8 kN)."""

    max: AnySI | None = None
    min: AnySI | None = None


SideLimits = Annotated[Limits, BeforeValidator(_symmetric)]


class Allowable(Strict):
    """Allowables of a result column [SI, same unit as the column]: `max`/`min` (ultimate,
    against factor x load), or `ultimate:` and `limit:` (each {max, min} or one magnitude)."""

    max: AnySI | None = None
    min: AnySI | None = None
    ultimate: SideLimits | None = Field(
        None,
        description="ultimate allowables (against ultimate factor x load): {max, min} or "
        "a magnitude for both sides; same as max/min",
    )
    limit: SideLimits | None = Field(
        None,
        description="limit allowables (against case x fitting factor x load, without the "
        "ultimate factor): {max, min} or a magnitude for both sides",
    )

    @model_validator(mode="after")
    def _one_ultimate(self) -> Allowable:
        if self.ultimate is not None and (self.max is not None or self.min is not None):
            raise PydanticCustomError(
                "allowable", "give 'ultimate' or 'max'/'min', not both (they are the same)"
            )
        return self

    def ultimate_limits(self) -> tuple[float | None, float | None]:
        """(max, min) ultimate allowables."""
        if self.ultimate is not None:
            return self.ultimate.max, self.ultimate.min
        return self.max, self.min

    def limit_limits(self) -> tuple[float | None, float | None]:
        """(max, min) limit allowables."""
        return (None, None) if self.limit is None else (self.limit.max, self.limit.min)


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
    "energy": "kJ",
    "flow": "L/min",
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
    energy: _report_unit("energy") = None
    flow: _report_unit("flow") = None

    def given(self) -> dict[str, str]:
        """{kind: unit} of the kinds given."""
        return {k: v for k, v in self.model_dump().items() if v is not None}


class Report(Strict):
    """Workbook report: `template` and `output` relative to the set file; `units` of the
    report (workbook, plots, envelope tables)."""

    template: str | None = None
    output: str = Field(min_length=1)
    units: ReportUnits = Field(default_factory=ReportUnits)
    histories: Literal["all", "envelope", "none"] = Field(
        "envelope",
        description="time-history sheets: all (every output row), envelope (the rows the "
        "charts need, every column's max and min rows kept exactly) or none",
    )
    noise_floor: float = Field(
        NOISE_FLOOR,
        ge=0.0,
        lt=1.0,
        description="a component whose peak is below this fraction of its request's (or the "
        "set's, same unit) largest peak is ~0: no factor, no margin",
    )
    matrix: Literal["runs", "families"] = Field(
        "runs", description="columns of the loads matrix: one per run or per family (case)"
    )
    digits: int = Field(
        4,
        ge=2,
        le=15,
        description="significant digits the workbook shows of each row's or column's peak "
        "(the cells keep the full value)",
    )
    charts: Annotated[list[str], BeforeValidator(_as_list)] = Field(
        default_factory=list,
        description="requests (each of their columns) or columns REQUEST.COMPONENT charted "
        "and plotted besides each family's largest loads, e.g. a joint friction or energy",
    )


class Comparison(Strict):
    """`comparisons: NAME:` the peak of chosen result columns in each of `runs` beside the
    `reference` run's, and their ratio (workbook sheet `Comparison`, `comparisons.csv`)."""

    reference: str = Field(min_length=1, description="the reference run: CASE or CASE[p=v,...]")
    runs: Annotated[list[str], BeforeValidator(_as_list)] = Field(
        min_length=1, description="the runs compared with the reference"
    )
    columns: Annotated[list[str], BeforeValidator(_as_list)] = Field(
        min_length=1,
        description="result columns REQUEST.COMPONENT, or REQUEST for all its components; "
        "'REF = RUN' (or 'REF = -RUN', negated): the reference's REF beside the runs' RUN",
    )


class ReferenceCurve(Strict):
    """`curves: NAME:` external curves (a spreadsheet's, a rig's) against a case's abscissa:
    overlaid on the runs' curves, with their differences (`reference-curves.csv`, workbook
    sheet `Reference curves`). The CSV's first column is the abscissa; every header is
    `NAME [unit]`."""

    file: str = Field(min_length=1, description="CSV file relative to this set file")
    case: str = Field(
        min_length=1, description="the case (every run of it) or one run CASE[p=v,...]"
    )
    x: str | None = Field(
        None, description="the case's abscissa expression, as the case writes it (a check)"
    )
    columns: dict[str, str] = Field(
        min_length=1,
        description="{result column REQUEST.COMPONENT: CSV header 'NAME [unit]'}",
    )
    label: str = Field("reference", min_length=1, description="legend of the curves")


class NamedAxis(Strict):
    """An axis fixed in space: a name for the report, a point on it and its direction
    (global axes)."""

    name: str = Field(min_length=1, description="the axis' name in the report (hinge line)")
    at: Position = Field(description="a point of the axis, global frame [length]")
    direction: Direction = Field(description="its direction, global frame [dimensionless]")

    @model_validator(mode="after")
    def _some_direction(self) -> NamedAxis:
        if not any(self.direction):
            raise PydanticCustomError("axis", "the axis direction must not be zero")
        return self


class MassProperties(Strict):
    """`mass_properties:` every rigid body's mass, centre of mass and inertia about its
    centre and about `axis`, and the assembly's totals, with the bodies where the run of
    `case` puts them at time `at` (sheet `Mass properties`, `mass-properties.csv`)."""

    case: str = Field(min_length=1, description="the case whose configuration is used")
    at: Time = Field(0.0, description="time of the configuration [time] (default 0: the start)")
    axis: NamedAxis | None = Field(None, description="an axis to give the inertias about")


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
    case_factors: dict[str, Dimensionless] = Field(
        default_factory=dict,
        description="factor of the runs whose name or case (family) matches a glob pattern, "
        "multiplied into ultimate x fitting (every matching pattern), e.g. {'freefall-*': 1.25}",
    )
    allowables: dict[str, Allowable] = Field(
        default_factory=dict, description="by result column REQUEST.COMPONENT"
    )
    comparisons: dict[str, Comparison] = Field(
        default_factory=dict,
        description="peaks of chosen columns run by run against a reference run, with ratios",
    )
    curves: dict[str, ReferenceCurve] = Field(
        default_factory=dict,
        description="reference curves (CSV, units in the header) overlaid on a case's "
        "curves, with the differences tabulated",
    )
    mass_properties: MassProperties | None = Field(
        None, description="mass properties of the bodies in a chosen configuration"
    )
    report: Report | None = None
