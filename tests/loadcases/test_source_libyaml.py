"""YAML files are composed by libyaml when PyYAML has it (loadcases.source._compose): the
same data, key and value positions and diagnostics as the pure-Python loader on every YAML
file shipped (library, benchmarks, templates, repro inputs) and on tricky text; a text
libyaml refuses gets the pure-Python loader's own error (message, line, column, hint)."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from loadcases import source
from loadcases.diagnostics import InputError

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted(
    p
    for folder in ("loadcases/library", "benchmarks/models", "templates", "tests")
    for p in (ROOT / folder).rglob("*.yaml")
)
TRICKY = [
    "a: 1.0e-3\nb: .inf\nc: yes\nd: True\ne: 0x1F\nf: ~\ng: 2026-11-28\n",
    "x: &anchor {p: [1, 2, 'three'], q: \"4\"}\ny: *anchor\nz: {<<: *anchor, q: 5}\n",
    "dup: 1\ndup: 2\n",
    "text: |\n  two\n  lines\nfolded: >\n  one\n  line\n",
    "\ufeffbom: 1\r\nwin: [a, b]\r\n",
]


def _python(text: str, file: str = "f.yaml"):
    saved = source._LIBYAML
    source._LIBYAML = False
    try:
        return source.parse_yaml(text, file)
    finally:
        source._LIBYAML = saved


def _same(a, b) -> None:
    assert a.data == b.data
    assert a.keys == b.keys
    assert a.values == b.values

    def said(tree):
        return [(d.line, d.column, d.key, d.message) for d in tree.diagnostics]

    assert said(a) == said(b)


def test_libyaml_is_used_here() -> None:
    assert yaml.__with_libyaml__ and source._LIBYAML


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT)))
def test_shipped_files_compose_alike(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    try:
        expected = _python(text, str(path))
    except InputError as error:
        with pytest.raises(InputError) as raised:
            source.parse_yaml(text, str(path))
        assert str(raised.value) == str(error)
        return
    _same(source.parse_yaml(text, str(path)), expected)


@pytest.mark.parametrize("text", TRICKY)
def test_tricky_text_composes_alike(text: str) -> None:
    _same(source.parse_yaml(text, "f.yaml"), _python(text))


@pytest.mark.parametrize(
    "text",
    [
        "a:\n\tb: 1\n",  # a tab: the hint to indent with spaces
        "a: b: c\n",  # mapping values not allowed: the hint to quote
        "a: [1, 2\n",  # unclosed flow sequence
        "[" * 1500 + "]" * 1500,  # beyond libyaml's 1000 levels and our limit
        "k:\n" + "".join(" " * i + "k:\n" for i in range(1, 150)),  # beyond our 100 levels
    ],
)
def test_refused_text_gets_the_python_loaders_error(text: str) -> None:
    with pytest.raises(InputError) as expected:
        _python(text)
    with pytest.raises(InputError) as raised:
        source.parse_yaml(text, "f.yaml")
    got, want = raised.value.diagnostics, expected.value.diagnostics
    assert [(d.line, d.column, d.message, d.hint) for d in got] == [
        (d.line, d.column, d.message, d.hint) for d in want
    ]
