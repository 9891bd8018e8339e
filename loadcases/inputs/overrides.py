"""What-if overrides: `loads run FILE --set NAME=VALUE` changes one parameter for one run.

A value may carry a unit (`--set "length=1.5 m"`); a bare number is SI, as in `parameters:`.
A value is read by the quantity parser of the files (`loadcases.foundation.units.to_si`):
digits 0-9, a plain space, no line break; messages quote it once, at most 80 characters.
The parameter must be defined (`parameters:` of the case, its mechanism or, for a set, the
set) and a value must have the dimension of the definition when that has a unit. A run
with overrides is named like a sweep run, `CASE[length=1.5m]` (the value as written), so
it never takes the place (or the saved results) of the run without them.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from loadcases.foundation.clip import clip
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.foundation.units import (
    SIValue,
    UnitError,
    dimension_mismatch,
    quantity_dimension,
    to_si,
)
from loadcases.inputs.run_identity import Labels, Pairs, value_label
from loadcases.schema.errors import did_you_mean
from loadcases.yamlfiles.source import Locator

__all__ = [
    "OPTION",
    "Override",
    "OverrideError",
    "defined_parameters",
    "labels",
    "override_problems",
    "pairs",
    "parse_overrides",
]

OPTION = "--set"
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


class OverrideError(ValueError):
    """A `--set` option that cannot be read; the message names the option."""


@dataclass(frozen=True)
class Override:
    """One `--set NAME=VALUE`: the value as written and in SI."""

    name: str
    text: str
    value: float

    @property
    def option(self) -> str:
        """The option as given, for messages: `--set length=1.5 m` (clipped)."""
        return f"{OPTION} {clip(self.name)}={clip(self.text)}"


def parse_overrides(texts: Sequence[str]) -> tuple[Override, ...]:
    """The `--set` options in the order given; OverrideError naming the first bad one
    (not NAME=VALUE, a value that is not a finite quantity, a name given twice)."""
    found: dict[str, Override] = {}
    for text in texts:
        name, equals, value = text.partition("=")
        name, value = name.strip(" "), value.strip(" ")
        if not equals or not _NAME.fullmatch(name) or not value:
            raise OverrideError(
                f"{OPTION} '{clip(text)}': expected NAME=VALUE, e.g. {OPTION} length=1.5 or "
                f"{OPTION} 'length=1500 mm' (a parameter name, '=', a number with an "
                "optional unit)"
            )
        shown = f"{OPTION} {clip(name)}"
        if name in found:
            raise OverrideError(f"{shown}: given twice ({clip(found[name].text)}, {clip(value)})")
        try:
            number = _finite_number(value)
            si = to_si(number, "any")
            dims = quantity_dimension(number) if isinstance(number, str) else None
        except UnitError as error:  # the error quotes the value
            raise OverrideError(f"{shown}: {error}") from None
        # the value carries its dimension to the fields that use the parameter
        shown_value = f"{OPTION} {clip(name)}={clip(value)}"
        found[name] = Override(name, value, SIValue(si, _dims(dims), f"'{shown_value}'"))
    return tuple(found.values())


def _dims(dims: tuple[tuple[str, float], ...] | None) -> dict[str, float] | None:
    return None if dims is None else dict(dims)


_NOT_FINITE = re.compile(r"[-+]?(?:nan|inf|infinity)", re.IGNORECASE)


def _finite_number(value: str) -> str | float:
    """`value`, or its float for `nan` and `inf` (refused by `to_si` as not finite rather
    than as unreadable); any other text, a plain number too, is read as files are."""
    return float(value) if _NOT_FINITE.fullmatch(value) else value


def labels(overrides: Iterable[Override]) -> Labels:
    """{(name, SI value): the value as written} of each override, for run names."""
    return {(o.name, o.value): value_label(o.text) for o in overrides}


def pairs(overrides: Iterable[Override]) -> Pairs:
    """(name, SI value) of each override, in order."""
    return tuple((o.name, o.value) for o in overrides)


def defined_parameters(locators: Iterable[Locator | None]) -> dict[str, tuple[Locator, object]]:
    """Each parameter defined in the raw `parameters:` of the given files (later ones win):
    name -> (the file's locator, the value as written)."""
    found: dict[str, tuple[Locator, object]] = {}
    for locator in locators:
        if locator is None:
            continue
        data = locator.data
        section = data.get("parameters") if isinstance(data, dict) else None
        if isinstance(section, dict):
            found.update({str(name): (locator, raw) for name, raw in section.items()})
    return found


def override_problems(
    overrides: Sequence[Override],
    definitions: dict[str, tuple[Locator, object]],
    anchor: Locator,
    what: str,
) -> list[Diagnostic]:
    """Errors for overrides of parameters not in `definitions` (reported at the top of
    `anchor`'s file; `what` says where they were looked for, e.g. 'the case') or of another
    dimension than their definition (reported at the definition)."""
    found = []
    for override in overrides:
        if override.name not in definitions:
            found.append(
                Diagnostic(
                    anchor.tree.file,
                    *anchor.tree.position(("parameters",)),
                    override.option,
                    f"no parameter '{override.name}' in {what}",
                    hint=did_you_mean(override.name, definitions)
                    or "define it under `parameters:` of the case or its mechanism",
                )
            )
            continue
        locator, raw = definitions[override.name]
        problem = dimension_mismatch(override.text, raw)
        if problem is not None:
            found.append(
                locator.diagnostic(("parameters", override.name), f"{override.option}: {problem}")
            )
    return found
