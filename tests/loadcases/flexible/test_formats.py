"""Each import format reads the 2-node beam written in it (file units mm, N, s) and gives
the closed-form 12-DOF Euler-Bernoulli K and M in SI (tests/loadcases/flexible/beam.py,
Przemieniecki 1968) to 1e-12 relative: the file's terms are short exact numbers, so the
only error left is the unit conversion's rounding (measured 1e-16)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

from loadcases.flexible.neutral import write_neutral
from loadcases.flexible.read import read_fe_model
from mechlib.flexible.fe_model import FEModel
from tests.loadcases.flexible import files
from tests.loadcases.flexible.beam import FILE_BEAM, SI_BEAM, element, relative_error

UNITS = {"length": "mm", "force": "N", "time": "s"}
GRIDS = [101, 202]
TOLERANCE = 1e-12


@pytest.fixture
def beam_files(tmp_path: Path) -> tuple[Path, np.ndarray, np.ndarray]:
    K, M = element(FILE_BEAM)
    files.nodes_csv(tmp_path, GRIDS, np.array([0.0, FILE_BEAM.L]), {101: "root", 202: "tip"})
    return tmp_path, K, M


def _assert_closed_form(path: Path) -> None:
    imported = read_fe_model(path)
    K, M = element(SI_BEAM)
    model = imported.model
    assert relative_error(model.stiffness, K) < TOLERANCE
    assert relative_error(model.mass, M) < TOLERANCE
    assert model.coordinates[1, 0] == pytest.approx(0.002, rel=1e-15)
    assert list(model.node_ids) == GRIDS
    assert [model.node_ids[i] for i in model.interface] == GRIDS
    assert imported.warnings == ()


def test_neutral_round_trip_is_exact(tmp_path: Path) -> None:
    K, M = element(SI_BEAM)
    dof_map = np.column_stack([np.repeat([0, 1], 6), np.tile(np.arange(6), 2)])
    model = FEModel(
        np.array(GRIDS),
        np.array([[0, 0, 0], [0.002, 0, 0]]),
        dof_map,
        sp.csr_matrix(K),
        sp.csr_matrix(M),
        (0, 1),
    )
    header, arrays = write_neutral(
        tmp_path / "beam", model, description="a beam", node_names={"tip": 1}
    )
    assert header.name == "beam.json" and arrays.name == "beam.npz"
    back = read_fe_model(header)
    assert (back.model.stiffness != model.stiffness).nnz == 0
    assert (back.model.mass != model.mass).nnz == 0
    assert np.array_equal(back.model.dof_map, dof_map)
    assert back.model.interface == (0, 1)
    assert back.node("tip") == 1 and back.node(101) == 0
    assert back.description == "a beam"
    assert back.files == (header, arrays)


def test_neutral_in_file_units(beam_files: tuple[Path, np.ndarray, np.ndarray]) -> None:
    folder, K, M = beam_files
    arrays = {
        "node_ids": np.array(GRIDS),
        "coordinates": np.array([[0.0, 0, 0], [FILE_BEAM.L, 0, 0]]),
        "dof_map": np.column_stack([np.repeat(GRIDS, 6), np.tile(np.arange(1, 7), 2)]),
    }
    for name, matrix in (("stiffness", K), ("mass", M)):
        csr = sp.csr_matrix(matrix)
        arrays |= {
            f"{name}_{p}": np.asarray(getattr(csr, p))
            for p in ("data", "indices", "indptr", "shape")
        }
    np.savez(folder / "part.npz", **arrays)
    _assert_closed_form(files.header(folder, format="npz", units=UNITS, interface=GRIDS))


def test_matrix_market(beam_files: tuple[Path, np.ndarray, np.ndarray]) -> None:
    folder, K, M = beam_files
    scipy.io.mmwrite(folder / "K.mtx", sp.coo_matrix(K), precision=17, symmetry="symmetric")
    scipy.io.mmwrite(folder / "M.mtx", M, precision=17)
    path = files.header(
        folder,
        format="matrix-market",
        units=UNITS,
        stiffness="K.mtx",
        mass="M.mtx",
        nodes="nodes.csv",
        interface=["root", 202],
    )
    _assert_closed_form(path)


@pytest.mark.parametrize("layout", ["dense", "sparse", "bigmat"])
def test_op4_ascii(beam_files: tuple[Path, np.ndarray, np.ndarray], layout: str) -> None:
    folder, K, M = beam_files
    (folder / "se.op4").write_text(files.op4_ascii({"KAA": K, "MAA": M}, layout))
    path = files.nastran_header(
        folder, "op4", "se.op4", ("KAA", "maa"), units=UNITS, nodes="nodes.csv", interface=GRIDS
    )
    _assert_closed_form(path)


@pytest.mark.parametrize("layout", ["dense", "sparse", "bigmat"])
@pytest.mark.parametrize("order", ["<", ">"])
def test_op4_binary(
    beam_files: tuple[Path, np.ndarray, np.ndarray], layout: str, order: str
) -> None:
    folder, K, M = beam_files
    (folder / "k.op4").write_bytes(files.op4_binary({"KAA": K}, layout, order))
    (folder / "m.op4").write_bytes(files.op4_binary({"MAA": M}, layout, order))
    path = files.header(
        folder,
        format="op4",
        units=UNITS,
        nodes="nodes.csv",
        interface=GRIDS,
        stiffness="k.op4",
        mass="m.op4",
    )
    _assert_closed_form(path)


def test_op4_nastran_sample_layout(tmp_path: Path) -> None:
    """The layout of an ASCII OP4 written by NASTRAN (a KGG with format 1P,5E16.9 and
    11-wide string headers, IS = IROW + 65536 (L + 1)): a 3 x 3 matrix typed here."""
    text = (
        "       3       3       6       2KGG     1P,5E16.9\n"
        "       1       0       5\n"
        "     327681\n"
        " 1.111537687E+08 4.583107587E+07\n"
        "       2       0       3\n"
        "     196610\n"
        "-2.708955224E+05\n"
        "       3       0       3\n"
        "     196611\n"
        " 2.500000000E-01\n"
        "       4       1       1\n"
        " 1.000000000E+00\n"
    )
    (tmp_path / "kgg.op4").write_text(text)
    from loadcases.flexible.op4 import read_op4

    found = read_op4(tmp_path / "kgg.op4")["KGG"]
    expected = np.diag([1.111537687e8, -2.708955224e5, 0.25])
    expected[1, 0] = 4.583107587e7
    assert found.form == 6
    assert np.array_equal(found.matrix.toarray(), expected)


@pytest.mark.parametrize("style", ["small", "large", "free"])
def test_dmig(tmp_path: Path, style: str) -> None:
    K, M = element(FILE_BEAM)
    bulk = (
        "$ a 2-node beam: K and M as DMIG, grids, a-set\n"
        + "GRID    101             0.      0.      0.\n"
        + "GRID    202             2.      0.      0.\n"
        + "ASET1   123456  101     202\n"
        + files.dmig("KAAX", K, GRIDS, style)
        + files.dmig("MAAX", M, GRIDS, style)
    )
    (tmp_path / "se.pch").write_text(bulk)
    path = files.nastran_header(tmp_path, "dmig", "se.pch", ("KAAX", "MAAX"), units=UNITS)
    _assert_closed_form(path)


def test_dmig_wtmass(tmp_path: Path) -> None:
    """PARAM,WTMASS in the bulk data is not applied (NASTRAN's MAA/MGG already hold it; DMIG
    mass input is not scaled by it): a warning; the header's wtmass scales M (only M)."""
    K, M = element(FILE_BEAM)
    text = "PARAM,WTMASS,0.5\nGRID,101,,0.,0.,0.\nGRID,202,,2.,0.,0.\n"
    text += files.dmig("K", K, GRIDS, "free") + files.dmig("M", M, GRIDS, "free")
    (tmp_path / "se.bdf").write_text(text)
    keys = {
        "format": "dmig",
        "units": UNITS,
        "interface": GRIDS,
        "stiffness": {"file": "se.bdf", "matrix": "K"},
        "mass": {"file": "se.bdf", "matrix": "M"},
    }
    K_si, M_si = element(SI_BEAM)
    as_written = read_fe_model(files.header(tmp_path, **keys))
    (warning,) = as_written.warnings
    assert "PARAM,WTMASS,0.5" in warning.message and "se.bdf line 1" in warning.message
    assert as_written.wtmass == 1.0
    assert relative_error(as_written.model.mass, M_si) < TOLERANCE
    scaled = read_fe_model(files.header(tmp_path, wtmass=0.5, **keys))
    assert scaled.warnings == () and scaled.wtmass == 0.5
    assert relative_error(scaled.model.mass, 0.5 * M_si) < TOLERANCE
    assert relative_error(scaled.model.stiffness, K_si) < TOLERANCE


def test_imperial_units_without_wtmass_warn(
    beam_files: tuple[Path, np.ndarray, np.ndarray],
) -> None:
    folder, K, M = beam_files
    (folder / "se.op4").write_text(files.op4_ascii({"KAA": K, "MAA": M}, "sparse"))
    units = {"length": "in", "force": "lbf", "time": "s"}
    common = {
        "format": "op4",
        "units": units,
        "nodes": "nodes.csv",
        "interface": GRIDS,
        "stiffness": {"file": "se.op4", "matrix": "KAA"},
        "mass": {"file": "se.op4", "matrix": "MAA"},
    }
    warned = read_fe_model(files.header(folder, **common))
    assert len(warned.warnings) == 1 and "no wtmass" in warned.warnings[0].message
    slinch = 4.4482216152605 / 0.0254  # kg in one lbf*s^2/in
    assert warned.model.mass[0, 0] == pytest.approx(M[0, 0] * slinch, rel=1e-12)
    weighed = read_fe_model(files.header(folder, wtmass=1 / 386.0886, **common))
    assert weighed.warnings == ()
    assert weighed.model.mass[0, 0] == pytest.approx(M[0, 0] * slinch / 386.0886, rel=1e-12)


def test_header_units_with_mass(beam_files: tuple[Path, np.ndarray, np.ndarray]) -> None:
    """`mass: t` beside force N, length mm is consistent (1 t = 1 N*s^2/mm)."""
    folder, K, M = beam_files
    scipy.io.mmwrite(folder / "K.mtx", K, precision=17)
    scipy.io.mmwrite(folder / "M.mtx", M, precision=17)
    path = files.header(
        folder,
        format="matrix-market",
        units={**UNITS, "mass": "t"},
        stiffness="K.mtx",
        mass="M.mtx",
        nodes="nodes.csv",
        interface=GRIDS,
    )
    _assert_closed_form(path)
    data = json.loads(path.read_text())
    data["units"] = {"length": "mm", "mass": "t", "time": "s"}  # force derived
    path.write_text(json.dumps(data))
    _assert_closed_form(path)


def test_the_documented_export_script(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The numpy/scipy export script of docs/flexible-bodies-import.md, run as printed on
    the beam, writes files that read back as the closed form."""
    doc = Path(__file__).resolve().parents[3] / "docs" / "flexible-bodies-import.md"
    text = doc.read_text(encoding="utf-8").split("### Exporting", 1)[1]
    script = text.split("```python\n", 1)[1].split("```", 1)[0]
    K, M = element(FILE_BEAM)
    monkeypatch.chdir(tmp_path)
    names = {
        "K": K,
        "M": M,
        "node_ids": [1001, 1002],
        "coordinates": [[0.0, 0, 0], [FILE_BEAM.L, 0, 0]],
        "dof_map": [[n, c] for n in (1001, 1002) for c in range(1, 7)],
    }
    exec(compile(script, str(doc), "exec"), names)
    imported = read_fe_model(tmp_path / "panel.json")
    K_si, M_si = element(SI_BEAM)
    assert relative_error(imported.model.stiffness, K_si) < TOLERANCE
    assert relative_error(imported.model.mass, M_si) < TOLERANCE
    assert imported.node("hinge_b") == 1 and imported.model.interface == (0, 1)


def test_op4_ascii_without_dummy_values(tmp_path: Path) -> None:
    """Some writers end a matrix with its last record alone (no dummy value line)."""
    from loadcases.flexible.op4 import read_op4

    K, M = element(FILE_BEAM)
    text = files.op4_ascii({"KAA": K, "MAA": M}, "sparse")
    lines = text.splitlines()
    ends = [i for i, line in enumerate(lines) if line.startswith("      13       1       1")]
    kept = [line for i, line in enumerate(lines) if i - 1 not in ends]
    (tmp_path / "se.op4").write_text("\n".join(kept) + "\n")
    found = read_op4(tmp_path / "se.op4")
    assert len(kept) == len(lines) - 2
    assert np.array_equal(found["KAA"].matrix.toarray(), K)
    assert np.array_equal(found["MAA"].matrix.toarray(), M)
