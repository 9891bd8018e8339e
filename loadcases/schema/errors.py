"""Pydantic validation errors -> short, positioned diagnostics naming the key."""

from __future__ import annotations

import difflib
import types
import typing
from typing import Any, Union

from pydantic import BaseModel, ValidationError
from pydantic.fields import FieldInfo

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.yamlfiles.source import KeyPath, Locator

__all__ = ["did_you_mean", "plain_boolean_diagnostics", "validation_diagnostics"]

_NUMBER_TYPES = ("float_type", "float_parsing", "finite_number")
_WHOLE_NUMBER_TYPES = ("int_type", "int_parsing", "int_parsing_size", "int_from_float")
_SIMPLE = {
    "string_type": "expected a text",
    "dict_type": "expected a mapping of keys",
    "model_type": "expected a mapping of keys",
    "model_attributes_type": "expected a mapping of keys",
    "list_type": "expected a list",
    "tuple_type": "expected a list",
    "bool_type": "expected true or false",
    "bool_parsing": "expected true or false",
}

# a Field(gt=..., ge=..., lt=..., le=...) range: (operator, ctx key of the bound)
_RANGES = {
    "greater_than": (">", "gt"),
    "greater_than_equal": (">=", "ge"),
    "less_than": ("<", "lt"),
    "less_than_equal": ("<=", "le"),
}


def _number(value: Any) -> str:
    """A bound or value of a range error: floats as %g (values are SI after conversion)."""
    return f"{value:g}" if isinstance(value, float) else _show(value)


def did_you_mean(word: str | int, choices: typing.Iterable[str]) -> str | None:
    """`did you mean 'x'?` for the closest of `choices` (difflib), or None (`word` may be
    a YAML key that is a number)."""
    close = difflib.get_close_matches(str(word), list(choices), n=1, cutoff=0.6)
    return f"did you mean '{close[0]}'?" if close else None


def _show(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, (list, tuple)):
        return f"a list of {len(value)} values"
    return "nothing" if value is None else repr(value) if isinstance(value, str) else str(value)


def _unwrap(tp: Any) -> tuple[Any, list[Any]]:
    """Strip Annotated layers (collecting their metadata) and a `| None`."""
    meta: list[Any] = []
    while True:
        if typing.get_origin(tp) is typing.Annotated:
            meta.extend(tp.__metadata__)
            tp = tp.__origin__
            continue
        if _is_union(tp):
            members = [m for m in typing.get_args(tp) if m is not type(None)]
            if len(members) == 1:
                tp = members[0]
                continue
        return tp, meta


def _is_union(tp: Any) -> bool:
    return typing.get_origin(tp) in (Union, types.UnionType)


def _member_by_tag(members: tuple[Any, ...], meta: list[Any], tag: Any) -> Any:
    """The union member selected by discriminator `tag`, or None if this is no tag."""
    field = next(
        (m.discriminator for m in meta if isinstance(m, FieldInfo) and m.discriminator), None
    )
    for member in members:
        inner, inner_meta = _unwrap(member)
        if (
            field
            and isinstance(field, str)
            and isinstance(inner, type)
            and issubclass(inner, BaseModel)
            and field in inner.model_fields
        ) and tag in typing.get_args(inner.model_fields[field].annotation):
            return inner
        if any(getattr(m, "tag", None) == tag for m in inner_meta):
            return inner
    return None


def _step(tp: Any, part: Any) -> tuple[Any, bool]:
    """Type after loc element `part`, and whether `part` was a union tag (not a data key)."""
    tp, meta = _unwrap(tp)
    if _is_union(tp):
        member = _member_by_tag(typing.get_args(tp), meta, part)
        return (member, True) if member is not None else (Any, isinstance(part, str))
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        field = tp.model_fields.get(part) if isinstance(part, str) else None
        return (field.annotation if field else Any), False
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin is dict and len(args) == 2:
        return args[1], False
    if origin in (list, set, frozenset) and args:
        return args[0], False
    if origin is tuple and args:
        if len(args) == 2 and args[1] is Ellipsis:
            return args[0], False
        return (args[part] if isinstance(part, int) and part < len(args) else Any), False
    return Any, False


def _resolve(model: type[BaseModel], loc: tuple[Any, ...]) -> tuple[KeyPath, Any]:
    """Data key path of a pydantic `loc` (union tags removed) and the type at its parent."""
    tp: Any = model
    path: list[Any] = []
    parent: Any = model
    for part in loc:
        parent = tp
        tp, is_tag = _step(tp, part)
        if not is_tag:
            path.append(part)
    return tuple(path), parent


def _fields_of(tp: Any) -> list[str]:
    inner, _ = _unwrap(tp)
    if isinstance(inner, type) and issubclass(inner, BaseModel):
        return list(inner.model_fields)
    return []


def _message(error: Any, path: KeyPath, parent: Any) -> tuple[str, str | None, KeyPath]:
    """(message, hint, key path) of one pydantic error dict."""
    kind, ctx, value = error["type"], error.get("ctx") or {}, error.get("input")
    if kind == "missing":
        return "required key is missing", None, path
    if kind == "extra_forbidden":
        fields = _fields_of(parent)
        hint = did_you_mean(path[-1], fields) if path else None
        if hint is None and fields:
            hint = "allowed keys: " + ", ".join(fields)
        return "unknown key", hint, path
    if kind == "union_tag_invalid":
        key = str(ctx.get("discriminator", "type")).strip("'")
        tags = [t.strip(" '") for t in str(ctx.get("expected_tags", "")).split(",")]
        hint = did_you_mean(ctx.get("tag", ""), tags) or "use one of: " + ", ".join(tags)
        return f"unknown {key} '{ctx.get('tag')}'", hint, (*path, key)
    if kind == "union_tag_not_found":
        key = str(ctx.get("discriminator", "type")).strip("'")
        return f"missing key '{key}'", None, path
    if kind == "literal_error":
        return (
            f"expected {ctx.get('expected')}, got {_show(value)}",
            did_you_mean(
                str(value),
                [
                    s.strip("' ")
                    for s in str(ctx.get("expected", "")).replace(" or ", ", ").split(",")
                ],
            ),
            path,
        )
    if kind in ("too_short", "too_long"):
        return _length_message(kind, ctx, value), None, path
    if kind in _NUMBER_TYPES:
        return f"expected a number, got {_show(value)}", None, path
    if kind in _WHOLE_NUMBER_TYPES:
        return f"expected a whole number, got {_show(value)}", None, path
    if kind == "expected":  # a validator's own `expected ...`: the value shown as above
        return f"{error['msg']}, got {_show(value)}", None, path
    if kind in _SIMPLE:
        return f"{_SIMPLE[kind]}, got {_show(value)}", None, path
    if kind == "string_too_short":
        return "must not be empty", None, path
    if kind in _RANGES:
        op, bound = _RANGES[kind]
        return f"must be {op} {_number(ctx.get(bound))}, got {_number(value)}", None, path
    return str(error["msg"]).removeprefix("Value error, "), None, path


def _length_message(kind: str, ctx: dict[str, Any], value: Any) -> str:
    """`expected 3 values, got 2` (tuples) or `expected at least 1 value, got 0` (lists)."""
    got = ctx.get("actual_length", len(value) if hasattr(value, "__len__") else "?")
    if isinstance(value, (list, tuple)) and kind == "too_long" and "max_length" in ctx:
        return f"expected {ctx['max_length']} values, got {got}"
    if (
        kind == "too_short"
        and isinstance(value, (list, tuple))
        and ctx.get("field_type") == "Tuple"
    ):
        return f"expected {ctx.get('min_length')} values, got {got}"
    bound = "at least" if kind == "too_short" else "at most"
    count = ctx.get("min_length" if kind == "too_short" else "max_length")
    noun = "value" if count == 1 else "values"
    return f"expected {bound} {count} {noun}, got {got}"


def validation_diagnostics(
    error: ValidationError, model: type[BaseModel], locator: Locator
) -> list[Diagnostic]:
    """One diagnostic per pydantic error of validating `model` at `locator`."""
    result: list[Diagnostic] = []
    seen: set[tuple[KeyPath, str]] = set()
    for item in error.errors(include_url=False):
        path, parent = _resolve(model, tuple(item["loc"]))
        message, hint, path = _message(item, path, parent)
        if (path, message) in seen:
            continue
        seen.add((path, message))
        result.append(locator.diagnostic(path, message, hint=hint))
    return result


def _mentions_any(tp: Any) -> bool:
    """Whether a field type holds raw data somewhere (`dict[str, Any]`): validated
    elsewhere, as an inline mechanism is."""
    return tp is Any or any(_mentions_any(arg) for arg in typing.get_args(tp))


def _keyword(tp: Any, value: str) -> bool:
    """Whether `value` is one of the words a field of type `tp` takes (`Literal["off"]`)."""
    if typing.get_origin(tp) is typing.Literal:
        return value in typing.get_args(tp)
    return any(_keyword(arg, value) for arg in typing.get_args(tp))


def _has(node: Any, part: str | int) -> bool:
    """Whether `node[part]` is an item of a dict, list or tuple."""
    if isinstance(node, dict):
        return part in node
    return isinstance(node, (list, tuple)) and isinstance(part, int) and 0 <= part < len(node)


def _validated(model: BaseModel, path: KeyPath) -> tuple[bool, Any]:
    """(found, value) at the data key `path` of a validated model: (False, None) where the
    path leaves the models (raw data, a key the model does not keep)."""
    node: Any = model
    field_type: Any = None
    for part in path:
        if isinstance(node, BaseModel):
            field = type(node).model_fields.get(part) if isinstance(part, str) else None
            if field is None or _mentions_any(field.annotation):
                return False, None
            node, field_type = getattr(node, str(part)), field.annotation
        elif _has(node, part):
            node, field_type = node[part], None
        else:
            return False, None
    if isinstance(node, str) and field_type is not None and _keyword(field_type, node):
        return False, None  # `accuracy: off`: the word the key takes, whatever YAML 1.1 reads
    return True, node


def plain_boolean_diagnostics(model: BaseModel, locator: Locator) -> list[Diagnostic]:
    """Errors for the plain `yes`, `no`, `on`, `off` of `locator`'s data that `model` (valid)
    keeps as text: a YAML 1.1 reader takes them for booleans. Where a key takes true or
    false they are booleans here too, and where it takes that word they mean it."""
    found = []
    prefix = locator.prefix
    for path, text in locator.tree.plain_booleans.items():
        if path[: len(prefix)] != prefix:
            continue
        known, value = _validated(model, path[len(prefix) :])
        if known and not isinstance(value, bool):
            found.append(
                locator.diagnostic(
                    path[len(prefix) :],
                    locator.tree.plain_boolean(path) or text,
                    hint=f"quote it ('{text}') if it is text",
                )
            )
    return found
