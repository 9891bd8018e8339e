"""Case skeletons (loadcases.inputs.scaffold): every kind validates and runs; files are never
overwritten; the physics of each stand-in mechanism is what its comments say."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from loadcases.inputs import scaffold
from loadcases.inputs.loader import load_case, validate_files
from loadcases.run import run_case

KINDS = ["blank", "lifting", "jamming", "opening", "opened", "jettison", "deployment", "rod-end"]


def test_blank_and_the_seven_families_are_offered() -> None:
    assert list(scaffold.SKELETONS) == KINDS
    for kind in KINDS:
        assert scaffold.template_path(kind).is_file()


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """Every skeleton written as `my-KIND`, validated and run once."""
    folder = tmp_path_factory.mktemp("skeletons")
    done = {}
    for kind in KINDS:
        path = scaffold.write_skeleton(kind, f"my-{kind}", folder)
        assert path == folder / f"my-{kind}.case.yaml"
        assert [d for d in validate_files([path]) if d.severity == "error"] == []
        cf = load_case(path)
        assert cf.case.case == f"my-{kind}"
        done[kind] = run_case(cf)
    return done


@pytest.mark.parametrize("kind", KINDS)
def test_every_skeleton_runs_ok(outcomes: dict, kind: str) -> None:
    solution = outcomes[kind].solution
    assert solution.status == "ok", solution.message
    assert solution.time.size >= 1
    for name, values in solution.channels.items():
        assert np.isfinite(values).all(), name


def col(outcomes: dict, kind: str, column: str) -> np.ndarray:
    return outcomes[kind].solution.channels[column]


def test_blank_drive_torque_is_the_static_moment(outcomes: dict) -> None:
    """The arm turns at constant rate (no angular acceleration): the drive torque is the
    moment of the weight (2 kg at 0.25 m) and of the 50 N tip load (at 0.5 m),
    (2 * 9.81 * 0.25 + 50 * 0.5) cos(angle) N*m, to 1e-9 N*m."""
    angle = col(outcomes, "blank", "arm_angle.value")
    torque = col(outcomes, "blank", "drive_torque.value")
    assert angle[-1] == pytest.approx(math.pi / 2, abs=1e-12)
    np.testing.assert_allclose(torque, (2 * 9.81 * 0.25 + 50 * 0.5) * np.cos(angle), atol=1e-9)


def test_lifting_handle_torque_changes_sign_past_top_dead_centre(outcomes: dict) -> None:
    torque = col(outcomes, "lifting", "handle_torque.value")
    angle = col(outcomes, "lifting", "latch_shaft_rotation.value")
    assert angle[-1] == pytest.approx(math.radians(110), abs=1e-9)
    assert torque[angle < math.radians(80)].max() > 10.0  # N*m to lift the door
    assert torque[angle > math.radians(100)].max() < 0.0  # goes on by itself
    # the guide and lever carry the door weight (80 kg) between them
    assert col(outcomes, "lifting", "latch_shaft_force.fy").min() > 80 * 9.81 * 0.99


def test_jamming_rod_force_is_the_handle_load_times_the_lever_ratio(outcomes: dict) -> None:
    axial = col(outcomes, "jamming", "rod_p2p6_force.fx")
    # 1334 N at 300 mm on a 100 mm lever, rod along x at the design position: 4002 N
    # compression (weight of the light links neglected within 0.5 %)
    assert axial[0] == pytest.approx(-3 * 1334.0, rel=5e-3)


def test_opening_reaches_the_open_angle(outcomes: dict) -> None:
    angle = col(outcomes, "opening", "hinge_angle.value")
    assert angle[0] == pytest.approx(0.0, abs=1e-9)
    assert math.degrees(angle[-1]) == pytest.approx(102.0, abs=0.5)
    # the aft hinge (inline) carries no load along the hinge line
    assert np.abs(col(outcomes, "opening", "hinge_aft_force.fx")).max() < 1e-6


def test_opened_door_hangs_on_the_wire_and_the_cb_rod(outcomes: dict) -> None:
    assert col(outcomes, "opened", "wire_force.value")[0] > 100.0
    assert math.degrees(col(outcomes, "opened", "hinge_angle.value")[0]) == pytest.approx(
        101.0, abs=1.0
    )
    # the CB rod (a spring at its open length) holds the door back too: in tension
    assert col(outcomes, "opened", "cb_rod_force.value")[0] > 100.0
    # the aft hinge (inline) carries no load along the hinge line
    assert abs(col(outcomes, "opened", "hinge_aft_force.fx")[0]) < 1e-6


def test_jettison_passes_the_release_angle(outcomes: dict) -> None:
    angle = col(outcomes, "jettison", "hinge_angle.value")
    assert math.degrees(angle[-1]) > 113.0
    assert col(outcomes, "jettison", "hinge_rate.value")[-1] > 0.0


def test_deployment_moves_in_step_up_to_the_deployed_angle(outcomes: dict) -> None:
    hl1 = col(outcomes, "deployment", "hl1_angle.value")
    hl2 = col(outcomes, "deployment", "hl2_angle.value")
    hl3 = col(outcomes, "deployment", "hl3_angle.value")
    np.testing.assert_allclose(hl2, -2 * hl1, atol=1e-8)
    np.testing.assert_allclose(hl3, -hl2, atol=1e-8)
    assert 80.0 < math.degrees(hl1[-1]) <= 90.0


def test_rod_end_duty_cycle_deflects_about_35_deg(outcomes: dict) -> None:
    angle = col(outcomes, "rod-end", "surface_angle.value")
    assert math.degrees(np.abs(angle).max()) == pytest.approx(35.0, abs=1.5)


def test_existing_file_is_never_overwritten(tmp_path: Path) -> None:
    target = tmp_path / "mine.case.yaml"
    target.write_text("case: mine\n")
    with pytest.raises(FileExistsError, match="exists: not overwritten"):
        scaffold.write_skeleton("opening", "mine", tmp_path)
    assert target.read_text() == "case: mine\n"
    assert [p.name for p in tmp_path.iterdir()] == ["mine.case.yaml"]


@pytest.mark.parametrize("name", ["", "../up", "a/b", "-x", "x.case.yaml", "sp ace"])
def test_invalid_names_are_refused(tmp_path: Path, name: str) -> None:
    with pytest.raises(ValueError, match="invalid name"):
        scaffold.write_skeleton("lifting", name, tmp_path)
    assert not list(tmp_path.iterdir())


def test_unknown_kind_suggests_the_closest() -> None:
    with pytest.raises(ValueError, match=r"unknown kind 'jetison' \(did you mean 'jettison'\?\)"):
        scaffold.template_path("jetison")


def test_names_that_yaml_would_read_as_other_types_are_quoted(tmp_path: Path) -> None:
    text = scaffold.skeleton_text("lifting", "true")
    assert 'case: "true"' in text
    path = scaffold.write_skeleton("lifting", "1.5", tmp_path)
    assert load_case(path).case.case == "1.5"
