"""Annotated field types that turn YAML numbers and quantity texts into SI floats.

Validation context: `{"units": {"length": "mm", ...}}` (the file's `units:` header) gives the
unit of bare numbers of the five file-unit kinds; every other bare number is SI.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, PlainValidator, ValidationInfo
from pydantic_core import PydanticCustomError

from loadcases.foundation.number_text import SIGNED_NUMBER
from loadcases.foundation.units import (
    SIValue,
    UnitError,
    UnreadableError,
    finite,
    to_si,
    vector_to_si,
)

__all__ = [
    "SI_UNITS",
    "Angle",
    "AngularVelocity",
    "AnySI",
    "Damping",
    "Dimensionless",
    "Direction",
    "Expression",
    "Force",
    "ForceOrTorque",
    "Inertia",
    "Length",
    "Mass",
    "Name",
    "NamePair",
    "Position",
    "Pressure",
    "RawQuantity",
    "Stiffness",
    "Strict",
    "Time",
    "Torque",
    "TorsionalDamping",
    "TorsionalStiffness",
    "Values",
    "Velocity",
    "describe",
    "expression",
    "quantity",
    "vector",
]

SI_UNITS: dict[str, str] = {
    "length": "m",
    "angle": "rad",
    "mass": "kg",
    "time": "s",
    "force": "N",
    "torque": "N*m",
    "inertia": "kg*m^2",
    "velocity": "m/s",
    "angular_velocity": "rad/s",
    "acceleration": "m/s^2",
    "angular_acceleration": "rad/s^2",
    "stiffness": "N/m",
    "torsional_stiffness": "N*m/rad",
    "damping": "N*s/m",
    "torsional_damping": "N*m*s/rad",
    "pressure": "Pa",
    "area": "m^2",
    "volume": "m^3",
    "density": "kg/m^3",
    "second_moment": "m^4",
    "frequency": "Hz",
    "flow": "m^3/s",
    "leakage": "m^3/(s*Pa)",
    "current": "A",
    "current_gain": "A/m",
    "integral_gain": "A/(m*s)",
    "dimensionless": "1",
    "any": "SI",
    "force_or_torque": "N or N*m",
}
_FILE_KINDS = ("length", "angle", "mass", "time", "force")
# In an expression field a quantity text needs a space before its unit ("100 N"): "2t"
# is then a malformed expression, not 2 tonnes.
_EXPRESSION_QUANTITY = re.compile(rf"^ *{SIGNED_NUMBER} +[A-Za-z°%µ]")


class Strict(BaseModel):
    """Base of every input model: unknown keys are errors, validated models are frozen."""

    # defer_build: a model's validator is built when it first validates (or its JSON
    # schema is asked for), not when its class is made: `loads validate` builds the few
    # models at the top of a file's tree (which take in the rest) instead of all 75 at
    # import, each with a copy of its subtree (about 35 ms of the command's 0.55 s)
    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)


def describe(text: str, dimension: str) -> str:
    """Field description with its unit: `text [length: m; bare numbers in units.length]`."""
    bare = f"bare numbers in units.{dimension}" if dimension in _FILE_KINDS else "bare numbers SI"
    return f"{text} [{dimension}: {SI_UNITS[dimension]}; {bare}]"


def _file_units(info: ValidationInfo) -> Mapping[str, str] | None:
    """The file's `units:` header from the validation context."""
    return (info.context or {}).get("units")


def _fail(error: UnitError) -> PydanticCustomError:
    return PydanticCustomError("quantity", str(error))


def _scalar(dimension: str) -> Callable[[Any, ValidationInfo], float]:
    def convert(value: Any, info: ValidationInfo) -> float:
        if dimension == "force_or_torque":
            return _force_or_torque(value)
        try:
            return to_si(value, dimension, _file_units(info))
        except UnitError as error:
            raise _fail(error) from None

    return convert


def _force_or_torque(value: Any) -> float:
    """A force (N) or torque (N*m) as SI; bare numbers SI (the joint type decides which)."""
    try:
        return to_si(value, "force")
    except UnitError:
        try:
            return to_si(value, "torque")
        except UnitError as error:
            raise PydanticCustomError(
                "quantity", str(error).replace("expected a torque", "expected a force or a torque")
            ) from None


def quantity(dimension: str) -> Any:
    """Annotated float type: a number or quantity text of `dimension`, validated to SI."""
    return Annotated[float, BeforeValidator(_scalar(dimension), json_schema_input_type=float | str)]


def vector(dimension: str, size: int | None = 3) -> Any:
    """Annotated tuple type: `size` components (any count if None) of `dimension`, in SI."""

    def convert(value: Any, info: ValidationInfo) -> tuple[float, ...]:
        try:
            return vector_to_si(value, dimension, _file_units(info), size)
        except UnitError as error:
            raise _fail(error) from None

    inner = tuple[float, float, float] if size == 3 else tuple[float, ...]
    return Annotated[
        inner, BeforeValidator(convert, json_schema_input_type=list[float | str] | str)
    ]


def _inertia(value: Any, info: ValidationInfo) -> tuple[float, ...]:
    try:
        result = vector_to_si(value, "inertia", None, None)
    except UnitError as error:
        raise _fail(error) from None
    if len(result) not in (3, 6):
        raise PydanticCustomError(
            "quantity",
            "expected 3 values [Ixx, Iyy, Izz] or 6 [Ixx, Iyy, Izz, Ixy, Ixz, Iyz], got {n}",
            {"n": len(result)},
        )
    return result


def expression(dimension: str = "any") -> Any:
    """Annotated str type of an expression: numbers become their text, and a plain quantity
    text such as "100 N" becomes its SI number (checked against `dimension`)."""

    def convert(value: Any) -> str:
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise PydanticCustomError("expression", "expected an expression text or a number")
        if not isinstance(value, str):
            try:
                if isinstance(value, SIValue):  # a parameter put in place of its name
                    return repr(to_si(value, dimension))
                return repr(finite(float(value), value))
            except UnitError as error:
                raise _fail(error) from None
        if not value.strip():
            raise PydanticCustomError("expression", "empty expression")
        if _EXPRESSION_QUANTITY.match(value):
            try:
                return repr(to_si(value, dimension))
            except UnreadableError:
                pass  # no quantity: the expression checks say what is wrong with it
            except UnitError as error:
                raise _fail(error) from None
        return value.strip()

    return Annotated[str, BeforeValidator(convert, json_schema_input_type=float | str)]


def _raw(value: Any) -> float | str:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise PydanticCustomError("quantity", "expected a number or a quantity text")
    # a parameter put in place keeps its SI marker: no file unit applies to it later
    return value if isinstance(value, (str, SIValue)) else float(value)


Length = quantity("length")
Angle = quantity("angle")
Mass = quantity("mass")
Time = quantity("time")
Force = quantity("force")
Torque = quantity("torque")
Velocity = quantity("velocity")
AngularVelocity = quantity("angular_velocity")
Stiffness = quantity("stiffness")
TorsionalStiffness = quantity("torsional_stiffness")
Damping = quantity("damping")
TorsionalDamping = quantity("torsional_damping")
Pressure = quantity("pressure")
Dimensionless = quantity("dimensionless")
AnySI = quantity("any")
ForceOrTorque = quantity("force_or_torque")
Position = vector("length")
Direction = vector("dimensionless")
Values = vector("any", None)
Inertia = Annotated[
    tuple[float, ...], BeforeValidator(_inertia, json_schema_input_type=list[float | str] | str)
]
Expression = expression()
# A joint coordinate or rate whose dimension depends on the joint type: converted by the loader.
# (PlainValidator: the value as `_raw` gives it, so a parameter's SIValue stays one)
RawQuantity = Annotated[float | str, PlainValidator(_raw, json_schema_input_type=float | str)]
Name = Annotated[str, Field(min_length=1)]
NamePair = tuple[Name, Name]
