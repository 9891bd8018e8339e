"""Safe YAML reading that keeps the 1-based line and column of every key and item.

Scalars follow the YAML 1.2 core schema (`true`/`false` only are booleans, `1.0e7` and `2e6`
are numbers, integers are decimal or `0x` hexadecimal, dates stay text), so that `on`, `no`
or `2024-01-01` never change type behind an engineer's back. Anchors, aliases and `<<` merge
keys work; tags other than the core ones are refused by the safe loader.

A file means what it says to every YAML reader: a plain (unquoted) scalar that a YAML 1.1
reader (PyYAML's default, many tools) reads as another number is refused with a hint to
quote it or write the number (`1:30` is 90 there, `010` is 8, `1_000` and `0b101` numbers);
so is a plain key it reads as a number or a boolean (`on:`). A plain `yes`, `no`, `on`,
`off` value (a boolean there) is kept in `SourceTree.plain_booleans`: the loader accepts it
only where a key takes true or false (`loadcases.schema.errors.plain_boolean_diagnostics`).
A key holding a hidden character (`loadcases.foundation.clip`: a control, bidirectional or
zero-width character) is refused, and so is a text value holding one (line breaks and tabs
aside): keys become names in files, messages and workbooks.
"""

from __future__ import annotations

import hashlib
import pickle
import re
from collections import OrderedDict
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from loadcases.foundation.clip import clip, describe_character, hidden_character
from loadcases.foundation.diagnostics import Diagnostic, InputError, Severity
from loadcases.foundation.limits import MAX_YAML_DEPTH, MAX_YAML_VALUES

__all__ = ["KeyPath", "Locator", "SourceTree", "format_key", "load_yaml", "parse_yaml"]

KeyPath = tuple[str | int, ...]
_MERGE_TAG = "tag:yaml.org,2002:merge"
_QUOTES = ("'", '"')
_CORE_TAGS = frozenset(
    f"tag:yaml.org,2002:{name}" for name in ("str", "int", "float", "bool", "null", "seq", "map")
)


class _CoreLoader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 core-schema booleans and floats, no timestamps."""


_CoreLoader.yaml_implicit_resolvers = {
    first: [
        (tag, rx)
        for tag, rx in resolvers
        if tag.rsplit(":", 1)[-1] not in ("bool", "int", "float", "timestamp")
    ]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_CoreLoader.add_implicit_resolver(
    "tag:yaml.org,2002:bool", re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF")
)
_CoreLoader.add_implicit_resolver(
    "tag:yaml.org,2002:int",
    re.compile(r"^(?:[-+]?(?:0|[1-9][0-9]*)|0x[0-9a-fA-F]+)$"),
    list("-+0123456789"),
)
_CoreLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?
                   |[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$""",
        re.X,
    ),
    list("-+0123456789."),
)


# What a YAML 1.1 reader makes of a plain scalar (PyYAML's resolver and constructor).
_YAML11_RESOLVER = yaml.resolver.Resolver()
_YAML11_CONSTRUCTOR = yaml.constructor.SafeConstructor()


def _yaml11_reading(node: Node, ours: Any) -> Any:
    """What a YAML 1.1 reader makes of the plain scalar `node` (a boolean or a number)
    when it is not `ours`, the value read here; else None."""
    if not isinstance(node, ScalarNode) or node.style is not None:
        return None
    tag = _YAML11_RESOLVER.resolve(ScalarNode, node.value, (True, False))
    if tag.rsplit(":", 1)[-1] not in ("bool", "int", "float"):
        return None
    theirs = _YAML11_CONSTRUCTOR.yaml_constructors[tag](
        _YAML11_CONSTRUCTOR, ScalarNode(tag, node.value)
    )
    numbers = (int, float)
    if isinstance(theirs, bool) or isinstance(ours, bool) or not isinstance(ours, numbers):
        same = type(theirs) is type(ours) and theirs == ours
    else:
        same = theirs == ours or (theirs != theirs and ours != ours)  # nan is nan
    return None if same else theirs


def yaml11_text(text: str, reading: Any) -> str:
    """`YAML 1.1 reads the plain on as the boolean true` (`reading` is True)."""
    what = f"the boolean {str(reading).lower()}" if isinstance(reading, bool) else "the number"
    if not isinstance(reading, bool):
        what += f" {reading:g}" if isinstance(reading, float) else f" {reading}"
    return f"YAML 1.1 reads the plain {clip(text)} as {what}"


def format_key(path: KeyPath) -> str:
    """Dotted text of a key path: `('joints', 'hinge', 'bodies', 1)` -> `joints.hinge.bodies[1]`."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text


@dataclass
class SourceTree:
    """A YAML document as plain Python data, with the position of every key and item.

    `data` holds dict/list/str/int/float/bool/None; `diagnostics` holds non-fatal problems
    found while reading (duplicate keys).
    """

    file: str
    data: Any
    keys: dict[KeyPath, tuple[int, int]] = field(default_factory=dict)
    values: dict[KeyPath, tuple[int, int]] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # plain `yes`, `no`, `on`, `off` (booleans to YAML 1.1): path -> the text as written
    plain_booleans: dict[KeyPath, str] = field(default_factory=dict)
    # items merged in from another file (`extends:`): item path -> the file it was written in
    origins: dict[KeyPath, str] = field(default_factory=dict)

    def file_at(self, path: KeyPath) -> str:
        """The file the key at `path` was written in (`file`, or a base file's)."""
        for end in range(min(len(path), 2), 0, -1):
            found = self.origins.get(tuple(path[:end]))
            if found is not None:
                return found
        return self.file

    def position(self, path: KeyPath) -> tuple[int, int]:
        """(line, col) of the key or item at `path`, else of its nearest known ancestor."""
        for end in range(len(path), -1, -1):
            found = self.keys.get(tuple(path[:end]))
            if found is not None:
                return found
        return (1, 1)

    def value_position(self, path: KeyPath) -> tuple[int, int]:
        """(line, col) of the first character of the value at `path` (inside any quotes)."""
        found = self.values.get(tuple(path))
        return found if found is not None else self.position(path)

    def plain_boolean(self, path: KeyPath) -> str | None:
        """`YAML 1.1 reads the plain on as the boolean true` when the value at `path` is
        such a word, else None."""
        text = self.plain_booleans.get(tuple(path))
        return None if text is None else yaml11_text(text, text.lower() in ("yes", "on"))

    def plain_boolean_hint(self, path: KeyPath) -> str | None:
        """The hint for a problem of the value at `path` when it is a plain `on` & co.
        Quoting it is no remedy: this reader takes it as that text already, and the text
        is what was refused."""
        reading = self.plain_boolean(path)
        return None if reading is None else f"{reading}: write the value you mean"


@dataclass(frozen=True)
class Locator:
    """Positions and diagnostics for keys of one model inside a tree (`prefix` for an inline
    mechanism: `("mechanism",)`)."""

    tree: SourceTree
    prefix: KeyPath = ()

    @property
    def data(self) -> Any:
        """The plain data at `prefix`."""
        data = self.tree.data
        for part in self.prefix:
            data = data[part]
        return data

    def where(self, path: KeyPath) -> tuple[str, int, int]:
        """(file, line, col) of the key at `path` (relative to `prefix`)."""
        full = (*self.prefix, *path)
        return (self.tree.file_at(full), *self.tree.position(full))

    def diagnostic(
        self,
        path: KeyPath,
        message: str,
        *,
        hint: str | None = None,
        severity: Severity = "error",
        offset: int | None = None,
        of_value: bool = True,
    ) -> Diagnostic:
        """A diagnostic at the key `path`; with `offset`, at that character of its value.
        `of_value` False: the problem is the key being given at all (a setting that does
        nothing there), so a plain `off` written as its value earns no YAML 1.1 hint."""
        full = (*self.prefix, *path)
        if hint is None and of_value:
            hint = self.tree.plain_boolean_hint(full)
        line, col = self.tree.position(full)
        if offset is not None and full in self.tree.values:
            line, col = self.tree.values[full]
            col += offset
        file = self.tree.file_at(full)
        return Diagnostic(file, line, col, format_key(full), message, severity, hint)


class _Builder:
    """Turns composed nodes into plain data, recording positions and duplicate keys."""

    def __init__(self, tree: SourceTree) -> None:
        self.tree = tree
        self.constructor = _CoreLoader("")
        self.stack: set[int] = set()
        self.count = 0  # values built, aliases expanded
        self.problems: list[Diagnostic] = []  # hidden characters, YAML 1.1 numbers

    def problem(self, path: KeyPath, message: str, hint: str) -> None:
        line, col = self.tree.position(path)
        self.problems.append(
            Diagnostic(self.tree.file, line, col, format_key(path), message, hint=hint)
        )

    def build(self, node: Node, path: KeyPath) -> Any:
        if id(node) in self.stack:
            raise yaml.MarkedYAMLError(
                problem="an alias refers to itself", problem_mark=node.start_mark
            )
        self.count += 1
        if self.count > MAX_YAML_VALUES or len(path) > MAX_YAML_DEPTH:
            raise yaml.MarkedYAMLError(
                problem=(
                    f"more than {MAX_YAML_VALUES:,} values once aliases are expanded"
                    if self.count > MAX_YAML_VALUES
                    else f"nested more than {MAX_YAML_DEPTH} levels deep"
                ),
                problem_mark=node.start_mark,
            )
        self.stack.add(id(node))
        try:
            return self._build(node, path)
        finally:
            self.stack.discard(id(node))

    def _build(self, node: Node, path: KeyPath) -> Any:
        if node.tag not in _CORE_TAGS:
            raise yaml.MarkedYAMLError(
                problem=f"tag {node.tag} is not allowed", problem_mark=node.start_mark
            )
        line, col = node.start_mark.line + 1, node.start_mark.column + 1
        if (
            isinstance(node, ScalarNode)
            and node.style in _QUOTES
            and node.start_mark.line == node.end_mark.line
        ):
            col += 1
        self.tree.values.setdefault(path, (line, col))
        if isinstance(node, MappingNode):
            return self._mapping(node, path)
        if isinstance(node, SequenceNode):
            items = []
            for index, item in enumerate(node.value):
                sub = (*path, index)
                self.tree.keys[sub] = (item.start_mark.line + 1, item.start_mark.column + 1)
                items.append(self.build(item, sub))
            return items
        return self._scalar(node, path)

    def _scalar(self, node: Node, path: KeyPath) -> Any:
        value = self.constructor.construct_object(node, deep=True)
        hidden = (
            hidden_character(value.replace("\n", "").replace("\t", ""))
            if isinstance(value, str)
            else None
        )
        if hidden is not None:
            self.problem(
                path,
                f"the value holds {describe_character(hidden)}, a character not shown as written",
                "retype the value: text holds no control, bidirectional or zero-width "
                "characters (line breaks and tabs aside)",
            )
        reading = _yaml11_reading(node, value)
        if isinstance(reading, bool):
            self.tree.plain_booleans[path] = node.value
        elif reading is not None:
            self.problem(
                path,
                yaml11_text(node.value, reading),
                f"quote it ('{clip(node.value)}') if it is text, or write the number you mean",
            )
        return value

    def _key(self, key_node: Node, path: KeyPath) -> str:
        """The text of a mapping key (problems recorded at `path`, its own)."""
        key = self.constructor.construct_object(key_node, deep=True)
        text = key if isinstance(key, str) else str(key)
        hidden = hidden_character(text)
        if hidden is not None:
            self.problem(
                path,
                f"the key holds {describe_character(hidden)}, a character not shown as written",
                "retype the key: keys and names hold no control, bidirectional or zero-width "
                "characters",
            )
        reading = _yaml11_reading(key_node, key)
        if reading is not None:
            self.problem(
                path,
                yaml11_text(key_node.value, reading).replace("plain", "plain key", 1),
                f"quote it ('{clip(key_node.value)}')",
            )
        return text

    def _pairs(self, node: MappingNode) -> list[tuple[Node, Node, bool]]:
        """Own key/value pairs first, then those merged in by `<<` (flagged True)."""
        own: list[tuple[Node, Node, bool]] = []
        merged: list[tuple[Node, Node, bool]] = []
        for key, value in node.value:
            if key.tag == _MERGE_TAG:
                sources = value.value if isinstance(value, SequenceNode) else [value]
                for source in sources:
                    if isinstance(source, MappingNode):
                        merged.extend((k, v, True) for k, v, _ in self._pairs(source))
            else:
                own.append((key, value, False))
        return own + merged

    def _mapping(self, node: MappingNode, path: KeyPath) -> dict[Any, Any]:
        result: dict[Any, Any] = {}
        first: dict[Any, int] = {}
        for key_node, value_node, merged in self._pairs(node):
            key = self.constructor.construct_object(key_node, deep=True)
            key = key if isinstance(key, str) else str(key)
            line, col = key_node.start_mark.line + 1, key_node.start_mark.column + 1
            if key in result:
                if not merged:
                    self._duplicate(path, key, line, col, first[key])
                continue
            first[key] = line
            sub = (*path, key)
            self.tree.keys[sub] = (line, col)
            self._key(key_node, sub)
            result[key] = self.build(value_node, sub)
        return result

    def _duplicate(self, path: KeyPath, key: str, line: int, col: int, first: int) -> None:
        self.tree.diagnostics.append(
            Diagnostic(
                self.tree.file,
                line,
                col,
                format_key((*path, key)),
                f"duplicate key (first given on line {first})",
                hint="remove one of them: YAML keeps only one value per key",
            )
        )


def parse_yaml(text: str, file: str) -> SourceTree:
    """Parse YAML `text` (reported as `file`); raises InputError on a syntax error."""
    tree = SourceTree(file=file, data=None)
    try:
        node = yaml.compose(text, Loader=_CoreLoader)
        builder = _Builder(tree)
        tree.data = builder.build(node, ()) if node is not None else None
        if builder.problems:  # before anything reads the names or numbers
            raise InputError([*tree.diagnostics, *builder.problems])
    except RecursionError:  # the composer recurses once per nesting level
        raise InputError(
            [
                Diagnostic(
                    file,
                    1,
                    1,
                    "",
                    f"YAML syntax error: nested more than {MAX_YAML_DEPTH} levels deep",
                )
            ]
        ) from None
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        line, col = (mark.line + 1, mark.column + 1) if mark is not None else (0, 0)
        problem = error.problem or error.context or "invalid YAML"
        if error.context and error.problem:
            problem = f"{error.problem} ({error.context})"
        raise InputError(
            [
                Diagnostic(
                    file, line, col, "", f"YAML syntax error: {problem}", hint=_syntax_hint(problem)
                )
            ]
        ) from None
    except yaml.YAMLError as error:
        raise InputError([Diagnostic(file, 0, 0, "", f"YAML error: {error}")]) from None
    return tree


def _syntax_hint(problem: str) -> str | None:
    """A fix suggestion for the commonest YAML slips."""
    if "tab" in problem:
        return "indent with spaces, not tabs"
    if "mapping values are not allowed" in problem:
        return "quote text that contains ': ' or put a space after each ':'"
    return None


def load_yaml(path: str | Path) -> SourceTree:
    """Read the YAML file at `path`; raises InputError if it cannot be read or parsed. A
    file read before with the same contents, in this process or (through the user cache
    folder) another, is not parsed again (a copy of its tree)."""
    file = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        reason = error.strerror if isinstance(error, OSError) and error.strerror else str(error)
        raise InputError([Diagnostic(file, 0, 0, "", f"cannot read file: {reason}")]) from None
    key = (file, text)
    parsed = _PARSED.get(key)
    if parsed is None:
        parsed = pickle.dumps(_stored_or_parsed(text, file), protocol=pickle.HIGHEST_PROTOCOL)
        _remember(key, parsed)
    else:
        _PARSED.move_to_end(key)
    return pickle.loads(parsed)  # a fresh copy: callers put parameters into the data


def _stored_or_parsed(text: str, file: str) -> SourceTree:
    """The tree of `text` from the user cache folder (`loadcases.yamlfiles.parse_cache`),
    else parsed and stored there."""
    from loadcases.yamlfiles import parse_cache

    stored = parse_cache.recall(file, text, _parser_identity())
    if stored is not None:
        data, keys, values, plain_booleans = stored
        return SourceTree(
            file=file, data=data, keys=keys, values=values, plain_booleans=plain_booleans
        )
    tree = parse_yaml(text, file)
    if not tree.diagnostics:
        parse_cache.store(
            file, text, _parser_identity(), tree.data, tree.keys, tree.values, tree.plain_booleans
        )
    return tree


@lru_cache(maxsize=1)
def _parser_identity() -> bytes:
    """What a parsed tree depends on besides its file: this module's source, the input
    limits and PyYAML's version."""
    digest = hashlib.sha256(Path(__file__).read_bytes())
    digest.update(repr((MAX_YAML_VALUES, MAX_YAML_DEPTH, yaml.__version__)).encode())
    return digest.digest()


def _remember(key: tuple[str, str], parsed: bytes) -> None:
    """Keep a parsed tree, forgetting the least recently read ones beyond the budget."""
    global _parsed_size
    _PARSED[key] = parsed
    _parsed_size += _cost(key, parsed)
    while len(_PARSED) > 1 and (_parsed_size > _PARSED_BUDGET or len(_PARSED) > _PARSED_FILES):
        old, tree = _PARSED.popitem(last=False)
        _parsed_size -= _cost(old, tree)


def _cost(key: tuple[str, str], parsed: bytes) -> int:
    """Bytes (about) a kept tree holds: its file's text and its pickle."""
    return len(key[1]) + len(parsed)


# The trees of the files last read, by name and contents: a set reads its mechanism file
# once per case (the door: 22 times) and each run reads its files again; unpickling a
# tree is about ten times faster than parsing it. Bounded by count and by bytes (a long
# hardpoint table is one file).
_PARSED: OrderedDict[tuple[str, str], bytes] = OrderedDict()
_PARSED_FILES = 256
_PARSED_BUDGET = 16 * 2**20
_parsed_size = 0
