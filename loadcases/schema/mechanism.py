"""Pydantic models of a mechanism file (`*.mech.yaml`, SPEC 1.2): values in SI floats."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Discriminator, Field, Tag, model_validator
from pydantic_core import PydanticCustomError

from loadcases.foundation.units import FILE_UNIT_KINDS, UnitError, check_unit_name
from loadcases.schema.elements import Contact, ForceElement, Table
from loadcases.schema.flexible import Flexible
from loadcases.schema.forces_more import Limit
from loadcases.schema.types import (
    AnySI,
    Direction,
    Expression,
    Inertia,
    Length,
    Mass,
    Name,
    NamePair,
    Position,
    Strict,
    Time,
    describe,
    vector,
)
from mechlib.model.mechanism import JOINT_TYPES  # one list of joint types: the engine's

__all__ = [
    "COORDINATE_DIMENSION",
    "JOINT_TYPES",
    "AnyBody",
    "AxesJoint",
    "AxisJoint",
    "Body",
    "Coupler",
    "Event",
    "EventAction",
    "EventDelay",
    "FileUnits",
    "Fixed",
    "FlexibleBody",
    "Frame",
    "Joint",
    "MechanismModel",
    "NormalJoint",
    "Orientation",
    "Point",
    "PointOnCurve",
    "Screw",
    "Spherical",
]


def unit_name(kind: str, description: str) -> Any:
    """An optional unit name of `kind` (`mm`, `kN`, `deg/s`), checked at its key."""

    def check(value: Any) -> str:
        try:
            return check_unit_name(value, kind)
        except UnitError as error:
            raise PydanticCustomError("unit", str(error)) from None

    return Annotated[
        str | None, BeforeValidator(check), Field(default=None, description=description)
    ]


_FILE_EXAMPLES = {"length": "mm", "angle": "deg", "mass": "g", "time": "ms", "force": "kN"}


def _unit_name(kind: str) -> Any:
    return unit_name(kind, f"unit of bare {kind} numbers in this file, e.g. {_FILE_EXAMPLES[kind]}")


class FileUnits(Strict):
    """`units:` header: the unit of bare numbers of each kind in this file (default SI)."""

    length: _unit_name("length") = None
    angle: _unit_name("angle") = None
    mass: _unit_name("mass") = None
    time: _unit_name("time") = None
    force: _unit_name("force") = None

    def as_dict(self) -> dict[str, str]:
        """{kind: unit} of the kinds that are set."""
        return {k: getattr(self, k) for k in FILE_UNIT_KINDS if getattr(self, k)}


class Body(Strict):
    """A rigid body; `cm` and `inertia` in global axes at the design position."""

    mass: Mass = Field(description=describe("mass", "mass"))
    cm: Position = Field(description=describe("centre of mass, global frame", "length"))
    inertia: Inertia = Field(
        description="about the cm, global axes: [Ixx, Iyy, Izz] or "
        "[Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (Ixy = -integral of x*y dm) "
        "[inertia: kg*m^2, bare numbers always SI]"
    )


class FlexibleBody(Strict):
    """A flexible body: Craig-Bampton modes of a beam, grillage or plate; its mass properties
    come from its FE model."""

    flexible: Flexible


def _body_kind(value: Any) -> str:
    """`flexible` when the body has a `flexible:` key, else `rigid`."""
    has = "flexible" in value if isinstance(value, dict) else hasattr(value, "flexible")
    return "flexible" if has else "rigid"


AnyBody = Annotated[
    Annotated[Body, Tag("rigid")] | Annotated[FlexibleBody, Tag("flexible")],
    Discriminator(_body_kind),
]


class Point(Strict):
    """A named point fixed on `body`, given at its design position."""

    body: Name = Field(
        description="body carrying the point (or ground); on a flexible body, "
        "BODY.POINT (an interface point) carries it from that node by a rigid arm"
    )
    at: Position = Field(description=describe("position, global frame", "length"))


class Frame(Strict):
    """A named frame fixed on `body`: origin `at`, axes `x` and `y` (z = x cross y)."""

    body: Name = Field(description="body carrying the frame (or ground)")
    at: Position = Field((0.0, 0.0, 0.0), description=describe("origin", "length"))
    x: Direction = Field((1.0, 0.0, 0.0), description="x axis, global frame [dimensionless]")
    y: Direction = Field((0.0, 1.0, 0.0), description="y axis, global frame [dimensionless]")


_AT = describe("joint point, global frame at design", "length")
_AXIS = "unit direction, global frame (normalised on use) [dimensionless]"


class _TwoBody(Strict):
    bodies: NamePair = Field(
        description="[body 1, body 2]: coordinates are body 1 "
        "relative to body 2; reactions act on body 1 from body 2; BODY.POINT (an interface "
        "point of a flexible body): that node, reaching `at` by a rigid arm"
    )


class Fixed(_TwoBody):
    type: Literal["fixed"]
    at: Position = Field(description=_AT)


class Spherical(_TwoBody):
    type: Literal["spherical"]
    at: Position = Field(description=_AT)


class Orientation(_TwoBody):
    type: Literal["orientation"]
    at: Position | None = Field(None, description=_AT + " (where reactions are reported)")


class AxisJoint(_TwoBody):
    type: Literal["revolute", "cylindrical", "prismatic", "inline", "parallel"]
    at: Position = Field(description=_AT)
    axis: Direction = Field(description="axis " + _AXIS)


class Screw(_TwoBody):
    type: Literal["screw"]
    at: Position = Field(description=_AT)
    axis: Direction = Field(description="axis " + _AXIS)
    pitch: Length = Field(description=describe("travel per revolution", "length"))


class AxesJoint(_TwoBody):
    type: Literal["universal", "perpendicular"]
    at: Position = Field(description=_AT)
    axes: tuple[Direction, Direction] = Field(
        description="[a1 fixed in body 1, a2 fixed in body 2] " + _AXIS
    )


class NormalJoint(_TwoBody):
    type: Literal["planar", "inplane"]
    at: Position = Field(description=_AT)
    normal: Direction = Field(description="plane normal " + _AXIS)


class Coupler(Strict):
    type: Literal["coupler", "gear"]
    joints: NamePair = Field(description="[j1, j2]: coordinate of j2 = ratio * coordinate of j1")
    ratio: AnySI = Field(description="coordinate ratio [SI: rad/rad, m/rad, rad/m or m/m]")


class PointOnCurve(_TwoBody):
    """Point `at` of body 1 stays on a curve fixed in body 2 (a table of points)."""

    type: Literal["point_on_curve"]
    at: Position = Field(description=_AT)
    curve: list[Position] = Field(
        min_length=2,
        description=describe(
            "points [x, y, z] of the curve in body 2, global frame at design", "length"
        ),
    )
    interpolation: Literal["akima", "linear", "cubic"] = "cubic"


Joint = Annotated[
    Fixed
    | Spherical
    | Orientation
    | AxisJoint
    | Screw
    | AxesJoint
    | NormalJoint
    | Coupler
    | PointOnCurve,
    Field(discriminator="type"),
]
# Dimension of the single coordinate of a joint type (motions, `initial:` values).
COORDINATE_DIMENSION = {
    "revolute": "angle",
    "screw": "angle",
    "cylindrical": "angle",
    "inline": "angle",
    "prismatic": "length",
}

_ACTIONS = ("activate", "deactivate", "release", "lock", "stop")


class EventAction(Strict):
    """One action of an event: `action` on `target` (None for `stop`)."""

    action: Literal["activate", "deactivate", "release", "lock", "stop"]
    target: str | None = None

    @model_validator(mode="before")
    @classmethod
    def _from_yaml(cls, value: Any) -> Any:
        """Accept `stop` or `{activate: latch}` as written in YAML."""
        if isinstance(value, str):
            value = {value: None}
        if not isinstance(value, dict) or len(value) != 1:
            raise PydanticCustomError(
                "action", "expected an action such as 'stop' or '{activate: NAME}'"
            )
        ((action, target),) = value.items()
        if action not in _ACTIONS:
            raise PydanticCustomError(
                "action",
                "unknown action '{a}': use activate, deactivate, release, lock or stop",
                {"a": action},
            )
        if (target is None) != (action == "stop") or (
            target is not None and not isinstance(target, str)
        ):
            what = "takes no name" if action == "stop" else "needs the name of what it acts on"
            raise PydanticCustomError("action", "action '{a}' {w}", {"a": action, "w": what})
        return {"action": action, "target": target}


class EventDelay(Strict):
    """`delay` after the event named `event` fired."""

    event: Name = Field(description="the event this one follows")
    delay: Time = Field(0.0, ge=0, description=describe("time after that event fired", "time"))


def _action_list(value: Any) -> Any:
    """`then: stop` or `then: {lock: knee}` as a list of one action."""
    return value if isinstance(value, list) else [value]


class Event(Strict):
    """`when` a condition on the state becomes true (or `after` another event and a delay),
    do `then`."""

    when: Expression | None = Field(
        None, description="condition expression, e.g. 'angle(hl2) >= 90*deg'"
    )
    after: EventDelay | None = Field(
        None, description="instead of `when`: {event: NAME, delay: TIME} after that event fired"
    )
    then: Annotated[list[EventAction], BeforeValidator(_action_list)] = Field(
        min_length=1,
        description="actions (one, or a list): stop, {activate: "
        "NAME}, {deactivate: NAME}, {release: JOINT}, {lock: JOINT}",
    )

    @model_validator(mode="after")
    def _when_or_after(self) -> Event:
        if (self.when is None) == (self.after is None):
            raise PydanticCustomError(
                "event", "give either 'when' (a condition) or 'after' ({event: NAME, delay: TIME})"
            )
        return self


class Section(Strict):
    """A section of a rigid body: the plane through `at` normal to `normal`. Its loads are
    the force and moment that the rest of the body applies to the kept part across the
    plane: the part on the side of `side` (a point), else the part the normal points out
    of (the normal is then the outward normal of its cut face: fx along it is tension).
    `mass`, `cm`, `inertia`: the kept part's own mass properties (default: massless)."""

    body: Name = Field(description="the rigid body cut")
    at: Position = Field(
        description=describe("a point of the section plane, global frame", "length")
    )
    normal: Direction = Field(description="normal of the plane, global frame [dimensionless]")
    side: Position | None = Field(
        None, description=describe("a point of the kept part, global frame", "length")
    )
    mass: Mass = Field(0.0, description=describe("mass of the kept part", "mass"))
    cm: Position | None = Field(
        None, description=describe("centre of mass of the kept part, global frame", "length")
    )
    inertia: Inertia = Field(
        (0.0, 0.0, 0.0),
        description="of the kept part about its cm, global axes, as a body's "
        "[inertia: kg*m^2, bare numbers always SI]",
    )

    @model_validator(mode="after")
    def _checked(self) -> Section:
        if not any(self.normal):
            raise PydanticCustomError("section", "the normal must not be zero")
        if self.mass > 0.0 and self.cm is None:
            raise PydanticCustomError("section", "give the cm of the kept part's mass")
        return self


class MechanismModel(Strict):
    """A mechanism: what exists. Positions and axes in the global frame at design."""

    name: str | None = None
    extends: str | None = Field(
        None,
        description="a base mechanism file (relative to this file, inside its folder): its "
        "items, those named here replaced whole (docs/user-guide.md); merged by the loader",
    )
    remove: list[str] = Field(
        default_factory=list,
        description="base items dropped: NAME (any section but parameters) or SECTION.NAME",
    )
    units: FileUnits = Field(default_factory=FileUnits)
    plane: Literal["xy", "yz", "xz"] | None = Field(
        None,
        description="a planar mechanism: its bodies move in this plane (3 coordinates each); "
        "joint axes along its normal, loads and velocities in it; absent: 3-D",
    )
    gravity: vector("acceleration") = Field(
        (0.0, 0.0, 0.0),
        description="gravity vector [acceleration: m/s^2, always SI]; absent: no gravity",
    )
    parameters: dict[str, AnySI] = Field(
        default_factory=dict,
        description="named values for expressions [any dimension, SI; bare numbers SI]",
    )
    bodies: dict[str, AnyBody] = Field(default_factory=dict)
    points: dict[str, Point] = Field(default_factory=dict)
    frames: dict[str, Frame] = Field(default_factory=dict)
    joints: dict[str, Joint] = Field(default_factory=dict)
    forces: dict[str, ForceElement] = Field(default_factory=dict)
    contacts: dict[str, Contact] = Field(default_factory=dict)
    sections: dict[str, Section] = Field(
        default_factory=dict,
        description="sections of rigid bodies whose internal loads a case may request",
    )
    limits: dict[str, Limit] = Field(
        default_factory=dict,
        description="stops on joint coordinates (IMPACT law), effect `contact`",
    )
    tables: dict[str, Table] = Field(default_factory=dict)
    events: dict[str, Event] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _interface_points(self) -> MechanismModel:
        """Each interface point of a flexible body is a point `BODY.NAME` of the mechanism."""
        for body, b in self.bodies.items():
            flexible = getattr(b, "flexible", None)
            for name, at in (flexible.points() if flexible else {}).items():
                point = f"{body}.{name}"
                if point in self.points:
                    raise PydanticCustomError(
                        "points", f"point {point} is also a point of flexible body {body}"
                    )
                self.points[point] = Point(body=body, at=at)
        return self
