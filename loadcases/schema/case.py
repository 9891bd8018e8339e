"""Pydantic models of a case file (`*.case.yaml`, SPEC 1.3): values in SI floats."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Discriminator, Field, Tag, model_validator
from pydantic.json_schema import JsonDict
from pydantic_core import PydanticCustomError

import mechlib as ml
from loadcases.foundation.accuracy_target import DEFAULT_ACCURACY, TARGET_ABOVE, TARGET_BELOW
from loadcases.foundation.units import UnitError, UnreadableError, to_si
from loadcases.schema.mechanism import Event, FileUnits
from loadcases.schema.torque_margin import TorqueMargin
from loadcases.schema.types import (
    AnySI,
    Dimensionless,
    Expression,
    Name,
    RawQuantity,
    Strict,
    describe,
    quantity,
    vector,
)

__all__ = [
    "ANALYSIS_TYPES",
    "KNOWN_EFFECTS",
    "REQUEST_KINDS",
    "TARGET_FORM",
    "AccuracyBudget",
    "AccuracyTarget",
    "Analysis",
    "CaseModel",
    "ContactRequest",
    "ElementRequest",
    "ExpressionRequest",
    "Initial",
    "JointRequest",
    "Motion",
    "MotionRequest",
    "PointRequest",
    "Request",
]

ANALYSIS_TYPES = ("kinematic", "static", "quasi-static", "dynamic", "modes")
KNOWN_EFFECTS = ("gravity", "friction", "contact", "flexibility", "aero", "hydraulics", "damping")
_FRAME = "frame of the components: ground (default), a body or a named frame"


class Motion(Strict):
    """A joint coordinate driven as a function of time."""

    joint: Name = Field(description="revolute, screw, cylindrical (angle) or prismatic joint")
    value: Expression = Field(
        description="coordinate expression of t, SI (rad or m), e.g. "
        "'crank_speed * t' or 'step(t, 0, 0, 2, 90*deg)'"
    )


class Initial(Strict):
    """Initial state of a joint (`value`, `rate`), of a body (`omega`, `velocity`) or of a
    flexible body's modes (`modes`, `rates`).

    `value` and `rate` are SI floats after loading (rad, rad/s for angular joints; m, m/s
    for prismatic ones); in the file they may carry units (`10 deg`, `2 rad/s`). `modes`
    and `rates` are bare SI numbers, one per mode (kg^0.5*m and kg^0.5*m/s).
    """

    value: RawQuantity | None = Field(None, description="joint coordinate [angle or length]")
    guess: RawQuantity | None = Field(
        None,
        description="joint coordinate to assemble near, not imposed: chooses the branch of a "
        "closed loop [angle or length]",
    )
    rate: RawQuantity | None = Field(
        None, description="joint coordinate rate [angular velocity or velocity, bare numbers SI]"
    )
    omega: vector("angular_velocity") | None = Field(
        None, description=describe("body angular velocity, global axes", "angular_velocity")
    )
    velocity: vector("velocity") | None = Field(
        None, description=describe("body cm velocity, global axes", "velocity")
    )
    modes: list[float] | None = Field(
        None,
        description="modal coordinates of a flexible body, one per mode as built "
        "(the `modes` request's q1..qn) [kg^0.5*m]",
    )
    rates: list[float] | None = Field(
        None, description="rates of a flexible body's modal coordinates, one per mode [kg^0.5*m/s]"
    )
    deformed: Literal["static"] | None = Field(
        None,
        description="static: a flexible body starts a dynamic run in its quasi-static "
        "deflection (elastic forces balancing the loads, reactions and inertia at the start)",
    )


_TIME = quantity("time")


class Branches(Strict):
    """When the assembly, or a quasi-static or kinematic run, is said to leave the branch
    of the drawn geometry (or of the guesses), and what follows."""

    angle: quantity("angle") = Field(
        default=math.radians(30.0),
        gt=0,
        description=describe(
            "largest distance of a joint from its guess, and of a joint's jump in one "
            "assembly stage (default 30 deg)",
            "angle",
        ),
    )
    on_change: Literal["warn", "error"] = Field(
        default="warn", description="warn (default), or error: the run fails (exit 1), rows kept"
    )


def _mechanism_ref(value: Any) -> Any:
    if not isinstance(value, (str, dict)) or (isinstance(value, str) and not value.strip()):
        raise PydanticCustomError(
            "mechanism",
            "expected a mechanism file name (relative to this file) or the mechanism as a mapping",
        )
    return value


MechanismRef = Annotated[str | dict[str, Any], BeforeValidator(_mechanism_ref)]


class AccuracyBudget(Strict):
    """What the engine may spend to meet an accuracy target: the estimate's companion and
    the tighter runs together (the first run is not counted). A tighter run that would go
    over it (its cost predicted as twice the last run's) is not started."""

    cpu: _TIME | None = Field(
        None, description=describe("CPU time of the companion and the tighter runs", "time")
    )
    steps: int | None = Field(
        None,
        description="integrator steps of the companion and the tighter runs",
        json_schema_extra={"minimum": 1},
    )
    refinements: int | None = Field(
        None,
        description="most tighter runs (each halves every step)",
        json_schema_extra={"minimum": 0},
    )


# `loads schema` states the target's bounds (loadcases.checks.analysis refuses the rest)
_TARGET_BOUNDS: JsonDict = {"exclusiveMinimum": TARGET_ABOVE, "exclusiveMaximum": TARGET_BELOW}
# how a text that is no target starts to be refused (the number form adds `off` and the mapping)
TARGET_FORM = (
    f"expected a target such as {DEFAULT_ACCURACY:g} (a fraction of each request's peak, "
    f"between {TARGET_ABOVE:g} and {TARGET_BELOW:g})"
)
_ACCURACY_FORMS = f"{TARGET_FORM}, off, or a mapping {{target, budget, measure}}"


def _target_reader(forms: str) -> Callable[[Any], Any]:
    """The check of a target as a number or a quantity text (then read as dimensionless):
    a text that is no quantity (`false`, `none`, `OFF`, `off2`) or a list is refused
    naming `forms`; a quantity of another dimension (`1 mm`) is left to say so."""

    def check(value: Any) -> Any:
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise PydanticCustomError("expected", forms)
        if isinstance(value, str):
            try:
                to_si(value, "dimensionless")
            except UnreadableError:
                raise PydanticCustomError("expected", forms) from None
            except UnitError:
                pass
        return value

    return check


class AccuracyTarget(Strict):
    """`accuracy: {target: 1e-2, budget: {cpu: 60 s}}`: the target with its budget."""

    target: Annotated[Dimensionless, BeforeValidator(_target_reader(TARGET_FORM))] = Field(
        DEFAULT_ACCURACY,
        description=(
            "estimated global error of each request's envelope, of its peak "
            f"(default {DEFAULT_ACCURACY:g})"
        ),
        json_schema_extra=_TARGET_BOUNDS,
    )
    budget: AccuracyBudget | None = Field(
        None, description="what meeting it may cost (default: 8 refinements, 600 s of CPU)"
    )
    measure: Literal["peaks", "histories"] = Field(
        "peaks",
        description=(
            "what must meet it: the envelope peaks (default) or the whole time histories "
            "(a trajectory benchmark's error, a phase drift)"
        ),
    )


def _accuracy_form(value: Any) -> str:
    """`analysis.accuracy`'s form: a mapping (target and budget), `off`, or a number."""
    if isinstance(value, dict | AccuracyTarget):
        return "target"
    return "off" if value == "off" else "number"


Accuracy = Annotated[
    Annotated[Dimensionless, BeforeValidator(_target_reader(_ACCURACY_FORMS)), Tag("number")]
    | Annotated[Literal["off"], Tag("off")]
    | Annotated[AccuracyTarget, Tag("target")],
    Discriminator(_accuracy_form),
]


class Analysis(Strict):
    """What to solve and for how long."""

    type: Literal["kinematic", "static", "quasi-static", "dynamic", "modes"]
    end: _TIME | None = Field(None, description=describe("end time", "time"))
    step: _TIME | None = Field(None, description=describe("output interval", "time"))
    tolerance: Dimensionless | None = Field(None, description="dynamic: local error tolerance")
    accuracy: Accuracy | None = Field(
        None,
        description=(
            "dynamic: target of the estimated global error of each request, relative to its "
            f"peak, between {TARGET_ABOVE:g} and {TARGET_BELOW:g} (default "
            f"{DEFAULT_ACCURACY:g}, warned about); given without a tolerance, the engine "
            "tightens its steps to meet it, within a budget ({target: 1e-2, budget: {cpu: "
            "60 s, steps: 1e6, refinements: 4}}); off: no estimate (one solve)"
        ),
        json_schema_extra=_TARGET_BOUNDS,
    )
    integrator: str | None = Field(None, description="dynamic: e.g. generalized-alpha, radau")
    rho_inf: Dimensionless | None = Field(
        None,
        description=(
            "dynamic, generalized-alpha: spectral radius at infinite frequency, 0 to 1 "
            "(default 0.9; lower damps high-frequency modes more, 1 not at all)"
        ),
    )
    max_step: _TIME | None = Field(
        None, description=describe("dynamic: largest integrator step", "time")
    )
    output: Literal["steps", "dense"] | None = Field(
        None,
        description=(
            "dynamic: dense (default): the integrator's steps take the size the tolerance "
            "allows (up to max_step, or the mechanism's natural time sqrt(size / g)), "
            "whatever the output interval and the end, and the rows at the output times come "
            "from dense output, projected onto the constraints; steps: the steps end on the "
            "output times, their size at most the output interval"
        ),
    )
    max_steps: int | None = Field(
        None,
        description=(
            f"kinematic, quasi-static, dynamic: most steps a run may take, accepted and rejected "
            f"(default {ml.DEFAULT_MAX_STEPS}); a run that reaches it fails"
        ),
        json_schema_extra={"minimum": 1},
    )
    redundant: Literal["error", "drop"] = Field(
        "error", description="redundant constraint equations: error (default) or drop them"
    )


class Phase(Strict):
    """One analysis of a sequence: it starts from the state where the previous one ended."""

    name: Name | None = Field(None, description="the phase's name (default phase1, phase2, ...)")
    analysis: Analysis = Field(
        description="static, quasi-static or dynamic; `end` is the time the phase ends at "
        "(s, from the case's start), after the previous phase's end"
    )
    locks: list[Name] = Field(
        default_factory=list,
        description="joints held at their coordinate of the phase's first state while the "
        "phase lasts (hinges fixed for a static preload)",
    )
    motions: list[Name] | None = Field(
        None, description="the case's motions driving in this phase; absent: all"
    )


class JointRequest(Strict):
    """A joint's reaction (`force`: fx fy fz tx ty tz f t) or coordinate (`value`)."""

    joint: Name
    quantity: Literal["force", "angle", "omega", "alpha", "travel", "speed"]
    frame: Name = Field("ground", description=_FRAME)


class MotionRequest(Strict):
    """The effort a motion needs along its joint coordinate (`value`)."""

    motion: Name
    quantity: Literal["torque", "force"]


class PointRequest(Strict):
    """Position, velocity or acceleration of a point (`x y z`)."""

    point: Name
    quantity: Literal["position", "velocity", "acceleration"]
    frame: Name = Field("ground", description=_FRAME)


class ElementRequest(Strict):
    """Force of a force element (`value` for scalar elements, or `fx..tz`)."""

    force: Name
    quantity: Literal["force"] = "force"
    frame: Name = Field("ground", description=_FRAME)


class LimitRequest(Strict):
    """Of a joint limit: `value`, its effort along the joint coordinate (N*m or N, positive
    increases the coordinate), and `penetration` (rad or m, >= 0)."""

    limit: Name
    quantity: Literal["force"] = "force"


class ContactRequest(Strict):
    """Contact `force` (normal, friction, fx fy fz on body 1), `penetration` (value, m),
    `point` (x y z, m, ground axes), `sliding_speed` (value, m/s), `wear` (F_N * v_rel,
    value, W) or, of a clearance joint, `eccentricity` (ex ey ez in ground axes, value, m,
    and its polar angle, rad), `wear_work` (the integral of F_N * v_rel, value, J) and
    `polar` (radial, axial, m; angle, rad; clearance, m; normal, N; wear, W; wear_work, J:
    what the polar plots and the wear map read); `force_split` (elastic, damping: the normal
    force's elastic part k x^n and the rest, N; seed 004 fig. 5.13); `wear_depth` (a
    clearance joint with a `wear:` law: the Archard depth, value, m)."""

    contact: Name
    quantity: Literal[
        "force",
        "penetration",
        "point",
        "sliding_speed",
        "wear",
        "eccentricity",
        "wear_work",
        "polar",
        "force_split",
        "wear_depth",
    ]
    frame: Name = Field("ground", description=_FRAME)


class FlexibleRequest(Strict):
    """Of a flexible body: its modal coordinates (`modes`: q1..qn, kg^0.5*m) or the elastic
    `deformation` of one of its interface points (`point`; x y z, m, the body's axes)."""

    flexible: Name
    quantity: Literal["modes", "deformation"] = "modes"
    point: Name | None = None


class SectionRequest(Strict):
    """The internal loads of a body at a section of the mechanism (`fx fy fz tx ty tz f t`):
    on the section's kept part from the rest of the body, at the section point."""

    section: Name
    quantity: Literal["loads"] = "loads"
    frame: Name | None = Field(
        None,
        description="axes of the components: the section's body (default: they turn with "
        "it), ground, another body or a frame",
    )


def _column_unit(value: Any) -> str:
    """A unit name for an expression request's column (`kN`, `N*m`, `deg/s`)."""
    if not isinstance(value, str) or not value.strip():
        raise PydanticCustomError("unit", "expected a unit name such as 'kN'")
    try:
        to_si(f"1 {value.strip()}", "any")
    except UnitError:
        raise PydanticCustomError(
            "unit", "unknown unit '{unit}'", {"unit": value.strip()}
        ) from None
    return value.strip()


class ExpressionRequest(Strict):
    """Any expression of the state (`value`, SI)."""

    expression: Expression
    unit: Annotated[str, BeforeValidator(_column_unit)] | None = Field(
        None,
        description="the column's dimension, named by a unit of it (`kN` makes it a force, "
        "shown in the report's force unit); absent: inferred from the expression",
    )


class EnergyRequest(Strict):
    """The energy balance of the run (J): kinetic, gravitational, elastic, drive_work,
    load_work, dissipated and balance (docs/analyses.md, Energy)."""

    quantity: Literal["energy"]


REQUEST_KINDS = (
    "joint",
    "motion",
    "flexible",
    "point",
    "force",
    "limit",
    "contact",
    "section",
    "expression",
)


def _request_kind(value: Any) -> str | None:
    """The request kind: the first of REQUEST_KINDS given as a key; `energy` for a request
    with none of them and `quantity: energy`."""
    if isinstance(value, dict):
        kind = next((kind for kind in REQUEST_KINDS if kind in value), None)
        return kind or ("energy" if value.get("quantity") == "energy" else None)
    kind = next((kind for kind in REQUEST_KINDS if hasattr(value, kind)), None)
    return kind or ("energy" if isinstance(value, EnergyRequest) else None)


Request = Annotated[
    Annotated[JointRequest, Tag("joint")]
    | Annotated[MotionRequest, Tag("motion")]
    | Annotated[PointRequest, Tag("point")]
    | Annotated[ElementRequest, Tag("force")]
    | Annotated[LimitRequest, Tag("limit")]
    | Annotated[ContactRequest, Tag("contact")]
    | Annotated[FlexibleRequest, Tag("flexible")]
    | Annotated[SectionRequest, Tag("section")]
    | Annotated[ExpressionRequest, Tag("expression")]
    | Annotated[EnergyRequest, Tag("energy")],
    Discriminator(
        _request_kind,
        custom_error_type="request_kind",
        custom_error_message="a request needs one of the keys joint, motion, point, "
        "force, limit, contact, flexible, section or expression, or is `quantity: energy`",
    ),
]


class CaseModel(Strict):
    """A load case: what happens to a mechanism."""

    case: str = Field(min_length=1, description="case name; '/' makes sub-folders of results")
    units: FileUnits = Field(default_factory=FileUnits)
    mechanism: MechanismRef = Field(
        description="mechanism file relative to this file, or the mechanism inline"
    )
    level: Literal["limit", "ultimate"] = Field(
        "limit",
        description="level of the case's applied loads: limit (a set's ultimate factor "
        "multiplies its loads) or ultimate (its loads are ultimate as computed; limit = "
        "computed / ultimate factor)",
    )
    parameters: dict[str, AnySI] = Field(
        default_factory=dict, description="overrides of the mechanism's parameters [SI]"
    )
    motions: dict[str, Motion] = Field(default_factory=dict)
    effects: dict[str, bool] = Field(
        default_factory=dict, description="switch effects on/off: " + ", ".join(KNOWN_EFFECTS)
    )
    loads: list[Name] | None = Field(None, description="active force elements by name; absent: all")
    initial: dict[str, Initial] = Field(default_factory=dict, description="by joint or body")
    branches: Branches = Field(
        Branches(),
        description="assembly branches: {angle: 30 deg, on_change: warn | error}",
    )
    analysis: Analysis = Field(description="what to solve; with `phases`, leave it out")
    phases: list[Phase] | None = Field(
        None,
        description="analyses in sequence, each from the state where the last ended "
        "(instead of `analysis`)",
        json_schema_extra={"minItems": 1},
    )
    requests: dict[str, Request] = Field(default_factory=dict)
    abscissa: Expression | None = Field(None, description="x-axis expression for envelopes")
    events: dict[str, Event] = Field(
        default_factory=dict,
        description="events of this case "
        "(dynamic analyses), added to the mechanism's; names "
        "unique across both",
    )
    torque_margin: TorqueMargin | None = Field(
        None,
        description="torque margin TM_j = "
        "sum D_j / sum R_j per hinge line (seed 003 "
        "eq. 2.1), reported along the run",
    )

    @model_validator(mode="before")
    @classmethod
    def _phased(cls, data: Any) -> Any:
        """A case with `phases` and no `analysis`: a stand-in until `_last_phase` (both
        given: loadcases.checks.phases reports it at the key)."""
        if isinstance(data, dict) and data.get("phases") and "analysis" not in data:
            return {**data, "analysis": {"type": "static"}}
        return data

    @model_validator(mode="after")
    def _last_phase(self) -> CaseModel:
        """A phased case's `analysis` is its last phase's (the settings a run reads once:
        `redundant`, and what a set records)."""
        if self.phases:
            object.__setattr__(self, "analysis", self.phases[-1].analysis)
        return self
