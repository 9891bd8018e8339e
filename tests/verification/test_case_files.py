"""The verification case files themselves: well-formed, and with the intended mobility.

The YAML-level checks need no engine; `test_files_validate` asks the load-case layer
(`loadcases.inputs.loader.validate_files`, as `loads validate` does) for problems.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from conftest import LIBRARY

CASE_KEYS = {
    "case",
    "mechanism",
    "motions",
    "effects",
    "loads",
    "initial",
    "analysis",
    "requests",
    "abscissa",
    "units",
    "parameters",
}
MECHANISM_KEYS = {
    "name",
    "units",
    "gravity",
    "parameters",
    "bodies",
    "points",
    "joints",
    "forces",
    "contacts",
    "tables",
    "events",
}
EQUATIONS = {
    "fixed": 6,
    "revolute": 5,
    "prismatic": 5,
    "cylindrical": 4,
    "universal": 4,
    "spherical": 3,
    "planar": 3,
}
"""Constraint equations of each joint type in 3D (Gruebler-Kutzbach count)."""

# case file -> (degrees of freedom before motions by the Gruebler count, number of motions)
MOBILITY = {
    "slider_crank.case.yaml": (1, 1),
    "slider_crank_free.case.yaml": (1, 0),  # let go spinning: no drive motion
    "pendulum.case.yaml": (1, 0),
    "fourbar_quasistatic.case.yaml": (1, 1),
    "static_spring_bar.case.yaml": (1, 0),
    "heavy_top.case.yaml": (3, 0),
    "double_pendulum.case.yaml": (2, 0),
    # four revolutes: 18 - 20 = -2 by count, yet the loop moves: 3 redundant equations
    # (fourbar_redundant.case.yaml, refused by design, lives in tests/verification/cases)
    "fourbar_redundant_drop.case.yaml": (-2, 1),
    "latch_spring.case.yaml": (1, 0),
    "ball_in_socket.case.yaml": (6, 0),  # a free ball held by its contact only
    "ln_restitution.case.yaml": (6, 0),  # a free ball bouncing on a plane
}
CASE_FILES = sorted(MOBILITY)


def _load(path: Path) -> dict[str, Any]:
    with path.open(encoding="utf-8") as stream:
        data = yaml.safe_load(stream)
    assert isinstance(data, dict), f"{path.name}: not a mapping"
    return data


def _mechanism(case_path: Path) -> dict[str, Any]:
    """The case's mechanism mapping, inline or from the file it names."""
    mech = _load(case_path)["mechanism"]
    return _load(case_path.parent / mech) if isinstance(mech, str) else mech


def test_every_case_file_is_listed() -> None:
    """Each *.case.yaml in the verification library is checked here (and vice versa)."""
    assert sorted(p.name for p in LIBRARY.glob("*.case.yaml")) == CASE_FILES


@pytest.mark.parametrize("file_name", CASE_FILES)
def test_case_keys(file_name: str) -> None:
    """Top-level keys are those of SPEC 1.3 (and 1.2 for an inline mechanism); every case
    has a name, an analysis and requests."""
    case = _load(LIBRARY / file_name)
    assert set(case) <= CASE_KEYS, set(case) - CASE_KEYS
    assert {"case", "mechanism", "analysis", "requests"} <= set(case)
    assert set(_mechanism(LIBRARY / file_name)) <= MECHANISM_KEYS


@pytest.mark.parametrize("file_name", CASE_FILES)
def test_names_are_unique_and_resolved(file_name: str) -> None:
    """Names of bodies, points, joints and forces are unique across them (SPEC 1.2); joints
    and points refer to known bodies; requests and motions to known items."""
    mech = _mechanism(LIBRARY / file_name)
    sections = [list(mech.get(s, {}) or {}) for s in ("bodies", "points", "joints", "forces")]
    names = [n for section in sections for n in section]
    assert len(names) == len(set(names)), names
    bodies = set(mech["bodies"]) | {"ground"}
    for joint in mech.get("joints", {}).values():
        assert set(joint["bodies"]) <= bodies
    for point in (mech.get("points") or {}).values():
        assert point["body"] in bodies
    case = _load(LIBRARY / file_name)
    motions = case.get("motions") or {}
    for motion in motions.values():
        assert motion["joint"] in mech.get("joints", {})
    for name, request in case["requests"].items():
        if "joint" in request:
            assert request["joint"] in mech.get("joints", {}), name
        if "point" in request:
            assert request["point"] in mech["points"], name
        if "motion" in request:
            assert request["motion"] in motions, name
        if "force" in request:
            assert request["force"] in mech["forces"], name


@pytest.mark.parametrize("file_name", CASE_FILES)
def test_mobility(file_name: str) -> None:
    """Gruebler count 6 (bodies) - sum(joint equations) as designed (see MOBILITY)."""
    mech = _mechanism(LIBRARY / file_name)
    dof = 6 * len(mech["bodies"]) - sum(
        EQUATIONS[j["type"]] for j in mech.get("joints", {}).values()
    )
    expected_dof, motions = MOBILITY[file_name]
    assert dof == expected_dof
    assert len(_load(LIBRARY / file_name).get("motions") or {}) == motions


def test_files_validate() -> None:
    """`loads validate` finds no error in any verification file (the redundant four-bar is
    only refused when run: redundancy is a property of the built model)."""
    from loadcases.inputs.loader import validate_files

    paths = sorted(LIBRARY.glob("*.yaml"))
    errors = [d for d in validate_files(paths) if d.severity == "error"]
    assert not errors, "\n".join(d.format() for d in errors)


@pytest.mark.parametrize("file_name", CASE_FILES)
def test_no_toggle_warning(file_name: str, run_case) -> None:
    """Away from toggles no near-singular warning: the smallest toggle measure of these
    cases is 0.76 of its best (four-bar quasi-static), the threshold 0.1
    (docs/analyses.md, near-singular positions); nor through the free slider-crank's dead
    centres (slider_crank_free.case.yaml: its reactions stay bounded, its mobility whole)."""
    outcome = run_case(file_name)
    assert not [w for w in outcome.solution.warnings if "near-singular" in w]
