"""Values that are admissible but implausible: a warning at `validate` with the likely slip.

A density of 7850 kg/mm^3 (7.85e12 kg/m^3: the unit of a length in mm carried into a
density) passes every range check, and later ends a run in a singular system matrix (the
masses dwarf the stiffnesses). Densities of engineering solids and liquids lie between
those of foams and of the heaviest metals; a parameter of a density (the air's in a drag
formula) may be a gas's, down to the thin air of high altitude.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from loadcases.expressions.dimensions import DimensionScope
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.schema import MechanismModel
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = ["DENSITY_RANGE", "PARAMETER_DENSITY_RANGE", "density_warnings"]

# kg/m^3: rigid foams (about 30) to osmium (22,590), with a margin
DENSITY_RANGE = (10.0, 30_000.0)
# kg/m^3: the air at 30 km (0.018) to osmium, with a margin: any fluid or solid
PARAMETER_DENSITY_RANGE = (1e-3, 30_000.0)
_DENSITY = {"[mass]": 1.0, "[length]": -3.0}
_FLEXIBLE_SOURCES = ("beam", "grillage", "plate")


def _densities(model: MechanismModel) -> Iterator[tuple[KeyPath, float]]:
    """(key path, value in kg/m^3) of every density of the mechanism."""
    for name, body in model.bodies.items():
        flexible = getattr(body, "flexible", None)
        for source in _FLEXIBLE_SOURCES:
            material = getattr(getattr(flexible, source, None), "material", None)
            if material is not None:
                yield ("bodies", name, "flexible", source, "material", "rho"), material.rho
    for name, force in model.forces.items():
        density = getattr(getattr(force, "jet_pipe", None), "density", None)
        if density is not None:
            yield ("forces", name, "jet_pipe", "density"), density


def _density_parameters(
    model: MechanismModel, scope: DimensionScope | None
) -> Iterator[tuple[KeyPath, float]]:
    """(key path, value in kg/m^3) of every parameter written as a density."""
    if scope is None:
        return
    for name, value in model.parameters.items():
        dims = scope.names(name)
        if dims is not None and dict(dims) == _DENSITY and isinstance(value, (int, float)):
            yield ("parameters", name), float(value)


def density_warnings(
    model: MechanismModel, at: Locator, scope: DimensionScope | None = None
) -> list[Diagnostic]:
    """A warning for each density outside DENSITY_RANGE (a parameter's: outside
    PARAMETER_DENSITY_RANGE), naming the unit slip it may be; `scope` gives the parameters'
    dimensions."""
    found = [
        (path, value, DENSITY_RANGE, "solids and liquids") for path, value in _densities(model)
    ]
    found += [
        (path, value, PARAMETER_DENSITY_RANGE, "gases, liquids and solids")
        for path, value in _density_parameters(model, scope)
    ]
    return [
        at.diagnostic(
            path,
            f"implausible density {value:.4g} kg/m^3 ({what}: {low:g} to {high:,.0f} kg/m^3)",
            severity="warning",
            hint=_hint(value, (low, high)),
        )
        for path, value, (low, high), what in found
        if not low <= value <= high
    ]


def _hint(value: Any, bounds: tuple[float, float] = DENSITY_RANGE) -> str:
    for factor, unit in ((1e9, "kg/mm^3"), (1e12, "t/mm^3"), (1e-3, "g/m^3"), (1e3, "g/cm^3")):
        if bounds[0] <= value / factor <= bounds[1]:
            return (
                f"written in {unit} where kg/m^3 was meant? {value / factor:g} kg/m^3 is "
                f"{value:.4g} kg/m^3 read as {unit} (steel: 7850 kg/m^3 = 7.85e-9 t/mm^3)"
            )
    return "check the unit: steel is 7850 kg/m^3 = 7.85 g/cm^3 = 7.85e-9 t/mm^3"
