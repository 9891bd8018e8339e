"""Hostile flexible-body files (issue 39 items 1 and 2): every importer is a parser with
limits. Each file below is a valid two-node beam component (tests/loadcases/flexible) with
one defect of the issue's list; `loads flex check` must stop with exit 2 and a message
naming the file, where in it (line or byte) and what was expected: no internal error, no
traceback, no gigabyte allocation, no silent acceptance."""

from __future__ import annotations

import os
import struct
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

from loadcases.flexible.bulk import read_bulk
from loadcases.flexible.op4 import read_op4
from tests.hardening.conftest import loads
from tests.loadcases.flexible import files
from tests.loadcases.flexible.beam import FILE_BEAM, element

UNITS = {"length": "mm", "force": "N", "time": "s"}
GRIDS = [1, 2]


def _nodes(folder: Path, text: str | None = None) -> None:
    (folder / "nodes.csv").write_text(text or "id,x,y,z\n1,0,0,0\n2,2,0,0\n")


def mm_beam(folder: Path, k_text: str | None = None, **keys: object) -> Path:
    """A Matrix Market component; `k_text` replaces the stiffness file's text."""
    K, M = element(FILE_BEAM)
    scipy.io.mmwrite(folder / "K.mtx", sp.coo_matrix(K), precision=17)
    scipy.io.mmwrite(folder / "M.mtx", sp.coo_matrix(M), precision=17)
    if k_text is not None:
        (folder / "K.mtx").write_text(k_text)
    _nodes(folder)
    head = {
        "format": "matrix-market",
        "units": UNITS,
        "stiffness": "K.mtx",
        "mass": "M.mtx",
        "nodes": "nodes.csv",
        "interface": GRIDS,
    }
    return files.header(folder, **{**head, **keys})


def op4_beam(folder: Path, data: bytes | str) -> Path:
    """An OP4 component whose stiffness file is `data` (mass: a valid file)."""
    _, M = element(FILE_BEAM)
    if isinstance(data, str):
        (folder / "k.op4").write_text(data)
    else:
        (folder / "k.op4").write_bytes(data)
    (folder / "m.op4").write_text(files.op4_ascii({"MAA": M}, "sparse"))
    _nodes(folder)
    return files.header(
        folder,
        format="op4",
        units=UNITS,
        nodes="nodes.csv",
        stiffness="k.op4",
        mass="m.op4",
        interface=GRIDS,
    )


def dmig_beam(folder: Path, extra: str) -> Path:
    """A DMIG component (small field) with the bulk-data text `extra` appended."""
    K, M = element(FILE_BEAM)
    text = files.dmig("K", K, GRIDS, "small") + files.dmig("M", M, GRIDS, "small")
    text += (
        "GRID    1               0.      0.      0.\nGRID    2               2.      0.      0.\n"
    )
    (folder / "se.pch").write_text(text + extra)
    return files.nastran_header(folder, "dmig", "se.pch", ("K", "M"), units=UNITS, interface=GRIDS)


def npz_beam(folder: Path, change: Callable[[dict], None] | None = None, **keys: object) -> Path:
    """A neutral component (npz beside its header); `change` edits the arrays."""
    K, M = element(FILE_BEAM)
    arrays: dict = {
        "node_ids": np.array(GRIDS, dtype=np.int64),
        "coordinates": np.array([[0.0, 0, 0], [2.0, 0, 0]]),
        "dof_map": np.column_stack([np.repeat(GRIDS, 6), np.tile(np.arange(1, 7), 2)]),
    }
    for name, matrix in (("stiffness", K), ("mass", M)):
        csr = sp.csr_matrix(matrix)
        for part in ("data", "indices", "indptr", "shape"):
            arrays[f"{name}_{part}"] = np.asarray(getattr(csr, part))
    if change is not None:
        change(arrays)
    np.savez(folder / "part.npz", **arrays)
    head = {"format": "npz", "units": UNITS, "interface": GRIDS}
    return files.header(folder, **{**head, **keys})


def _refused(path: Path, *words: str) -> str:
    """`loads flex check path` exits 2 with every one of `words` in its output."""
    result = loads("flex", "check", path)
    assert result.exit_code == 2, result.output
    assert "internal error" not in result.output and "Traceback" not in result.output
    for word in words:
        assert word in result.output, (word, result.output)
    return result.output


def _op4_header(ncol: int, nrow: int, fmt: str = "1P,3E23.16", kind: int = 2) -> str:
    return f"{ncol:8}{nrow:8}{6:8}{kind:8}{'KAA':8}{fmt}\n"


def test_valid_files_pass(tmp_path: Path) -> None:
    """The unmodified components of this file read (the defects below are the only ones)."""
    K, _ = element(FILE_BEAM)
    for make in (
        lambda d: mm_beam(d),
        lambda d: op4_beam(d, files.op4_ascii({"KAA": K}, "sparse")),
        lambda d: op4_beam(d, files.op4_binary({"KAA": K}, "bigmat")),
        lambda d: dmig_beam(d, ""),
        lambda d: npz_beam(d),
    ):
        folder = tmp_path / str(len(list(tmp_path.iterdir())))
        folder.mkdir()
        result = loads("flex", "check", make(folder))
        assert result.exit_code == 0, result.output


# ---- OP4 -----------------------------------------------------------------------------------


def test_op4_number_width_zero(tmp_path: Path) -> None:
    K, _ = element(FILE_BEAM)
    text = files.op4_ascii({"KAA": K}, "sparse").replace("1P,3E23.16", "1P,3E0.0", 1)
    _refused(op4_beam(tmp_path, text), "k.op4:1:", "number format")


def test_op4_negative_ncol(tmp_path: Path) -> None:
    text = _op4_header(-12, 12) + f"{-11:8}{1:8}{1:8}\n 1.0E+00\n"
    _refused(op4_beam(tmp_path, text), "k.op4:1:", "NCOL")


def test_op4_bigmat_rows_beyond_the_limit(tmp_path: Path) -> None:
    text = _op4_header(12, -9_999_999) + f"{13:8}{1:8}{1:8}\n 1.0E+00\n"  # I8's largest
    _refused(op4_beam(tmp_path, text), "k.op4:1:", "9999999 rows")


def test_op4_dense_count_beyond_the_file(tmp_path: Path) -> None:
    """NW of 10^8 - 1 values in a 3-line file: refused from the file's length, not read."""
    text = _op4_header(12, 12) + f"{1:8}{1:8}{99_999_999:8}\n" + " 1.0E+00" * 3 + "\n"
    _refused(op4_beam(tmp_path, text), "k.op4:2:", "99999999 values")


def test_op4_short_cells_still_read(tmp_path: Path) -> None:
    """The file-length check counts a line as holding at least one value: hand-written
    values shorter than the format's width, one a line, are still read."""
    text = _op4_header(1, 4) + f"{1:8}{1:8}{4:8}\n 4.0E+00\n-1.0E+00\n 2.0\n 3.\n"
    text += f"{2:8}{1:8}{1:8}\n 1.0E+00\n"  # 38 characters after the column: 1 cell of 23
    (tmp_path / "k.op4").write_text(text)
    matrix = read_op4(tmp_path / "k.op4")["KAA"].matrix.toarray()
    assert matrix.ravel().tolist() == [4.0, -1.0, 2.0, 3.0]


def test_op4_binary_record_shorter_than_its_word_count(tmp_path: Path) -> None:
    order = "<"
    head = struct.pack(order + "4i8s", 12, 12, 6, 2, b"KAA     ")
    body = struct.pack(order + "3i", 1, 1, 24) + struct.pack(order + "d", 1.0)
    tail = struct.pack(order + "3i", 13, 1, 2) + struct.pack(order + "d", 1.0)
    data = b"".join(
        struct.pack("<i", len(r)) + r + struct.pack("<i", len(r)) for r in (head, body, tail)
    )
    _refused(op4_beam(tmp_path, data), "k.op4", "byte 32", "24 words")


def test_op4_binary_short_record(tmp_path: Path) -> None:
    order = "<"
    head = struct.pack(order + "4i8s", 12, 12, 6, 2, b"KAA     ")
    body = struct.pack(order + "2i", 1, 1)
    data = b"".join(struct.pack("<i", len(r)) + r + struct.pack("<i", len(r)) for r in (head, body))
    _refused(op4_beam(tmp_path, data), "k.op4", "byte 32")


def test_op4_binary_rows_beyond_the_limit(tmp_path: Path) -> None:
    order = "<"
    head = struct.pack(order + "4i8s", 12, -(2**31 - 1), 6, 2, b"KAA     ")
    tail = struct.pack(order + "3i", 13, 1, 2) + struct.pack(order + "d", 1.0)
    data = b"".join(struct.pack("<i", len(r)) + r + struct.pack("<i", len(r)) for r in (head, tail))
    _refused(op4_beam(tmp_path, data), "k.op4", "byte 0", "2147483647 rows")


# ---- DMIG ----------------------------------------------------------------------------------


def _last_line(folder: Path) -> int:
    return len((folder / "se.pch").read_text().splitlines())


def test_dmig_free_field_grid_with_only_an_id(tmp_path: Path) -> None:
    """Missing trailing fields are blank, and blank coordinates 0.0 (as in NASTRAN)."""
    path = dmig_beam(tmp_path, "GRID,7\n")
    assert read_bulk([tmp_path / "se.pch"]).grids[7][0] == (0.0, 0.0, 0.0)
    result = loads("flex", "check", path)
    assert result.exit_code == 0, result.output


def test_dmig_aset1_thru_beyond_the_limit(tmp_path: Path) -> None:
    path = dmig_beam(tmp_path, "ASET1,123456,1,THRU,30000000\n")
    _refused(path, f"se.pch:{_last_line(tmp_path)}:", "THRU", "30,000,000 grids")


def test_dmig_grid_id_out_of_range(tmp_path: Path) -> None:
    path = dmig_beam(tmp_path, "GRID,99999999999999999999,,0.,0.,0.\n")
    _refused(path, f"se.pch:{_last_line(tmp_path)}:", "node id 99999999999999999999 out of range")


# ---- Matrix Market -------------------------------------------------------------------------

BANNER = "%%MatrixMarket matrix coordinate real general\n"


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (BANNER + "2000000000 2000000000 1\n1 1 1.0\n", "2000000000 rows x 2000000000 columns"),
        (BANNER + "12 12 1000000000\n1 1 1.0\n", "1000000000 entries"),
        ("%%MatrixMarket matrix array real general\n100000 100000\n1.0\n", "10000000000 values"),
        (
            "%%MatrixMarket matrix coordinate integer general\n12 12 1\n1 1 "
            "99999999999999999999999\n",
            "99999999999999999999999",
        ),
        ("%%MatrixMarket matrix coordinate complex general\n12 12 1\n1 1 1.0 2.0\n", "complex"),
        (BANNER + "12 12 1\n1 1 nan\n", "nan"),
        (BANNER + "12 12 2\n1 1 1.0\n", "2 entries"),
        (BANNER + "12 12 1\n13 1 1.0\n", "row '13': expected 1-12"),
    ],
)
def test_matrix_market_header_against_the_file(tmp_path: Path, text: str, words: str) -> None:
    _refused(mm_beam(tmp_path, text), "K.mtx", words)


# ---- JSON headers --------------------------------------------------------------------------


def test_header_nested_deep(tmp_path: Path) -> None:
    path = tmp_path / "part.json"
    path.write_text('{"format": "npz", "description": ' + "[" * 100_000 + "]" * 100_000 + "}")
    _refused(path, "part.json:1:", "nested")


def test_header_nul_in_a_file_name(tmp_path: Path) -> None:
    _refused(mm_beam(tmp_path, stiffness="K\u0000.mtx"), "part.json:", "stiffness", "control")


@pytest.mark.parametrize(
    ("units", "key", "words"),
    [
        ({"length": "mm/0", "force": "N"}, "units.length", "unknown unit 'mm/0'"),
        # were internal errors: mass = force * time^2 / length divided by zero
        ({"length": "mm*0", "force": "N"}, "units.length", "expected a positive size"),
        ({"length": "mm", "mass": "kg", "time": "s/1e400"}, "units.time", "positive size"),
    ],
)
def test_header_unit_dividing_by_zero(tmp_path: Path, units: dict, key: str, words: str) -> None:
    _refused(mm_beam(tmp_path, units=units), "part.json:", key, words)


def test_units_overflowing_in_si(tmp_path: Path) -> None:
    """`1e300 mm` is a length unit: the stiffness, finite as written, is not once in SI."""
    path = mm_beam(tmp_path, units={"length": "1e300 mm", "force": "N"})
    _refused(path, "part.json:", "units", "overflow once in SI")


def test_file_value_overflowing_in_si_is_refused_without_a_numpy_warning(
    tmp_path: Path,
) -> None:
    """Fuzzing (issue 39, op4_binary, example 878: a byte of an exponent set to 0xff): a
    stiffness of 1.5e308 N/mm is finite as written and 1.5e311 N/m in SI. It was refused,
    but the scaling printed NumPy's overflow warning first; now only the refusal."""
    K, _ = element(FILE_BEAM)
    K = K.copy()
    K[0, 0] = 1.5e308
    path = op4_beam(tmp_path, files.op4_binary({"KAA": K}, "sparse"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _refused(path, "part.json:", "units", "stiffness matrix of k.op4 overflow once in SI")


def test_control_character_in_a_node_name(tmp_path: Path) -> None:
    _refused(mm_beam(tmp_path, node_names={"hin\u0000ge": 1}), "part.json:", "U+0000")
    path = mm_beam(tmp_path)
    _nodes(tmp_path, "id,x,y,z,name\n1,0,0,0,hin\u202ege\n2,2,0,0,\n")
    _refused(path, "nodes.csv:2:", "U+202E")


def test_header_true_is_not_node_1(tmp_path: Path) -> None:
    _refused(mm_beam(tmp_path, interface=[True, 2]), "part.json:", "interface[0]")


def test_header_float_node_id(tmp_path: Path) -> None:
    _refused(mm_beam(tmp_path, interface=[1.0, 2]), "part.json:", "interface[0]")


# ---- node tables ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("table", "words"),
    [
        ("id,x,y,z\n1,0,0,0\n1000000000000000000000000000000,2,0,0\n", "nodes.csv:3:"),
        ("id,x,y,z\n1,0,0,0\n1e30,2,0,0\n", "nodes.csv:3:"),
        ("id,x,y,z\n1,0,0,0\n2,nan,0,0\n", "nodes.csv:3:"),
        ("id,x,y,z\n1,0,0,0\n2,2,0," + "9" * 20_000_000 + "\n", "nodes.csv:3:"),
        ("id,x,y,z\n1,0,0,0\n-2,2,0,0\n", "nodes.csv:3:"),
        ("id,x,y,z\n1,0,0,0\n\u0662,2,0,0\n", "nodes.csv:3:"),
    ],
)
def test_node_table(tmp_path: Path, table: str, words: str) -> None:
    path = mm_beam(tmp_path)
    _nodes(tmp_path, table)
    _refused(path, words)


def test_node_table_coordinate_beyond_the_limit(tmp_path: Path) -> None:
    """A node at 1e200 mm (found by fuzzing node tables): it was refused for a misleading
    reason (4 rigid-body modes) after NumPy overflow warnings printed by the checks."""
    header = mm_beam(tmp_path)
    _nodes(tmp_path, "id,x,y,z\n1,0,0,0\n2,1e200,0,0\n")
    output = _refused(header, "nodes.csv", "node 2 is 1e+197 m from the origin, beyond 1e+06 m")
    assert "Warning" not in output, output
    _nodes(tmp_path, "id,x,y,z\n1,0,0,0\n2,1e9,0,0\n")  # 1000 km in mm: at the limit
    assert "origin" not in loads("flex", "check", header).output  # (refused for its K)


# ---- npz -----------------------------------------------------------------------------------


def test_npz_nan_coordinates(tmp_path: Path) -> None:
    def nan(arrays: dict) -> None:
        arrays["coordinates"][1, 0] = np.nan

    _refused(npz_beam(tmp_path, nan), "part.npz", "coordinates", "finite")


def test_npz_complex_matrix(tmp_path: Path) -> None:
    def complex_(arrays: dict) -> None:
        arrays["stiffness_data"] = arrays["stiffness_data"] * (1 + 1e-3j)

    _refused(npz_beam(tmp_path, complex_), "part.npz", "stiffness_data", "complex")


def test_npz_declared_shape_beyond_the_limit(tmp_path: Path) -> None:
    def huge(arrays: dict) -> None:
        arrays["stiffness_shape"] = np.array([2**40, 2**40])

    _refused(npz_beam(tmp_path, huge), "part.npz", "stiffness_shape")


def test_npz_link_out_of_the_folder(tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    inside = tmp_path / "inside"
    outside.mkdir()
    inside.mkdir()
    npz_beam(outside)
    path = npz_beam(inside)
    (inside / "part.npz").unlink()
    os.symlink(outside / "part.npz", inside / "part.npz")
    _refused(path, "leaves the folder")


@pytest.mark.parametrize("part", ["stiffness_indices", "mass_indptr"])
@pytest.mark.parametrize("made", ["complex", "float", "nan"])
def test_npz_index_arrays_of_integers_only(tmp_path: Path, part: str, made: str) -> None:
    """CSR index arrays that are not integers (found by fuzzing npz arrays): scipy cast
    2+2j and 2.5 to 2 without a word, and NaN with a NumPy warning."""

    def change(arrays: dict) -> None:
        index = np.asarray(arrays[part])
        arrays[part] = {
            "complex": lambda: index.astype(complex) * (1 + 1j),
            "float": lambda: index.astype(float) + 0.5,
            "nan": lambda: np.full(index.shape, np.nan),
        }[made]()

    output = _refused(npz_beam(tmp_path, change), "part.npz", f"{part}: expected integers")
    assert "Warning" not in output, output


# ---- matrices before an eigen-solver -------------------------------------------------------


def _matrices(folder: Path, K: np.ndarray, M: np.ndarray) -> Path:
    scipy.io.mmwrite(folder / "K2.mtx", sp.coo_matrix(K), precision=17)
    scipy.io.mmwrite(folder / "M2.mtx", sp.coo_matrix(M), precision=17)
    return mm_beam(folder, stiffness="K2.mtx", mass="M2.mtx", interface=[1])


def test_indefinite_stiffness(tmp_path: Path) -> None:
    """Positive diagonal, yet x^T K x < 0 for x = e1 + e7 (axial terms made -2 EA/L)."""
    K, M = element(FILE_BEAM)
    K[0, 6] = K[6, 0] = -2 * K[0, 0]
    _refused(_matrices(tmp_path, K, M), "K2.mtx", "stiffness", "not positive semi-definite")


def test_stiffness_singular_with_the_interface_held(tmp_path: Path) -> None:
    """No torsional stiffness: node 2 turns freely about x with node 1 held."""
    K, M = element(FILE_BEAM)
    K[3, :] = K[:, 3] = K[9, :] = K[:, 9] = 0.0
    _refused(_matrices(tmp_path, K, M), "K2.mtx", "node 2 rx")


def test_stiffness_grounded(tmp_path: Path) -> None:
    """A spring to ground on node 1 ux: five rigid-body modes where six are expected."""
    K, M = element(FILE_BEAM)
    K[0, 0] += K[0, 0]
    _refused(_matrices(tmp_path, K, M), "K2.mtx", "5 rigid-body modes")


def test_mass_on_rotations_only(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    rotations = np.array([0, 0, 0, 1, 1, 1] * 2, dtype=bool)
    M[~rotations, :] = M[:, ~rotations] = 0.0
    M[rotations, rotations] = M[rotations, rotations] + 1.0
    _refused(_matrices(tmp_path, K, M), "M2.mtx", "no mass on translations")


def test_mass_positive_definite_on_the_interior(tmp_path: Path) -> None:
    """No mass at node 2 rz: the fixed-interface eigenproblem has a massless DOF."""
    K, M = element(FILE_BEAM)
    M[11, :] = M[:, 11] = 0.0
    _refused(_matrices(tmp_path, K, M), "M2.mtx", "node 2 rz")


def test_mass_positive_definite_on_the_interface(tmp_path: Path) -> None:
    """No mass at node 2 ux, both nodes interface nodes (no interior to check): the
    reduction's eigenproblem has a massless DOF (found by fuzzing: a DMIG mass card's
    name mistyped dropped that column; it was a LAPACK error, an internal error)."""
    _, M = element(FILE_BEAM)
    M[6, :] = M[:, 6] = 0.0
    folder = tmp_path / "mm"
    folder.mkdir()
    scipy.io.mmwrite(folder / "M2.mtx", sp.coo_matrix(M), precision=17)
    _refused(mm_beam(folder, mass="M2.mtx"), "M2.mtx", "node 2 ux", "not positive definite")
    text = dmig_beam(tmp_path, "").with_name("se.pch")
    card = "DMIG    M       2       1"
    assert card in text.read_text()
    text.write_text(text.read_text().replace(card, "DMIX    M       2       1"))
    _refused(text.with_name("part.json"), "se.pch", "node 2 ux", "not positive definite")


def test_mass_scale(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    _refused(_matrices(tmp_path, K, M * 1e-300), "M2.mtx", "kg")


def test_eigen_solver_failure_after_the_checks(tmp_path: Path, monkeypatch) -> None:
    """Should LAPACK still fail on a model that passed every check, `loads flex check`
    says so and exits 1 (a solver failure), with the model's summary printed before."""
    import numpy.linalg

    import loadcases.flexible.summary as summary

    def failing(model: object, count: int) -> None:
        raise numpy.linalg.LinAlgError("leading minor of order 7 not positive definite")

    monkeypatch.setattr(summary, "free_free_frequencies", failing)
    result = loads("flex", "check", mm_beam(tmp_path))
    assert result.exit_code == 1, result.output
    assert "mass:" in result.output and "the free-free eigenproblem failed" in result.output
    assert "internal error" not in result.output and "Traceback" not in result.output


def test_validate_and_run_refuse_what_flex_check_refuses(tmp_path: Path) -> None:
    """A mechanism whose flexible body is an imported component with mass on rotations
    only: `loads validate` and `loads run` stop with exit 2 naming the mass file."""
    K, M = element(FILE_BEAM)
    rotations = np.array([0, 0, 0, 1, 1, 1] * 2, dtype=bool)
    M[~rotations, :] = M[:, ~rotations] = 0.0
    M[rotations, rotations] = M[rotations, rotations] + 1.0
    _matrices(tmp_path, K, M)
    (tmp_path / "c.case.yaml").write_text(
        """\
case: imported
mechanism:
  units: {length: mm}
  bodies:
    part:
      flexible:
        file: {path: part.json}
        interface: {root: [0, 0, 0]}
        fixed_interface_modes: 2
  joints:
    clamp: {type: fixed, bodies: [part, ground], at: [0, 0, 0]}
analysis: {type: static}
requests:
  root: {point: part.root, quantity: position}
""",
        encoding="utf-8",
    )
    for command in (("validate",), ("run", "-o", tmp_path / "out")):
        result = loads(*command[:1], tmp_path / "c.case.yaml", *command[1:])
        assert result.exit_code == 2, result.output
        assert "M2.mtx" in result.output and "no mass on translations" in result.output
        assert "internal error" not in result.output and "Traceback" not in result.output
