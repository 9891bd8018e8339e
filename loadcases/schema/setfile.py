"""Pydantic models of a load-case set (`*.set.yaml`, SPEC 1.4): values in SI floats."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BeforeValidator, Field

from loadcases.schema.mechanism import FileUnits
from loadcases.schema.types import AnySI, Dimensionless, Strict

__all__ = ["Allowable", "Report", "SetModel"]


def _as_list(value: Any) -> Any:
    return [value] if isinstance(value, str) else value


class Allowable(Strict):
    """Limits of a result column [SI, same unit as the column]."""

    max: AnySI | None = None
    min: AnySI | None = None


class Report(Strict):
    """Workbook report: `template` and `output` relative to the set file."""

    template: str | None = None
    output: str = Field(min_length=1)


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
