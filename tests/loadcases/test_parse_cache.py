"""Parsed YAML trees kept in the cache folder (loadcases.yamlfiles.parse_cache): a stored
tree is the one the parser gives, to the last position and value; a broken, foreign or
outdated entry is parsed again; the folder stays bounded; a cache that cannot be written
costs only the parse."""

from __future__ import annotations

import marshal
import os
from pathlib import Path

import numpy as np
import pytest

import loadcases.yamlfiles.source as source
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from loadcases.yamlfiles import parse_cache
from loadcases.yamlfiles.source import load_yaml, parse_yaml

ROOT = Path(__file__).resolve().parents[2]

# Values a cache format could get wrong: NaN and infinities, -0.0, an integer beyond 64
# bits, text that only looks like a number or a boolean, non-ASCII keys, anchors and merge
# keys, empty values, nested lists, positions inside quotes.
AWKWARD = """\
name: "quoted: text"
numbers: [.nan, .inf, -.inf, -0.0, 1.0e-300, 123456789012345678901234567890, 0x1F, +12]
texts: ['1.0', "true", on, no, 2024-01-01, ~, null, '']
länge: 1.5
base: &base {mass: 2 kg, inertia: [1, 2, 3]}
derived:
  <<: *base
  mass: 3 kg
empty:
lists: [[1, [2, [3]]], {a: [b, {c: d}]}]
block: |
  two
  lines
"""


@pytest.fixture()
def folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh cache folder, nothing kept in memory, and a count of the texts parsed."""
    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(source, "_PARSED", source.OrderedDict())
    monkeypatch.setattr(source, "_parsed_size", 0)
    return tmp_path / "cache" / "yaml"


@pytest.fixture()
def parsed(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Files parsed (not read from a cache) from now on."""
    names: list[str] = []
    real = source.parse_yaml
    monkeypatch.setattr(source, "parse_yaml", lambda t, f: names.append(f) or real(t, f))
    return names


def _fresh_process() -> None:
    """Forget the trees kept in memory, as a new command would start."""
    source._PARSED.clear()
    source._parsed_size = 0


def _whole(tree: source.SourceTree) -> str:
    """Every value, type and position of a tree (repr tells 1 from 1.0 from True, and NaN
    equals itself)."""
    return repr(
        (tree.file, tree.data, tree.keys, tree.values, tree.diagnostics, tree.plain_booleans)
    )


def test_stored_trees_are_the_parsed_ones(folder: Path) -> None:
    """Every YAML file of the library and of the tests, and a text of awkward values: the
    tree read back from the cache equals the parsed one in every value and position."""
    files = sorted((ROOT / "loadcases" / "library").rglob("*.yaml"))
    files += sorted((ROOT / "tests").rglob("*.yaml"))
    texts = [(str(path), path.read_text(encoding="utf-8")) for path in files]
    texts.append(("awkward.yaml", AWKWARD))
    stored = 0
    for name, text in texts:
        try:
            tree = parse_yaml(text, name)
        except source.InputError:
            continue  # a bad test input: nothing to store
        if tree.diagnostics:
            continue
        identity = source._parser_identity()
        parse_cache.store(
            name, text, identity, tree.data, tree.keys, tree.values, tree.plain_booleans
        )
        back = parse_cache.recall(name, text, identity)
        assert back is not None, name
        data, keys, values, plain_booleans = back
        again = source.SourceTree(name, data, keys, values, plain_booleans=plain_booleans)
        assert _whole(again) == _whole(tree), name
        stored += 1
    assert stored >= 100
    assert len(list(folder.glob("*.tree"))) == stored


def test_a_file_is_parsed_once_across_commands(folder: Path, parsed: list[str], tmp_path) -> None:
    """The second command reading an unchanged file reads its tree from the cache; a changed
    file is parsed again."""
    path = tmp_path / "awkward.yaml"
    path.write_text(AWKWARD, encoding="utf-8")
    first = load_yaml(path)
    _fresh_process()
    second = load_yaml(path)
    assert parsed == [str(path)]
    assert _whole(second) == _whole(first)
    assert second.value_position(("name",)) == (1, 8)  # inside the quotes
    path.write_text(AWKWARD.replace("1.5", "2.5"), encoding="utf-8")
    _fresh_process()
    assert load_yaml(path).data["länge"] == 2.5
    assert parsed == [str(path)] * 2


@pytest.mark.parametrize(
    "damage",
    [
        lambda b: b[: len(b) // 2],  # cut short (a full disk)
        lambda b: b"\x00" * len(b),  # garbage
        lambda b: __import__("marshal").dumps((99, "other", {}, {}, {}, {})),  # another layout
        lambda b: __import__("marshal").dumps([1, 2, 3]),  # not an entry at all
    ],
    ids=["truncated", "garbage", "foreign", "not-a-tuple"],
)
def test_a_broken_entry_is_parsed_again(folder: Path, parsed: list[str], tmp_path, damage) -> None:
    path = tmp_path / "awkward.yaml"
    path.write_text(AWKWARD, encoding="utf-8")
    first = load_yaml(path)
    (entry,) = folder.glob("*.tree")
    entry.write_bytes(damage(entry.read_bytes()))
    _fresh_process()
    assert _whole(load_yaml(path)) == _whole(first)
    assert parsed == [str(path)] * 2
    _fresh_process()
    load_yaml(path)  # stored whole again by the second parse
    assert parsed == [str(path)] * 2


def test_another_parser_makes_another_entry(folder: Path, parsed, tmp_path, monkeypatch) -> None:
    """A change of the parser's source (its identity) is a new entry: trees of the old
    parser are never read by the new one."""
    path = tmp_path / "a.yaml"
    path.write_text("a: 1\n", encoding="utf-8")
    load_yaml(path)
    monkeypatch.setattr(source, "_parser_identity", lambda: b"another parser")
    _fresh_process()
    load_yaml(path)
    assert parsed == [str(path)] * 2
    assert len(list(folder.glob("*.tree"))) == 2


def test_the_same_text_under_another_name_is_another_entry(folder: Path, parsed, tmp_path):
    """Diagnostics name the file: a tree is stored per file name."""
    one, two = tmp_path / "one.yaml", tmp_path / "two.yaml"
    for path in (one, two):
        path.write_text("a: 1\n", encoding="utf-8")
    assert load_yaml(one).file == str(one)
    assert load_yaml(two).file == str(two)
    assert parsed == [str(one), str(two)]


def test_trees_with_duplicate_keys_are_not_stored(folder: Path, parsed, tmp_path) -> None:
    path = tmp_path / "dup.yaml"
    path.write_text("a: 1\na: 2\n", encoding="utf-8")
    assert len(load_yaml(path).diagnostics) == 1
    _fresh_process()
    assert len(load_yaml(path).diagnostics) == 1
    assert parsed == [str(path)] * 2
    assert not folder.exists() or not list(folder.glob("*.tree"))


def test_the_folder_keeps_the_entries_written_last(folder: Path, tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(parse_cache, "MAX_ENTRIES", 3)
    for n in range(5):
        parse_cache.store(f"f{n}.yaml", f"n: {n}\n", b"p", {"n": n}, {}, {})
        entry = parse_cache._entry(f"f{n}.yaml", f"n: {n}\n", b"p")
        os.utime(entry, ns=(n * 10**9, n * 10**9))  # distinct times even on a coarse clock
    kept = [parse_cache.recall(f"f{n}.yaml", f"n: {n}\n", b"p") for n in range(5)]
    assert [k is not None for k in kept] == [False, False, True, True, True]
    assert len(list(folder.glob("*.tree"))) == 3
    assert not list(folder.glob(".*.tmp"))  # no temporary file left (loadcases.foundation.atomic)


def test_a_cache_that_cannot_be_written_costs_only_the_parse(parsed, tmp_path, monkeypatch):
    blocker = tmp_path / "blocker"
    blocker.write_text("a file where the cache folder should be", encoding="utf-8")
    monkeypatch.setenv("LOADS_CACHE_DIR", str(blocker))
    monkeypatch.setattr(source, "_PARSED", source.OrderedDict())
    path = tmp_path / "a.yaml"
    path.write_text("a: [1, 2]\n", encoding="utf-8")
    assert load_yaml(path).data == {"a": [1, 2]}
    _fresh_process()
    assert load_yaml(path).data == {"a": [1, 2]}
    assert parsed == [str(path)] * 2


def test_a_long_text_is_not_stored(folder: Path, parsed, tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(parse_cache, "MAX_TEXT", 10)
    path = tmp_path / "a.yaml"
    path.write_text("values: [1, 2, 3, 4]\n", encoding="utf-8")
    load_yaml(path)
    _fresh_process()
    load_yaml(path)
    assert parsed == [str(path)] * 2


def _scaled(value: object, factor: float) -> object:
    """`value` (an entry as marshal gives it back, whatever its layout) with the wire's
    stiffness times `factor` wherever it is, in a tree or in a marshalled payload inside
    it; every other byte (names, digests) as it was."""
    if isinstance(value, bytes):
        try:
            inner = marshal.loads(value)
        except (EOFError, ValueError, TypeError):
            return value
        return marshal.dumps(_scaled(inner, factor))
    if isinstance(value, tuple):
        return tuple(_scaled(part, factor) for part in value)
    if isinstance(value, dict):
        wire = value.get("wire")
        if isinstance(wire, dict) and "stiffness" in wire:
            return {**value, "wire": {**wire, "stiffness": wire["stiffness"] * factor}}
        return {key: _scaled(part, factor) for key, part in value.items()}
    return value


def _crank(folder: Path) -> Path:
    """The slider-crank case and its mechanism in `folder`, solved over 50 ms."""
    good = ROOT / "tests" / "loadcases" / "good"
    mech = (good / "slider-crank.mech.yaml").read_text(encoding="utf-8")
    case = (good / "slider-crank.case.yaml").read_text(encoding="utf-8")
    (folder / "slider-crank.mech.yaml").write_text(mech, encoding="utf-8")
    path = folder / "slider-crank.case.yaml"
    path.write_text(case.replace("end: 1.0", "end: 0.05"), encoding="utf-8")
    return path


def _wire_stiffness(case: Path) -> float:
    return load_case(case).mechanism.forces["wire"].stiffness


def test_a_rewritten_entry_is_not_used(folder: Path, parsed: list[str], tmp_path) -> None:
    """Issue 39 item 7: an entry whose tree was changed in the cache folder (the wire ten
    times stiffer, its digests left as they were) is a miss: the file is parsed again and
    the entry overwritten; a run under the file's input hash is the file's run, the same
    as a run with no cache at all."""
    case = _crank(tmp_path)
    plain = run_case(load_case(case))  # fills the cache
    true = _wire_stiffness(case)
    assert len(list(folder.glob("*.tree"))) == 2  # the case and its mechanism
    mech = tmp_path / "slider-crank.mech.yaml"
    entry = parse_cache._entry(str(mech), mech.read_text("utf-8"), source._parser_identity())
    before = marshal.loads(entry.read_bytes())
    entry.write_bytes(marshal.dumps(_scaled(before, 10.0)))
    assert marshal.loads(entry.read_bytes()) != before
    _fresh_process()
    parsed.clear()
    assert _wire_stiffness(case) == true  # not 10 x
    assert len(parsed) == 1  # the mechanism, whose entry was changed
    _fresh_process()
    tampered = run_case(load_case(case))
    assert len(parsed) == 1  # overwritten by the parse: read from the cache again
    _fresh_process()
    with pytest.MonkeyPatch.context() as patch:  # no cache: every file parsed
        patch.setattr(parse_cache, "recall", lambda *args: None)
        bare = run_case(load_case(case))
    assert tampered.input_sha256 == plain.input_sha256 == bare.input_sha256
    for outcome in (plain, tampered):
        assert outcome.solution.channels.keys() == bare.solution.channels.keys()
        for name, column in bare.solution.channels.items():
            np.testing.assert_array_equal(outcome.solution.channels[name], column, name)


def test_an_entry_of_another_text_is_not_used(folder: Path, parsed, tmp_path) -> None:
    """An entry, whole and with its own digests, put under the name of another text's
    entry (a stale tree of the file before an edit) is a miss."""
    path = tmp_path / "a.yaml"
    path.write_text("force: 1\n", encoding="utf-8")
    load_yaml(path)
    (old,) = folder.glob("*.tree")
    path.write_text("force: 2\n", encoding="utf-8")
    _fresh_process()
    load_yaml(path)
    (new,) = set(folder.glob("*.tree")) - {old}
    new.write_bytes(old.read_bytes())
    _fresh_process()
    assert load_yaml(path).data == {"force": 2}
    assert parsed == [str(path)] * 3
