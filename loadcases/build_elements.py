"""Builders of the domain force elements (joint friction, seals, dampers, cable loops ...).

`ELEMENT_MAKERS[type](builder, name, model) -> mechlib element or None` (None after the
builder recorded a diagnostic with `builder.error(...)`). `loadcases.build` calls the
maker of every force element type it does not build itself.
"""
from __future__ import annotations

from typing import Any, Callable

__all__ = ["ELEMENT_MAKERS"]

ELEMENT_MAKERS: dict[str, Callable[[Any, str, Any], Any]] = {}
