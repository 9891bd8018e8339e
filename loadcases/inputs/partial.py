"""A file's model without its invalid items, so that `validate` reports every problem in one
pass: the semantic checks (names, expressions, dimensions) run on what is valid even when
some items are not, instead of waiting for the schema errors to be fixed.

An item is removed at its name (`forces.rub` for an error at `forces.rub.mu`), or a whole
optional section when the error is not inside a named item (`gravity`); when a required key
is wrong the file is not checked further. The checks' messages that name a removed item
(`unknown force 'rub'`) are dropped: the item's own error stands for them.
"""

from __future__ import annotations

import copy
from collections.abc import Iterable
from typing import Any

from pydantic import BaseModel, ValidationError

from loadcases.foundation.diagnostics import Diagnostic

__all__ = ["beside_removed", "validated_in_part"]

_ROUNDS = 3  # removing items rarely reveals new errors; a few rounds, then give up


def validated_in_part(
    model_class: type[BaseModel], data: Any, units: dict[str, str], error: ValidationError
) -> tuple[BaseModel | None, frozenset[str]]:
    """The model of `data` without the items `error` (its validation error) points at, and
    the names removed; (None, names) when what is left is still invalid. `data` is not
    changed."""
    pruned = copy.deepcopy(data)
    removed: set[str] = set()
    for _ in range(_ROUNDS):
        if not isinstance(pruned, dict) or not _prune(pruned, _locations(error), removed):
            return None, frozenset(removed)
        try:
            return model_class.model_validate(pruned, context={"units": units}), frozenset(removed)
        except ValidationError as again:
            error = again
    return None, frozenset(removed)


def _locations(error: ValidationError) -> list[tuple[Any, ...]]:
    return [tuple(item["loc"]) for item in error.errors()]


def _prune(data: dict[str, Any], locations: Iterable[tuple[Any, ...]], removed: set[str]) -> bool:
    """Remove from `data` each named item (or top-level key) a location points into;
    False if one cannot be removed (an error about the whole file)."""
    for location in locations:
        if not location or not isinstance(location[0], str):
            return False
        section = data.get(location[0])
        if (
            len(location) > 1
            and isinstance(section, dict)
            and isinstance(location[1], str)
            and isinstance(section.get(location[1]), dict)
        ):
            section.pop(location[1], None)
            removed.add(location[1])
        elif location[0] in data:
            data.pop(location[0])
    return True


def beside_removed(diagnostics: Iterable[Diagnostic], removed: frozenset[str]) -> list[Diagnostic]:
    """The diagnostics that name none of the `removed` items."""
    quoted = [f"'{name}'" for name in removed]
    return [d for d in diagnostics if not any(q in d.message for q in quoted)]
