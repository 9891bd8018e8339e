"""Builders of contact elements (impact, hertz, restitution between primitive geometries).

`CONTACT_MAKERS[type](builder, name, model) -> mechlib element or None` (None after the
builder recorded a diagnostic). `loadcases.build` adds the element as a force element of
the contact's effect (`contact`), so that `effects: {contact: false}` removes it.
"""
from __future__ import annotations

from typing import Any, Callable

__all__ = ["CONTACT_MAKERS", "CONTACT_COMPONENTS", "CONTACT_UNITS"]

CONTACT_MAKERS: dict[str, Callable[[Any, str, Any], Any]] = {}

# Request quantity -> (column component, key of the element's output), SPEC 1.2.1.
CONTACT_COMPONENTS: dict[str, tuple[tuple[str, str], ...]] = {
    "force": (("normal", "normal"), ("friction", "friction"), ("fx", "fx"), ("fy", "fy"),
              ("fz", "fz")),
    "penetration": (("value", "penetration"),),
}
CONTACT_UNITS: dict[str, str] = {"normal": "N", "friction": "N", "fx": "N", "fy": "N",
                                 "fz": "N", "penetration": "m"}
