"""Pydantic models of a flexible body (`bodies: NAME: flexible:`, issue 13): SI floats.

A built-in source (`beam:`, `grillage:` or `plate:`) or an imported one (`file:`) gives the
FE model;
`interface:` names the points (global, at design) where the mechanism attaches: each
becomes a node and a point `BODY.NAME`; `modes:` / `frequency_range:` select the
Craig-Bampton modes, `damping:` their ratios (default: 1 % below 100 Hz, 10 % below
1 kHz, 100 % above); `stiffening:` adds the modal geometric stiffness (spin-up beams),
`linear_limit:` the deformation share of the body's size beyond which a run warns.
"""

from __future__ import annotations

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.schema.types import (
    Dimensionless,
    Direction,
    Length,
    Position,
    Strict,
    describe,
    quantity,
    vector,
)

__all__ = [
    "BeamSection",
    "BeamSource",
    "FileSource",
    "Flexible",
    "GrillageSource",
    "MaterialModel",
    "PlateSource",
]

Density = quantity("density")
Pressure = quantity("pressure")
Area = quantity("area")
SecondMoment = quantity("second_moment")


class MaterialModel(Strict):
    """Isotropic material."""

    E: Pressure = Field(description=describe("Young's modulus", "pressure"))
    nu: Dimensionless = Field(description="Poisson's ratio [dimensionless]")
    rho: Density = Field(description=describe("density", "density"))


class BeamSection(Strict):
    """A solid rectangle (`width` along the section y axis, `height` along z) or the
    properties `A`, `Iy` (= int z^2 dA), `Iz` (= int y^2 dA), `J`."""

    width: Length | None = Field(None, description=describe("rectangle width", "length"))
    height: Length | None = Field(None, description=describe("rectangle height", "length"))
    A: Area | None = Field(None, description=describe("area", "area"))
    Iy: SecondMoment | None = Field(None, description=describe("Iy", "second_moment"))
    Iz: SecondMoment | None = Field(None, description=describe("Iz", "second_moment"))
    J: SecondMoment | None = Field(None, description=describe("torsion constant", "second_moment"))
    shear: bool = Field(True, description="Timoshenko shear deformation (k = 5/6)")

    @model_validator(mode="after")
    def _complete(self) -> BeamSection:
        rectangle = self.width is not None and self.height is not None
        props = None not in (self.A, self.Iy, self.Iz, self.J)
        if rectangle == props:
            raise PydanticCustomError("section", "give either width and height, or A, Iy, Iz and J")
        return self


class BeamSource(Strict):
    """A straight beam from `start` to `end` (global, design) in `elements` elements."""

    start: Position = Field(description=describe("first end", "length"))
    end: Position = Field(description=describe("second end", "length"))
    section: BeamSection
    material: MaterialModel
    elements: int = Field(20, ge=1, le=2000, description="number of elements")
    y_axis: Direction = Field(
        (0.0, 0.0, 1.0), description="section y axis (made normal to the beam) [dimensionless]"
    )


class GrillageSource(Strict):
    """A flat panel as a grillage of beams: corner `at`, edges along `x` and `y`."""

    at: Position = Field(description=describe("corner of the panel", "length"))
    x: Direction = Field((1.0, 0.0, 0.0), description="panel x edge [dimensionless]")
    y: Direction = Field((0.0, 1.0, 0.0), description="panel y edge [dimensionless]")
    size: vector("length", 2) = Field(description=describe("[lx, ly]", "length"))
    thickness: Length = Field(description=describe("thickness", "length"))
    material: MaterialModel
    mesh: tuple[int, int] = Field((10, 10), description="[nx, ny] cells")


class PlateSource(GrillageSource):
    """A flat panel of plate/shell elements (the extra `plate`: pyfe3d), the grillage's
    keys: corner `at`, edges along `x` and `y`."""


class FileSource(Strict):
    """An imported FE model (docs/flexible-bodies-import.md): the JSON header of a neutral,
    Matrix Market, OP4 or DMIG model, placed by its frame's origin `at` and axes `x`, `y`."""

    path: str = Field(
        min_length=1,
        description="the model's JSON header, relative to this file, inside its folder",
    )
    at: Position = Field(
        (0.0, 0.0, 0.0), description=describe("the model frame's origin, global", "length")
    )
    x: Direction = Field((1.0, 0.0, 0.0), description="the model's x axis, global [dimensionless]")
    y: Direction = Field((0.0, 1.0, 0.0), description="the model's y axis, global [dimensionless]")


class Flexible(Strict):
    """A flexible body reduced by Craig-Bampton (seed 003, chapter 1)."""

    beam: BeamSource | None = None
    grillage: GrillageSource | None = None
    plate: PlateSource | None = None
    file: FileSource | None = None
    interface: dict[str, Position] = Field(
        description=describe("named attachment points, global at design", "length")
    )
    load_points: dict[str, Position] = Field(
        default_factory=dict,
        description=describe(
            "named nodes kept for loads, points and requests but not held in the reduction "
            "(not Craig-Bampton boundary), global at design",
            "length",
        ),
    )
    modes: int | None = Field(None, ge=1, description="number of modes kept (lowest)")
    frequency_range: vector("frequency", 2) | None = Field(
        None, description=describe("[low, high]: the modes kept", "frequency")
    )
    fixed_interface_modes: int | None = Field(
        None, ge=0, description="fixed-interface modes of the basis (default max(10, modes))"
    )
    damping: float | dict[int, float] | None = Field(
        None,
        description="ratio of critical for all modes, or {mode number: ratio} over the "
        "default (1 % < 100 Hz, 10 % < 1 kHz, 100 % above) [dimensionless]",
    )
    stiffening: bool = Field(
        False,
        description="geometric stiffening: the stresses of the spin and of the interface "
        "loads stiffen the modes (built-in beam and grillage only)",
    )
    linear_limit: float = Field(
        0.1,
        gt=0.0,
        description="warn when interface nodes deform by more than this share of the "
        "body's size [dimensionless]",
    )

    @model_validator(mode="after")
    def _one_source(self) -> Flexible:
        if sum(s is not None for s in (self.beam, self.grillage, self.plate, self.file)) != 1:
            raise PydanticCustomError(
                "flexible", "give exactly one source: beam, grillage, plate or file"
            )
        if self.modes is not None and self.frequency_range is not None:
            raise PydanticCustomError("flexible", "give modes or frequency_range, not both")
        if not self.interface:
            raise PydanticCustomError("flexible", "name at least one interface point")
        both = sorted(set(self.interface) & set(self.load_points))
        if both:
            raise PydanticCustomError(
                "flexible",
                "{names}: both an interface point and a load point",
                {"names": ", ".join(both)},
            )
        return self

    def points(self) -> dict[str, tuple[float, float, float]]:
        """The named nodes of the body (interface points, then load points): each is the
        node body `BODY.NAME` of the mechanism."""
        return {**self.interface, **self.load_points}

    def source_key(self) -> str:
        for key in ("file", "beam", "plate"):
            if getattr(self, key) is not None:
                return key
        return "grillage"
