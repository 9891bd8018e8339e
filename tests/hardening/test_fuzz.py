"""Property-based fuzzing of the input files (issue 15 item 9, short budget).

Hypothesis mutates the crank mechanism and case of tests/loadcases/set_fixtures.py (the
tree's keys, values, types, units, expressions and YAML structure: a value replaced, a key
removed or added) and runs `loads validate` on every example and `loads run` on a part of
them. Whatever the input: the exit status is 0, 1 or 2; the output never says "internal
error" nor shows a traceback; a run that ends `ok` has finite numbers in every column.
Examples are derandomized so that CI sees the same inputs every time; the long budget is
`LOADS_FUZZ_EXAMPLES=10000 pytest tests/hardening/test_fuzz.py`.
"""

from __future__ import annotations

import copy
import csv
import json
import math
import os
from pathlib import Path
from typing import Any

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.hardening.conftest import loads
from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH

EXAMPLES = int(os.environ.get("LOADS_FUZZ_EXAMPLES", "60"))
SETTINGS = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
FILES = {
    "crank.mech.yaml": yaml.safe_load(CRANK_MECH),
    "crank.case.yaml": yaml.safe_load(CRANK_CASE),
}

# Values a user could mistype or an attacker could try.
NASTY = st.one_of(
    st.sampled_from(
        [
            ".nan",
            ".inf",
            "1e999",
            "-1e999",
            "1e300*1e10*t",
            "10**10**10",
            "1/0",
            "sin(",
            "t/0",
            "3 kg",
            "12 N/mm",
            "90 deg",
            "-5 mm",
            "",
            "=cmd|' /C calc'!A0",
            "../../etc/passwd",
            "__import__('os')",
            "angle(nowhere)",
            "table(x, t)",
            "step(t, 0, 0, 1, 1e308*1e308)",
            "0",
            "-1",
            "1e-300",
            # issue 39: bounded expressions and quantities, text shown as written
            "2(50 kg",
            "10**10**10 kg",
            "1 kg**(2**1000)",
            "+".join(["t"] * 200),
            "sin(" * 100 + "t" + ")" * 100,
            "1:30",
            "1,5 mm",
            "\u0661\u0662 kg",
            "12\u00a0kg",
            "cr\u202eank",
            "a\x07b",
            "line\nbreak",
            "crank$^$",
        ]
    ),
    st.integers(min_value=-(10**6), max_value=10**6),
    st.floats(allow_nan=True, allow_infinity=True),
    st.none(),
    st.booleans(),
    st.text(max_size=12),
    st.lists(st.integers(-3, 3), max_size=4),
    st.dictionaries(
        st.sampled_from(["type", "value", "x", "joint"]), st.integers(-2, 2), max_size=2
    ),
)


def _paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key path of a YAML tree (dict keys and list indices)."""
    out = [prefix] if prefix else []
    if isinstance(node, dict):
        for key, value in node.items():
            out += _paths(value, prefix + (key,))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            out += _paths(value, prefix + (index,))
    return out


def _mutate(tree: Any, path: tuple, action: str, value: Any) -> Any:
    tree = copy.deepcopy(tree)
    parent = tree
    for key in path[:-1]:
        parent = parent[key]
    last = path[-1]
    if action == "delete" and isinstance(parent, dict):
        del parent[last]
    elif action == "add" and isinstance(parent, dict):
        parent[f"unknown_{last}"] = value
    else:
        parent[last] = value
    return tree


MUTATION = st.tuples(
    st.sampled_from(sorted(FILES)),
    st.integers(min_value=0),
    st.sampled_from(["replace", "replace", "delete", "add"]),
    NASTY,
)


def _write(folder: Path, mutation: tuple) -> Path:
    name, pick, action, value = mutation
    for file, tree in FILES.items():
        if file == name:
            paths = _paths(tree)
            tree = _mutate(tree, paths[pick % len(paths)], action, value)
        text = (
            yaml.safe_dump(tree, allow_unicode=True)
            if isinstance(tree, dict)
            else yaml.safe_dump(tree)
        )
        (folder / file).write_text(text, encoding="utf-8")
    return folder / "crank.case.yaml"


def _assert_clean(result) -> None:
    assert result.exit_code in (0, 1, 2), (result.exit_code, result.output)
    assert "internal error" not in result.output, result.output
    assert "Traceback" not in result.output, result.output


@SETTINGS
@given(mutation=MUTATION)
def test_validate_never_fails_inside(tmp_path_factory, mutation) -> None:
    case = _write(tmp_path_factory.mktemp("fuzz"), mutation)
    _assert_clean(loads("validate", case))


@settings(SETTINGS, max_examples=max(EXAMPLES // 4, 5))
@given(mutation=MUTATION)
def test_run_never_fails_inside_nor_returns_nan_as_ok(tmp_path_factory, mutation) -> None:
    folder = tmp_path_factory.mktemp("fuzz")
    case = _write(folder, mutation)
    result = loads("run", case, "-o", folder / "out")
    _assert_clean(result)
    for summary in (folder / "out").glob("*.summary.json"):
        data = json.loads(summary.read_text(encoding="utf-8"))
        if data["status"] != "ok":
            continue
        with open(
            summary.with_name(summary.name.replace(".summary.json", ".csv")),
            newline="",
            encoding="utf-8",
        ) as handle:
            for row in csv.DictReader(handle):
                assert all(math.isfinite(float(v)) for v in row.values() if v != ""), row
