"""Bad imports stop with an InputError (exit 2) whose diagnostics name the file, the line and
key where known, and what is wrong."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.io

from loadcases.flexible.read import read_fe_model
from loadcases.foundation.diagnostics import Diagnostic, InputError
from tests.loadcases.flexible import files
from tests.loadcases.flexible.beam import FILE_BEAM, element

UNITS = {"length": "mm", "force": "N", "time": "s"}
GRIDS = [101, 202]


def _problems(path: Path) -> list[Diagnostic]:
    with pytest.raises(InputError) as caught:
        read_fe_model(path)
    return caught.value.diagnostics


def _one(
    path: Path, *, file: Path, words: str, line: int | None = None, key: str | None = None
) -> None:
    problems = _problems(path)
    assert len(problems) == 1, problems
    problem = problems[0]
    assert problem.file == str(file) and words in problem.message, problem
    if line is not None:
        assert problem.line == line, problem
    if key is not None:
        assert problem.key == key, problem


def _line_of(path: Path, text: str) -> int:
    """1-based line of the first occurrence of `text` in the file."""
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def _mm_beam(folder: Path, K: np.ndarray, M: np.ndarray, **keys: object) -> Path:
    scipy.io.mmwrite(folder / "K.mtx", K, precision=17)
    scipy.io.mmwrite(folder / "M.mtx", M, precision=17)
    files.nodes_csv(folder, GRIDS, np.array([0.0, 2.0]))
    return files.header(
        folder,
        **{
            "format": "matrix-market",
            "units": UNITS,
            "stiffness": "K.mtx",
            "mass": "M.mtx",
            "nodes": "nodes.csv",
            "interface": GRIDS,
            **keys,
        },
    )


def test_not_json(tmp_path: Path) -> None:
    path = tmp_path / "part.json"
    path.write_text('{\n  "format": "npz",\n  "units": {"length": "mm",}\n}\n')
    _one(path, file=path, words="not valid JSON", line=3)


def test_unknown_key_and_format(tmp_path: Path) -> None:
    path = files.header(tmp_path, format="nastran", units=UNITS, stifness="K.mtx")
    problems = _problems(path)
    lines = {"stifness": _line_of(path, '"stifness"'), "format": _line_of(path, '"format"')}
    assert {(p.key, p.line) for p in problems} == set(lines.items())
    assert "one of npz, matrix-market, op4, dmig" in next(
        p.message for p in problems if p.key == "format"
    )


@pytest.mark.parametrize(
    ("units", "key", "words"),
    [
        ({"length": "furlong_x", "force": "N"}, "units.length", "unknown unit 'furlong_x'"),
        ({"length": "kg", "force": "N"}, "units.length", "not a unit of length"),
        ({"force": "N"}, "units", "missing unit: length"),
        ({"length": "mm"}, "units", "force or mass"),
        ({"length": "in", "force": "lbf", "mass": "lb"}, "units.mass", "not consistent"),
        ({"length": "mm", "force": "N", "angle": "deg"}, "units.angle", "unknown unit kind"),
    ],
)
def test_units(tmp_path: Path, units: dict[str, str], key: str, words: str) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K, M, units=units)
    _one(path, file=path, words=words, key=key)


def test_missing_matrix_file(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K, M, mass="nowhere.mtx")
    _one(path, file=path, words="file not found", key="mass", line=_line_of(path, '"mass"'))


def test_file_outside_the_folder(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K, M, stiffness="../K.mtx")
    _one(path, file=path, words="leaves the folder", key="stiffness")


def test_unsymmetric_stiffness(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    K[0, 1] += 1e-6 * np.abs(K).max()
    path = _mm_beam(tmp_path, K, M)
    _one(path, file=tmp_path / "K.mtx", words="not symmetric")


def test_symmetric_within_tolerance(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    K[0, 1] += 1e-11 * np.abs(K).max()  # below the 1e-9 limit
    assert read_fe_model(_mm_beam(tmp_path, K, M)).model.stiffness.shape == (12, 12)


def test_negative_mass(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    M[8, 8] = -M[8, 8]
    path = _mm_beam(tmp_path, K, M)
    _one(path, file=tmp_path / "M.mtx", words="negative diagonal terms, the first at node 202 uz")


def test_indefinite_mass(tmp_path: Path) -> None:
    """Positive diagonal, yet an eigenvalue below zero: x^T M x < 0 for x = e0 - e6."""
    K, M = element(FILE_BEAM)
    M[0, 6] = M[6, 0] = 2 * M[0, 0]
    path = _mm_beam(tmp_path, K, M)
    _one(path, file=tmp_path / "M.mtx", words="not positive semi-definite")


def test_size_against_the_dof_map(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K[:6, :6], M)
    _one(path, file=tmp_path / "K.mtx", words="is 6 x 6 but the DOF map has 12 DOF")


def test_interface_node_without_six_dof(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    (tmp_path / "dofs.csv").write_text(
        "node,component\n"
        + "".join(f"{g},{c}\n" for g in GRIDS for c in range(1, 7) if (g, c) != (202, 6))
    )
    keep = [i for i in range(12) if i != 11]
    path = _mm_beam(tmp_path, K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], dofs="dofs.csv")
    _one(path, file=path, words="carries 5 DOF", key="interface[1]")


def test_unknown_interface_node(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K, M, interface=[101, "hinge"])
    _one(path, file=path, words='no node "hinge"', key="interface[1]")


def test_wtmass_is_for_nastran(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K, M, wtmass=0.00259)
    _one(path, file=path, words="wtmass is for NASTRAN", key="wtmass")


def test_node_table_errors(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    path = _mm_beam(tmp_path, K, M)
    (tmp_path / "nodes.csv").write_text("id,x,y,z\n101,0,0,0\n202,two,0,0\n")
    _one(path, file=tmp_path / "nodes.csv", words="expected a number, got 'two'", line=3, key="x")


def test_op4_several_matrices_need_a_name(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    (tmp_path / "se.op4").write_text(files.op4_ascii({"KAA": K, "MAA": M}, "sparse"))
    files.nodes_csv(tmp_path, GRIDS, np.array([0.0, 2.0]))
    path = files.header(
        tmp_path,
        format="op4",
        units=UNITS,
        nodes="nodes.csv",
        stiffness="se.op4",
        mass={"file": "se.op4", "matrix": "MGG"},
    )
    problems = _problems(path)
    messages = sorted(p.message for p in problems)
    assert messages == [
        "se.op4 has no matrix MGG (it holds KAA, MAA)",
        "se.op4 holds the matrices KAA, MAA: name one",
    ]


def test_op4_truncated_binary(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    data = files.op4_binary({"KAA": K}, "sparse")
    (tmp_path / "k.op4").write_bytes(data[:-30])
    (tmp_path / "m.op4").write_bytes(files.op4_binary({"MAA": M}, "sparse"))
    files.nodes_csv(tmp_path, GRIDS, np.array([0.0, 2.0]))
    path = files.header(
        tmp_path, format="op4", units=UNITS, nodes="nodes.csv", stiffness="k.op4", mass="m.op4"
    )
    _one(path, file=tmp_path / "k.op4", words="truncated or not an OP4 file")


def test_op4_complex_refused(tmp_path: Path) -> None:
    text = (
        "       1       1       1       4C       1P,3E23.16\n       2       1       1\n 1.0E+00\n"
    )
    (tmp_path / "c.op4").write_text(text)
    files.nodes_csv(tmp_path, GRIDS, np.array([0.0, 2.0]))
    path = files.header(
        tmp_path, format="op4", units=UNITS, nodes="nodes.csv", stiffness="c.op4", mass="c.op4"
    )
    problems = _problems(path)
    assert {p.message for p in problems} == {"matrix C is complex: stiffness and mass are real"}
    assert {p.line for p in problems} == {1}


@pytest.mark.parametrize(
    ("entry", "words"),
    [
        ("DMIG,K,101,0,,101,1,1.0", "scalar points are not supported"),
        ("GRID,303,7,0.,0.,0.", "coordinate system 7"),
        ("DMIG,K,101,1,,101,1,abc", "expected a real number, got 'abc'"),
    ],
)
def test_dmig_entries(tmp_path: Path, entry: str, words: str) -> None:
    text = "DMIG,K,0,6,2,0,,,12\nDMIG,M,0,6,2,0,,,12\n$ comment\n" + entry + "\n"
    (tmp_path / "se.pch").write_text(text)
    path = files.nastran_header(tmp_path, "dmig", "se.pch", ("K", "M"), units=UNITS)
    _one(path, file=tmp_path / "se.pch", words=words, line=4)


def test_dmig_without_grids(tmp_path: Path) -> None:
    K, M = element(FILE_BEAM)
    (tmp_path / "se.pch").write_text(
        files.dmig("K", K, GRIDS, "small") + files.dmig("M", M, GRIDS, "small")
    )
    path = files.nastran_header(tmp_path, "dmig", "se.pch", ("K", "M"), units=UNITS)
    _one(path, file=path, words="no GRID entry for grids 101, 202", key="nodes")
