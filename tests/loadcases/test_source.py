"""YAML source: plain data, positions of keys and items, duplicates and syntax errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.yamlfiles.source import Locator, format_key, load_yaml, parse_yaml

TEXT = """\
name: door
bodies:
  door: {mass: 30, cm: [1, 2, 3]}
flags: [on, yes, true, 1.0e7, 2e6, 2024-01-01]
joints:
  hinge:
    bodies:
      - door
      - ground
    when: "angle(hinge) > 1"
"""


def test_data_follows_yaml_core_schema() -> None:
    tree = parse_yaml(TEXT, "a.yaml")
    assert tree.data["bodies"]["door"] == {"mass": 30, "cm": [1, 2, 3]}
    assert tree.data["flags"] == ["on", "yes", True, 1.0e7, 2.0e6, "2024-01-01"]
    assert tree.diagnostics == []


def test_positions_of_keys_and_items() -> None:
    tree = parse_yaml(TEXT, "a.yaml")
    assert tree.position(("bodies", "door")) == (3, 3)
    assert tree.position(("bodies", "door", "cm")) == (3, 20)
    assert tree.position(("bodies", "door", "cm", 2)) == (3, 31)
    assert tree.position(("joints", "hinge", "bodies", 1)) == (9, 9)
    # nearest known ancestor for a missing path
    assert tree.position(("joints", "hinge", "axis")) == (6, 3)
    # value position is inside the quotes
    assert tree.value_position(("joints", "hinge", "when")) == (10, 12)


def test_locator_offsets_into_values() -> None:
    tree = parse_yaml(TEXT, "a.yaml")
    diag = Locator(tree, ("joints",)).diagnostic(("hinge", "when"), "bad", offset=6)
    assert diag.format() == "a.yaml:10:18: error: joints.hinge.when: bad"


def test_duplicate_keys_reported() -> None:
    tree = parse_yaml("a: 1\nb: 2\na: 3\n", "d.yaml")
    assert tree.data == {"a": 1, "b": 2}
    assert [d.format() for d in tree.diagnostics] == [
        "d.yaml:3:1: error: a: duplicate key (first given on line 1)\n"
        "d.yaml:3:1: hint: remove one of them: YAML keeps only one value per key"
    ]


def test_merge_keys_and_aliases() -> None:
    tree = parse_yaml("base: &b {mass: 1, cm: [0, 0, 0]}\narm: {<<: *b, mass: 2}\n", "m.yaml")
    assert tree.data["arm"] == {"mass": 2, "cm": [0, 0, 0]}
    assert tree.diagnostics == []


def test_syntax_error_has_position() -> None:
    with pytest.raises(InputError) as raised:
        parse_yaml("a: b: c\n", "s.yaml")
    assert str(raised.value) == (
        "s.yaml:1:5: error: YAML syntax error: mapping values are not "
        "allowed here\ns.yaml:1:5: hint: quote text that contains ': ' "
        "or put a space after each ':'"
    )


def test_unsafe_tags_refused() -> None:
    with pytest.raises(InputError, match="YAML syntax error"):
        parse_yaml("a: !!python/object/apply:os.system ['echo hi']\n", "u.yaml")


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="cannot read file"):
        load_yaml(tmp_path / "nope.yaml")


def test_format_key() -> None:
    assert format_key(("joints", "hinge", "bodies", 1)) == "joints.hinge.bodies[1]"
    assert format_key(()) == ""


def test_parsed_trees_kept_within_budget(tmp_path: Path, monkeypatch) -> None:
    """A tree read again is a copy of the kept one (not parsed again); the least recently
    read trees are forgotten beyond the byte budget, never the one just read."""
    import loadcases.yamlfiles.source as source
    from loadcases.yamlfiles import parse_cache

    monkeypatch.setattr(source, "_PARSED", source.OrderedDict())
    monkeypatch.setattr(source, "_parsed_size", 0)
    monkeypatch.setattr(parse_cache, "recall", lambda *a: None)  # memory alone
    parsed = []
    real = source.parse_yaml
    monkeypatch.setattr(source, "parse_yaml", lambda t, f: parsed.append(f) or real(t, f))
    files = []
    for n in range(3):
        files.append(tmp_path / f"f{n}.yaml")
        files[-1].write_text(f"name: f{n}\nvalues: {list(range(50))}\n", encoding="utf-8")
    first = load_yaml(files[0])
    first.data["name"] = "changed"  # a copy: the kept tree is untouched
    assert load_yaml(files[0]).data["name"] == "f0"
    assert parsed == [str(files[0])]
    one = source._cost(*next(iter(source._PARSED.items())))
    monkeypatch.setattr(source, "_PARSED_BUDGET", 2 * one + one // 2)  # two trees fit
    for path in files:
        load_yaml(path)
    assert [key[0] for key in source._PARSED] == [str(files[1]), str(files[2])]
    assert source._parsed_size == sum(source._cost(k, v) for k, v in source._PARSED.items())
    load_yaml(files[0])  # forgotten: parsed again
    assert parsed == [str(f) for f in (files[0], files[1], files[2], files[0])]
    monkeypatch.setattr(source, "_PARSED_BUDGET", 1)  # smaller than any tree: keeps the last
    load_yaml(files[1])
    assert [key[0] for key in source._PARSED] == [str(files[1])]
