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
examples for every surface; unset, a short budget (5 per importer, 4 hardpoint tables, 6
`--set` values) for `make test`. The long budget is
`LOADS_FUZZ_IMPORT_EXAMPLES=10000 pytest tests/hardening/test_fuzz_importers.py -k SURFACE`
(about 15 min or less per surface on one core: examples call the CLI in-process on the
smallest inputs that exercise each parser, and most `--set` values stop at the parsing and
checking of the case; one in eight is run).
"""

from __future__ import annotations

import contextlib
import csv
import functools
import json
import math
import os
import re
import signal
import struct
import tracemalloc
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from loadcases.foundation.clip import QUOTE_LIMIT
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.inputs.overrides import OverrideError, parse_overrides
from tests.hardening.conftest import loads
from tests.hardening.test_importer_limits import dmig_beam, mm_beam, npz_beam, op4_beam
from tests.loadcases.flexible import files
from tests.loadcases.flexible.beam import FILE_BEAM, element
from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH

_ASKED = os.environ.get("LOADS_FUZZ_IMPORT_EXAMPLES")
EXAMPLES = int(_ASKED or "5")


def _budget(short: int) -> int:
    """Examples of one surface: LOADS_FUZZ_IMPORT_EXAMPLES when given, else `short`."""
    return EXAMPLES if _ASKED else short


HANG_SECONDS = 120  # an example still running then is stopped (a cold kernel cache: ~60 s)
SETTINGS = settings(
    max_examples=EXAMPLES,
    deadline=30_000,  # ms: an example past 30 s is a hang (issue 39's bound)
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
PEAK_BYTES = 200_000_000  # no example of these few-kB files may allocate more

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


def _edited(text: str, edits: list) -> str:
    """`text` after each edit of `edits` in turn (_edit_text)."""
    for edit in edits:
        text = _edit_text(text, edit)
    return text


def _edit_file(path: Path, edits: list) -> None:
    """Apply `edits` to the text file at `path`, in place."""
    path.write_text(_edited(path.read_text(), edits))


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


@contextlib.contextmanager
def _hang_stopped() -> Iterator[None]:
    """Stops the example with TimeoutError once it runs past HANG_SECONDS: hypothesis'
    deadline (30 s) judges only an example that ends, and a hang would never end the run."""

    def stop(signum: int, frame: object) -> None:
        raise TimeoutError(f"an example past {HANG_SECONDS} s: a hang")

    previous = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, HANG_SECONDS)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _traced(*args: object) -> Any:
    """`loads *args` with its peak allocation checked against PEAK_BYTES."""
    tracemalloc.start()
    try:
        with _hang_stopped():
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
    """`loads flex check` exits 0/1/2 cleanly, without a NumPy warning, and prints finite
    numbers when it accepts."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = _traced("flex", "check", header)
    _assert_clean(result)
    # a NumPy warning is a number cast (2+1j to 2), overflowed or made NaN unchecked
    numeric = (RuntimeWarning, np.exceptions.ComplexWarning)
    assert not [w for w in caught if issubclass(w.category, numeric)], [str(w) for w in caught]
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
    text = _edited(files.op4_ascii({"KAA": K}, "sparse"), edits)
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
    _edit_file(folder / "se.pch", edits)
    _check_component(header)


@SETTINGS
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_matrix_market(tmp_path_factory: Any, edits: list) -> None:
    folder = _folder(tmp_path_factory)
    header = mm_beam(folder)
    _edit_file(folder / "K.mtx", edits)
    _check_component(header)


@SETTINGS
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_node_table(tmp_path_factory: Any, edits: list) -> None:
    folder = _folder(tmp_path_factory)
    header = mm_beam(folder)
    _edit_file(folder / "nodes.csv", edits)
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

CRANK_POINTS = "points:\n  tip: {body: crank, at: [0.1, 0, 0]}\n"
# the crank's point from a table, and a second row of the other body with SI values
TABLE = "name,body,x,y,z,units\ntip,crank,100,0,0,mm\nspare,ground,0.4,0,0,\n"


def _crank(folder: Path, mech: str = CRANK_MECH) -> Path:
    """The tiny crank case (tests/loadcases/set_fixtures) written in `folder`; its path."""
    (folder / "crank.mech.yaml").write_text(mech, encoding="utf-8")
    (folder / "crank.case.yaml").write_text(CRANK_CASE, encoding="utf-8")
    return folder / "crank.case.yaml"


@settings(SETTINGS, max_examples=_budget(4))
@given(edits=st.lists(TEXT_EDIT, min_size=1, max_size=3))
def test_hardpoint_table(tmp_path_factory: Any, edits: list) -> None:
    folder = _folder(tmp_path_factory)
    assert CRANK_POINTS in CRANK_MECH
    case = _crank(folder, CRANK_MECH.replace(CRANK_POINTS, "points: {from: hardpoints.csv}\n"))
    (folder / "hardpoints.csv").write_text(_edited(TABLE, edits), encoding="utf-8")
    _assert_clean(_traced("validate", case))


# A valid quantity of each crank parameter (speed rad/s, load N, stroke m), mutated below.
QUANTITIES = ["2", "2 rad/s", "1.5e-3", "10 N", "-0.25 kN", "1500 mm", "3 deg/s", "2.5E+2 N"]
# Decimal digits of other scripts (Arabic-Indic, extended Arabic-Indic, Devanagari, Bengali,
# Thai, Myanmar, Mongolian, fullwidth, mathematical bold): refused in a number.
OTHER_DIGITS = "\u0660\u0661\u06f2\u0967\u09e8\u0e53\u1043\u1814\uff11\U0001d7d0"
# Superscript, subscript and circled forms: a superscript is a power, as in files
# ("2 m\u00b2"), the others are refused as characters no quantity holds.
DIGIT_FORMS = "\u00b2\u00b3\u2081\u2460"
# Every Unicode space (category Zs), the other white space of str.split and zero-width ones.
SPACES = (
    " \u00a0\u1680" + "".join(chr(c) for c in range(0x2000, 0x200B)) + "\u202f\u205f\u3000"
    "\t\n\r\x0b\x0c\x1c\x1d\x1e\x1f\x85\u2028\u2029\u200b\u2060\ufeff"
)
CONTROLS = "\x00\x01\x07\x08\x1b\x7f\x9b\u202e\u2066\u061c\u200f"
PIECES = [
    "m",
    "mm",
    "rad/s",
    "N",
    "kN*m",
    "deg",
    "1/s",
    "s^-1",
    "m/s^2",
    "furlong",
    "rad/s/0",
    "(m",
    "m)",
    "2(50",
    "((",
    "))",
    "**",
    "^",
    "^999",
    "/",
    "%",
    "e999",
    "e-999",
    "e308",
    "E+99999999999999999999",
    "e",
    "1e400",
    "-",
    "+",
    ".",
    "..",
    "_",
    "=",
    ",",
    "'",
    '"',
    "nan",
    "inf",
    "-inf",
    "j",
    "0x1F",
    "1_000",
    "\u2212",
    "\u00b5m",
    "\u00b0",
]
SET_PIECE = st.one_of(
    st.sampled_from(list(OTHER_DIGITS + DIGIT_FORMS + SPACES + CONTROLS) + PIECES),
    st.characters(),
    st.text(max_size=3),
)
SET_EDIT = st.tuples(
    st.sampled_from(["insert", "replace", "delete", "repeat"]), st.integers(min_value=0), SET_PIECE
)


MAX_SET_CHARS = 200_000  # a repeated value is cut here (repeats of repeats grew to 20 GB)


def _edit_quantity(value: str, edit: tuple) -> str:
    """One character-level edit of a `--set` value: `piece` inserted or written over the
    character at `place`, that character deleted, or the value repeated (a long value, at most
    MAX_SET_CHARS)."""
    kind, place, piece = edit
    at = place % (len(value) + 1)
    if kind == "insert":
        return value[:at] + piece + value[at:]
    if kind == "replace":
        return value[:at] + piece + value[at + 1 :]
    if kind == "delete":
        return value[:at] + value[at + 1 :]
    times = min(2 + place % 400, MAX_SET_CHARS // max(len(value), 1) + 1)
    return (value * times)[:MAX_SET_CHARS]


SET_VALUES = st.builds(
    lambda base, edits: functools.reduce(_edit_quantity, edits, base),
    st.sampled_from(QUANTITIES),
    st.lists(SET_EDIT, max_size=4),
)
SET_NAMES = st.sampled_from(["speed", "load", "stroke", "nowhere", "", "speed=1", " load"])


@settings(SETTINGS, max_examples=_budget(6))
@given(name=SET_NAMES, value=SET_VALUES, solve=st.integers(0, 7).map(lambda n: n == 0))
def test_set_value(tmp_path_factory: Any, name: str, value: str, solve: bool) -> None:
    """A value the option parser refuses is the CLI's exit 2; one it reads is checked with
    the case (unknown parameter, other dimension) and, one time in eight, run: an `ok` run
    has finite numbers in every column."""
    folder = _folder(tmp_path_factory)
    case = _crank(folder)
    option = f"{name}={value}"
    try:
        overrides = parse_overrides([option])
    except OverrideError:
        solve = True  # the CLI stops at the option: exit 2, nothing solved
    else:
        assert all(math.isfinite(o.value) for o in overrides), overrides
        # read as files are: ASCII digits, plain spaces, no control characters
        assert not set(value) & set(OTHER_DIGITS + SPACES[1:] + CONTROLS), ascii(value)
        if not solve:
            try:
                with _hang_stopped():
                    load_case(case, what_if=overrides)
            except InputError as error:
                assert error.diagnostics
            return
    result = _traced("run", case, "--set", option, "-o", folder / "out")
    _assert_clean(result)
    assert len(value) <= QUOTE_LIMIT or value not in result.output, result.output
    _assert_finite_ok_runs(folder / "out")


def _assert_finite_ok_runs(folder: Path) -> None:
    """Every run of `folder` whose summary says `ok` has finite numbers in every column."""
    for summary in folder.glob("*.summary.json"):
        if json.loads(summary.read_text(encoding="utf-8"))["status"] != "ok":
            continue
        table = summary.with_name(summary.name.replace(".summary.json", ".csv"))
        with open(table, newline="", encoding="utf-8") as handle:
            for row in csv.DictReader(handle):
                assert all(math.isfinite(float(v)) for v in row.values() if v != ""), row
