"""Property-based fuzzing of the newer input surfaces (issue 39 item 9, short budget): the
flexible-body importers (OP4 ASCII and binary, DMIG, Matrix Market, the npz arrays and
JSON header, node tables), hardpoint tables and `--set` values.

Hypothesis mutates a valid two-node beam component (tests/hardening/test_importer_limits)
or the press example's hardpoint table, token by token, character by character, line by
line or word by word (binary), and runs `loads flex check`, `loads validate` or `loads run`.
Whatever the input: the exit status is 0, 1 or 2; no "internal error", no traceback; an
accepted component prints finite numbers only; a run that ends `ok` has finite numbers in
every column; no example takes more than 30 s; and no example allocates more than
PEAK_BYTES (traced by tracemalloc, which sees NumPy's buffers): sizes read from a file are
checked before anything is allocated.
Derandomized: CI sees the same inputs every time. Budget: LOADS_FUZZ_IMPORT_EXAMPLES
examples per surface (default 5, a second or two each; a quarter of them for `--set`, whose
examples are runs); the long budget is
`LOADS_FUZZ_IMPORT_EXAMPLES=10000 pytest tests/hardening/test_fuzz_importers.py`.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import shutil
import struct
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.hardening.conftest import loads
from tests.hardening.test_importer_limits import dmig_beam, mm_beam, npz_beam, op4_beam
from tests.loadcases.flexible import files
from tests.loadcases.flexible.beam import FILE_BEAM, element
from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH

EXAMPLES = int(os.environ.get("LOADS_FUZZ_IMPORT_EXAMPLES", "5"))
SETTINGS = settings(
    max_examples=EXAMPLES,
    deadline=30_000,  # ms: an example past 30 s is a hang (issue 39's bound)
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
PEAK_BYTES = 200_000_000  # no example of these few-kB files may allocate more
LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "examples"

# Tokens a user could mistype or an attacker could try in a numeric file.
TOKENS = st.one_of(
    st.sampled_from(
        [
            "0",
            "-1",
            "-2147483647",
            "2147483647",
            "4294967296",
            "99999999",
            "-9999999",
            "99999999999999999999999",
            "65536",
            "1e999",
            "-1e999",
            "nan",
            "inf",
            "1e-300",
            "1e300",
            "1.0",
            "1.5D+3",
            "1.+6",
            "1e30",
            "true",
            "THRU",
            "1+2j",
            "complex",
            "pattern",
            "array",
            "\x00",
            "\u202e",
            ",",
            "*",
            "+",
            "$",
            "",
            "E",
            "1P,3E0.0",
            "1P,3E99999999.1",
        ]
    ),
    st.integers(min_value=-(2**63), max_value=2**63),
    st.text(max_size=6),
)
TEXT_EDIT = st.tuples(
    st.sampled_from(["token", "chars", "delete", "duplicate", "truncate"]),
    st.integers(min_value=0),
    st.integers(min_value=0),
    TOKENS,
)


def _edit_text(text: str, edit: tuple) -> str:
    """One edit of a text file: a blank-separated token replaced, characters overwritten in
    place (fixed-width formats), a line deleted or duplicated, the file cut."""
    kind, line_pick, place, token = edit
    token = str(token)
    lines = text.splitlines(keepends=True)
    if not lines:
        return token
    k = line_pick % len(lines)
    if kind == "token":
        spans = [m.span() for m in re.finditer(r"[^\s,]+", lines[k])] or [(0, 0)]
        start, end = spans[place % len(spans)]
        lines[k] = lines[k][:start] + token + lines[k][end:]
    elif kind == "chars":
        at = place % max(len(lines[k]), 1)
        lines[k] = lines[k][:at] + token + lines[k][at + len(token) :]
    elif kind == "delete":
        del lines[k]
    elif kind == "duplicate":
        lines.insert(k, lines[k])
    else:
        return text[: place % max(len(text), 1)]
    return "".join(lines)


def _traced(*args: object) -> Any:
    """`loads *args` with its peak allocation checked against PEAK_BYTES."""
    tracemalloc.start()
    try:
        result = loads(*args)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < PEAK_BYTES, (peak, args)
    return result


def _assert_clean(result: Any) -> None:
    assert result.exit_code in (0, 1, 2), (result.exit_code, result.output)
    assert "internal error" not in result.output, result.output
    assert "Traceback" not in result.output, result.output


def _check_component(header: Path) -> None:
    """`loads flex check` exits 0/1/2 cleanly, and prints finite numbers when it accepts."""
    result = _traced("flex", "check", header)
    _assert_clean(result)
    if result.exit_code == 0:
        shown = result.output.lower()
        assert not re.search(r"\b(nan|inf)\b", shown), result.output


def _folder(factory: Any) -> Path:
    return Path(factory.mktemp("fuzz"))


# ---- flexible-body importers ---------------------------------------------------------------


@SETTINGS
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_op4_ascii(tmp_path_factory: Any, edits: list) -> None:
    K, _ = element(FILE_BEAM)
    text = files.op4_ascii({"KAA": K}, "sparse")
    for edit in edits:
        text = _edit_text(text, edit)
    _check_component(op4_beam(_folder(tmp_path_factory), text))


WORDS = st.one_of(
    st.sampled_from([0, -1, 1, 2, 3, 4, 24, 48, 65536, 2**31 - 1, -(2**31), 2**30, 12, 13]),
    st.integers(min_value=-(2**31), max_value=2**31 - 1),
)
BINARY_EDIT = st.tuples(
    st.sampled_from(["word", "byte", "truncate"]), st.integers(min_value=0), WORDS
)


@SETTINGS
@given(
    edits=st.lists(BINARY_EDIT, min_size=1, max_size=3),
    layout=st.sampled_from(["sparse", "bigmat", "dense"]),
)
def test_op4_binary(tmp_path_factory: Any, edits: list, layout: str) -> None:
    K, _ = element(FILE_BEAM)
    data = bytearray(files.op4_binary({"KAA": K}, layout))
    for kind, place, word in edits:
        if len(data) < 4:  # cut to nothing: an empty or 1-3 byte file is the case
            break
        if kind == "word":
            at = 4 * (place % (len(data) // 4))
            data[at : at + 4] = struct.pack("<i", word)
        elif kind == "byte":
            data[place % len(data)] = word % 256
        else:
            del data[place % len(data) :]
    _check_component(op4_beam(_folder(tmp_path_factory), bytes(data)))


@SETTINGS
@given(
    edits=st.lists(TEXT_EDIT, min_size=1, max_size=3),
    extra=st.sampled_from(["", "ASET1,123456,1,THRU,2\n", "PARAM,WTMASS,0.00259\n", "GRID,3\n"]),
)
def test_dmig(tmp_path_factory: Any, edits: list, extra: str) -> None:
    folder = _folder(tmp_path_factory)
    header = dmig_beam(folder, extra)
    text = (folder / "se.pch").read_text()
    for edit in edits:
        text = _edit_text(text, edit)
    (folder / "se.pch").write_text(text)
    _check_component(header)


@SETTINGS
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_matrix_market(tmp_path_factory: Any, edits: list) -> None:
    folder = _folder(tmp_path_factory)
    header = mm_beam(folder)
    text = (folder / "K.mtx").read_text()
    for edit in edits:
        text = _edit_text(text, edit)
    (folder / "K.mtx").write_text(text)
    _check_component(header)


@SETTINGS
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_node_table(tmp_path_factory: Any, edits: list) -> None:
    folder = _folder(tmp_path_factory)
    header = mm_beam(folder)
    text = (folder / "nodes.csv").read_text()
    for edit in edits:
        text = _edit_text(text, edit)
    (folder / "nodes.csv").write_text(text)
    _check_component(header)


ARRAYS = st.sampled_from(
    [
        "node_ids",
        "coordinates",
        "dof_map",
        "stiffness_data",
        "stiffness_indices",
        "stiffness_indptr",
        "stiffness_shape",
        "mass_data",
        "mass_shape",
    ]
)
NASTY_ARRAYS = st.sampled_from(
    [
        "delete",
        "float",
        "complex",
        "nan",
        "inf",
        "huge",
        "negative",
        "empty",
        "scalar",
        "strings",
        "transpose",
        "bool",
    ]
)


def _nasty_array(array: np.ndarray, kind: str) -> Any:
    """`array` made hostile in one way (None: removed)."""
    changed = {
        "float": lambda a: a.astype(float) + 0.5,
        "complex": lambda a: a.astype(complex) * (1 + 1j),
        "nan": lambda a: np.full(a.shape, np.nan),
        "inf": lambda a: np.full(a.shape, np.inf),
        "huge": lambda a: np.full(a.shape, 2**62, dtype=np.int64),
        "negative": lambda a: -np.abs(a),
        "empty": lambda a: np.zeros((0,)),
        "scalar": lambda a: np.array(7),
        "strings": lambda a: np.array(["a"] * max(a.size, 1)),
        "transpose": lambda a: a.T.copy() if a.ndim == 2 else a[::-1].copy(),
        "bool": lambda a: np.ones(a.shape, dtype=bool),
    }
    return None if kind == "delete" else changed[kind](array)


HEADER_VALUES = st.one_of(
    st.sampled_from(
        [
            [True, 2],
            [1.0, 2],
            [1e30],
            [2**70],
            "../part.npz",
            {"length": "mm/0", "force": "N"},
            {"length": "2(50", "force": "N"},
            {"length": "mm", "force": "N", "time": "0 s"},
            {"length": "m", "mass": "kg"},
            "K\x00.mtx",
            None,
            [],
            {},
            "npz",
            "op4",
            1e308,
        ]
    ),
    st.integers(),
    st.floats(),
    st.text(max_size=8),
)


@SETTINGS
@given(
    changes=st.lists(st.tuples(ARRAYS, NASTY_ARRAYS), max_size=2),
    key=st.sampled_from(["format", "units", "interface", "node_names", "wtmass", "extra", None]),
    value=HEADER_VALUES,
)
def test_npz_and_header(tmp_path_factory: Any, changes: list, key: str | None, value: Any) -> None:
    def change(arrays: dict) -> None:
        for name, kind in changes:
            if name not in arrays:  # removed by an earlier change
                continue
            try:
                made = _nasty_array(np.asarray(arrays[name]), kind)
            except (TypeError, ValueError, IndexError):  # cannot apply to an earlier change
                continue
            if made is None:
                arrays.pop(name, None)
            else:
                arrays[name] = made

    folder = _folder(tmp_path_factory)
    header = npz_beam(folder, change)
    if key is not None:
        data = json.loads(header.read_text())
        data[key] = value
        header.write_text(json.dumps(data, allow_nan=True))
    _check_component(header)


# ---- hardpoint tables and --set ------------------------------------------------------------

INLINE_POINTS = """\
points:
  crank_pin: {body: crank, at: [100, 0, 0]}
  slider_c:  {body: slider, at: [400, 0, 0]}
"""
TABLE = "name,body,x,y,z,units\ncrank_pin,crank,100,0,0,mm\nslider_c,slider,400,0,0,\n"


@settings(SETTINGS, max_examples=max(EXAMPLES // 2, 4))  # a validate of the press: 0.6 s
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_hardpoint_table(tmp_path_factory: Any, edits: list) -> None:
    folder = _folder(tmp_path_factory)
    mech = (LIBRARY / "press.mech.yaml").read_text()
    assert INLINE_POINTS in mech
    (folder / "press.mech.yaml").write_text(
        mech.replace(INLINE_POINTS, "points: {from: hardpoints.csv}\n")
    )
    shutil.copy(LIBRARY / "press_stroke.case.yaml", folder / "press_stroke.case.yaml")
    table = TABLE
    for edit in edits:
        table = _edit_text(table, edit)
    (folder / "hardpoints.csv").write_text(table, encoding="utf-8")
    _assert_clean(_traced("validate", folder / "press_stroke.case.yaml"))


SET_VALUES = st.one_of(
    TOKENS.map(str),
    st.sampled_from(
        ["2 rad/s", "1e999 rad/s", "2(50", "\u0661\u0662", "12\u00a0rad/s", "1\n2", "x" * 3000]
    ),
)


@settings(SETTINGS, max_examples=max(EXAMPLES // 4, 2))
@given(
    name=st.sampled_from(["speed", "load", "stroke", "nowhere", "", "speed=1"]), value=SET_VALUES
)
def test_set_value(tmp_path_factory: Any, name: str, value: str) -> None:
    folder = _folder(tmp_path_factory)
    (folder / "crank.mech.yaml").write_text(CRANK_MECH, encoding="utf-8")
    (folder / "crank.case.yaml").write_text(CRANK_CASE, encoding="utf-8")
    result = _traced(
        "run", folder / "crank.case.yaml", "--set", f"{name}={value}", "-o", folder / "out"
    )
    _assert_clean(result)
    for summary in (folder / "out").glob("*.summary.json"):
        if json.loads(summary.read_text(encoding="utf-8"))["status"] != "ok":
            continue
        table = summary.with_name(summary.name.replace(".summary.json", ".csv"))
        with open(table, newline="", encoding="utf-8") as handle:
            for row in csv.DictReader(handle):
                assert all(math.isfinite(float(v)) for v in row.values() if v != ""), row
