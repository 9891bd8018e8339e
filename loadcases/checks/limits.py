"""Joint limits of a mechanism (`limits:`) read and checked in one place: the joint has the
coordinate stopped, `min` < `max`, `depth` > 0. `loads validate` reports the problems at
their keys; the builder reads the values through the same function."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.units import UnitError, to_si
from loadcases.schema import MechanismModel
from loadcases.yamlfiles.source import Locator
from mechlib.elements.joint_limit import LIMIT_JOINTS

__all__ = ["LimitValues", "check_limits", "read_limit"]

_DIMENSION = {"angle": "angle", "travel": "length"}
_SI_UNIT = {"angle": "rad", "travel": "m"}


@dataclass(frozen=True)
class LimitValues:
    """A limit in SI: its coordinate ("angle" or "travel"), `lower` and `upper` (rad or m,
    None: no stop that side), `depth` (rad or m, None: not given)."""

    coordinate: str
    lower: float | None
    upper: float | None
    depth: float | None


def _coordinate(limit, joint_type: str) -> tuple[str | None, tuple[str, str] | None]:
    """The coordinate stopped, or (None, (key, problem))."""
    coordinates = LIMIT_JOINTS.get(joint_type)
    if coordinates is None:
        *others, last = LIMIT_JOINTS
        kinds = f"{', '.join(others)} or {last}"
        problem = f"joint '{limit.joint}' is {joint_type}; a limit needs a {kinds} joint"
        return None, ("joint", problem)
    coordinate = limit.coordinate or coordinates[0]
    if coordinate not in coordinates:
        problem = f"joint '{limit.joint}' is {joint_type}: it has no {coordinate} coordinate"
        return None, ("coordinate", problem)
    return coordinate, None


def read_limit(
    limit, joint_type: str, units: dict[str, str], parameters: Mapping[str, float]
) -> tuple[LimitValues | None, list[tuple[str, str]]]:
    """The limit's values in SI (bare numbers in the file's `units`, a parameter name its
    value) and the problems found as (key under the limit, message); values None when the
    limit cannot be built. A parameter without a value here (a case's) is left unchecked."""
    coordinate, problem = _coordinate(limit, joint_type)
    if coordinate is None:
        return None, [problem] if problem else []
    problems: list[tuple[str, str]] = []
    values: dict[str, float | None] = {}
    for key in ("min", "max", "depth"):
        raw = getattr(limit, key)
        values[key] = None
        if raw is None:
            continue
        if isinstance(raw, str) and raw.strip() in parameters:
            values[key] = float(parameters[raw.strip()])
            continue
        try:
            values[key] = to_si(raw, _DIMENSION[coordinate], units)
        except UnitError as error:
            problems.append((key, str(error)))
    lower, upper, depth = values["min"], values["max"], values["depth"]
    if lower is not None and upper is not None and lower >= upper:
        si = _SI_UNIT[coordinate]
        problems.append(
            (
                "max",
                f"must be > min, got max {limit.max} <= min {limit.min} "
                f"({upper:g} <= {lower:g} {si})",
            )
        )
    if depth is not None and depth <= 0.0:
        problems.append(("depth", f"must be > 0, got {limit.depth}"))
    if problems:
        return None, problems
    return LimitValues(coordinate, lower, upper, depth), []


def check_limits(model: MechanismModel, at: Locator) -> list[Diagnostic]:
    """Every problem of the mechanism's limits at its key (unknown joints: the reference
    checks)."""
    found = []
    units = model.units.as_dict()
    for name, limit in model.limits.items():
        joint = model.joints.get(limit.joint)
        if joint is None:
            continue
        _, problems = read_limit(limit, joint.type, units, model.parameters)
        found += [at.diagnostic(("limits", name, key), message) for key, message in problems]
    return found
