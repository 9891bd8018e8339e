"""Loader: good files load to SI models; each bad file gives exactly the expected messages."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError, sort_diagnostics
from loadcases.inputs.kinds import file_kind
from loadcases.inputs.loader import load_case, load_mechanism, load_set, validate_files

HERE = Path(__file__).parent
BAD, GOOD = HERE / "bad", HERE / "good"

EXPECTED = {
    "duplicate_key.mech.yaml": [
        "duplicate_key.mech.yaml:3:3: error: bodies.arm: duplicate key (first given on line 2)",
        "duplicate_key.mech.yaml:3:3: hint: remove one of them: YAML keeps only one value per key",
    ],
    "duplicate_name.mech.yaml": [
        "duplicate_name.mech.yaml:4:3: error: points.arm: name 'arm' is already used in bodies",
        "duplicate_name.mech.yaml:4:3: hint: names of bodies, points, joints, forces, contacts, "
        "limits, tables and events must be unique",
    ],
    "expressions.case.yaml": [
        "expressions.case.yaml:4:33: error: motions.drive.value: unknown name 'sped' in expression",
        "expressions.case.yaml:4:33: hint: did you mean 'speed'?",
        "expressions.case.yaml:5:11: error: motions.twist.joint: unknown joint 'hinj'",
        "expressions.case.yaml:5:11: hint: did you mean 'hinge'?",
        "expressions.case.yaml:5:38: error: motions.twist.value: invalid expression: expected ')'",
        "expressions.case.yaml:8:26: error: requests.a.expression: unknown joint 'hingee'",
        "expressions.case.yaml:8:26: hint: did you mean 'hinge'?",
        "expressions.case.yaml:8:42: error: requests.a.expression: unknown table 'curve'",
    ],
    "inline.case.yaml": [
        "inline.case.yaml:5:11: error: mechanism.bodies.arm.mass: mass must be positive",
        "inline.case.yaml:6:12: error: analysis.type: expected 'kinematic', 'static', "
        "'quasi-static', 'dynamic' or 'modes', got 'statik'",
        "inline.case.yaml:6:12: hint: did you mean 'static'?",
    ],
    "missing_mechanism.case.yaml": [
        "missing_mechanism.case.yaml:2:1: error: mechanism: mechanism file not found: "
        "bas.mech.yaml",
        "missing_mechanism.case.yaml:2:1: hint: did you mean 'base.mech.yaml'?",
        "missing_mechanism.case.yaml:3:1: error: analysis.end: a dynamic analysis needs 'end' (s)",
    ],
    "nomatch.set.yaml": [
        "nomatch.set.yaml:2:9: error: cases[0]: no case file matches 'lifting/*.case.yaml'",
        "nomatch.set.yaml:4:10: error: report.output: expected an .xlsx file name",
    ],
    "physics.mech.yaml": [
        "physics.mech.yaml:2:11: error: bodies.light.mass: mass must be positive",
        "physics.mech.yaml:3:34: error: bodies.flat.inertia: principal moments break the triangle "
        "inequality (3 > 1 + 1)",
        "physics.mech.yaml:3:34: hint: each principal moment must be <= the sum of the others",
        "physics.mech.yaml:4:34: error: bodies.bent.inertia: inertia is not positive definite "
        "(principal moments -1, 1, 3)",
        "physics.mech.yaml:6:64: error: joints.j1.axis: axis is a zero vector",
        "physics.mech.yaml:7:63: error: joints.j2.axes: the axes of the universal are parallel",
        "physics.mech.yaml:7:63: hint: give two axes at an angle (usually perpendicular)",
        "physics.mech.yaml:8:25: error: joints.j3.bodies: joint joins body 'bent' to itself",
        "physics.mech.yaml:9:36: error: joints.j4.joints[1]: unknown joint 'j9'",
        "physics.mech.yaml:9:36: hint: known joint names: j1, j2, j3, j4, j5",
        "physics.mech.yaml:10:64: error: joints.j5.axis: axis is too long to normalise (its "
        "length overflows); give a unit vector",
    ],
    "references.case.yaml": [
        "references.case.yaml:3:27: warning: effects.friktion: unknown effect 'friktion'",
        "references.case.yaml:3:27: hint: did you mean 'friction'?",
        "references.case.yaml:4:15: error: loads[1]: unknown force element 'spring'",
        "references.case.yaml:4:15: hint: known force element names: coil",
        "references.case.yaml:6:3: error: initial.hing: unknown joint or body 'hing'",
        "references.case.yaml:6:3: hint: did you mean 'hinge'?",
        "references.case.yaml:7:11: error: initial.hinge.value: expected an angle, got '3 m' (a "
        "length) for a revolute joint",
        "references.case.yaml:10:38: error: requests.f.frame: unknown frame 'arn'",
        "references.case.yaml:10:38: hint: did you mean 'arm'?",
        "references.case.yaml:11:7: error: requests.p.point: unknown point 'tipp'",
        "references.case.yaml:11:7: hint: did you mean 'tip'?",
        "references.case.yaml:12:7: error: requests.m.motion: unknown motion 'drive'",
    ],
    "servo_actuator.mech.yaml": [
        "servo_actuator.mech.yaml:11:61: error: forces.act.fidelity: expected 'lag', 'valve' or "
        "'jet_pipe', got 'servo'",
        "servo_actuator.mech.yaml:12:106: error: forces.act2.controller.kp: expected a current "
        "gain, got '2 N' (a force)",
    ],
    "servo_stroke.mech.yaml": [
        "servo_stroke.mech.yaml:11:71: error: forces.act.command: unknown name 'stroke_demand' in "
        "expression",
        "servo_stroke.mech.yaml:11:71: hint: use t, pi, a parameter, a unit name or a function",
        "servo_stroke.mech.yaml:11:87: error: forces.act.stroke: expected [retracted, extended] "
        "limits around the design length (0), got [0.01, 0.05] m",
        "servo_stroke.mech.yaml:11:87: hint: the stroke is measured from the design distance of "
        "the two points",
        "servo_stroke.mech.yaml:11:116: error: forces.act.cylinder.dead_volumes: expected two "
        "positive volumes [V1, V2], got 1 values",
    ],
    "units.mech.yaml": [
        "units.mech.yaml:1:9: error: units.length: 'deg' is not a unit of length",
        "units.mech.yaml:1:22: error: units.angel: unknown key",
        "units.mech.yaml:1:22: hint: did you mean 'angle'?",
    ],
    "unknown_body.mech.yaml": [
        "unknown_body.mech.yaml:4:41: error: joints.hinge.bodies[1]: unknown body 'grund'",
        "unknown_body.mech.yaml:4:41: hint: did you mean 'ground'?",
    ],
    "unknown_key.mech.yaml": [
        "unknown_key.mech.yaml:2:3: error: bodies.door.mass: required key is missing",
        "unknown_key.mech.yaml:3:5: error: bodies.door.mas: unknown key",
        "unknown_key.mech.yaml:3:5: hint: did you mean 'mass'?",
    ],
    "unknown_type.mech.yaml": [
        "unknown_type.mech.yaml:4:11: error: joints.hinge.type: unknown type 'revolut'",
        "unknown_type.mech.yaml:4:11: hint: did you mean 'revolute'?",
    ],
    "planar.case.yaml": [
        "planar.case.yaml:10:9: error: initial.arm.omega: an initial omega out of plane yz",
        "planar.case.yaml:10:9: hint: keep velocities in the plane and omega along x",
        "planar.case.yaml:10:29: error: initial.arm.velocity: an initial velocity out of plane yz",
        "planar.case.yaml:10:29: hint: keep velocities in the plane and omega along x",
    ],
    "limits.mech.yaml": [
        "limits.mech.yaml:10:7: error: limits.a.joint: unknown joint 'hing'",
        "limits.mech.yaml:10:7: hint: did you mean 'hinge'?",
        "limits.mech.yaml:11:30: error: limits.b.max: must be > min, got max 10.0 <= min 20.0 "
        "(0.174533 <= 0.349066 rad)",
        "limits.mech.yaml:12:7: error: limits.c.joint: joint 'socket' is spherical; a limit needs "
        "a revolute, prismatic or cylindrical joint",
        "limits.mech.yaml:13:21: error: limits.d.coordinate: joint 'hinge' is revolute: it has no "
        "travel coordinate",
        "limits.mech.yaml:14:21: error: limits.e.max: expected an angle, got '5 mm' (a length)",
        "limits.mech.yaml:15:60: error: limits.k.depth: must be > 0, got -1 deg",
    ],
    "limit_keys.mech.yaml": [
        "limit_keys.mech.yaml:7:3: error: limits.f: give 'min', 'max' or both",
        "limit_keys.mech.yaml:8:3: error: limits.g: 'damping' needs 'depth' (full damping there)",
        "limit_keys.mech.yaml:9:47: error: limits.h.restitution: must be <= 1, got 1.5",
        "limit_keys.mech.yaml:10:7: error: limits.i.type: unknown key",
        "limit_keys.mech.yaml:10:7: hint: allowed keys: joint, coordinate, min, max, stiffness, "
        "exponent, damping, depth, restitution, active",
    ],
    "limits.case.yaml": [
        "limits.case.yaml:6:9: error: loads[0]: 'stop' is a limit: limits are not loads, they "
        "act unless `effects: {contact: false}` or an `active: false` keeps them off",
        "limits.case.yaml:6:9: hint: remove 'stop' from loads",
        "limits.case.yaml:9:7: error: requests.r.limit: unknown limit 'stopp'",
        "limits.case.yaml:9:7: hint: did you mean 'stop'?",
    ],
    "planar.mech.yaml": [
        "planar.mech.yaml:4:1: error: gravity: gravity has a component along z, out of plane xy",
        "planar.mech.yaml:4:1: hint: set it to 0",
        "planar.mech.yaml:10:67: error: joints.pivot.axis: the axis of a revolute joint must be "
        "along the normal of plane xy (z)",
        "planar.mech.yaml:10:67: hint: remove `plane` to use the 3-D model",
        "planar.mech.yaml:11:11: error: joints.pin.type: a perpendicular joint has no planar form",
        "planar.mech.yaml:11:11: hint: remove `plane` to use the 3-D model",
        "planar.mech.yaml:12:72: error: joints.guide.axis: the axis of a prismatic joint must lie "
        "in plane xy",
        "planar.mech.yaml:12:72: hint: remove `plane` to use the 3-D model",
        "planar.mech.yaml:13:69: error: joints.knot.axes: a universal joint needs one axis along "
        "the normal of plane xy (z) and the other in the plane",
        "planar.mech.yaml:13:69: hint: remove `plane` to use the 3-D model",
        "planar.mech.yaml:15:49: error: forces.push.value[2]: a force component along the normal "
        "(2*t) leaves plane xy",
        "planar.mech.yaml:15:49: hint: make it 0, or remove `plane` to use the 3-D model",
        "planar.mech.yaml:16:44: error: forces.twist.value[0]: a torque component about an "
        "in-plane axis (1.0) leaves plane xy",
        "planar.mech.yaml:16:44: hint: make it 0, or remove `plane` to use the 3-D model",
        "planar.mech.yaml:19:163: error: contacts.floor.geometry.normal: the plane's normal "
        "must lie in plane xy: the contact would leave the plane",
        "planar.mech.yaml:19:163: hint: remove `plane` to use the 3-D model",
    ],
    "vector_length.mech.yaml": [
        "vector_length.mech.yaml:4:65: error: joints.hinge.axis: expected 3 values, got 2",
    ],
    "wrong_dimension.mech.yaml": [
        "wrong_dimension.mech.yaml:3:20: error: bodies.arm.cm: item 2: expected a length, got '12 "
        "kg' (a mass)",
        "wrong_dimension.mech.yaml:7:46: error: forces.coil.stiffness: expected a torsional "
        "stiffness, got '50 N/m' (a stiffness)",
    ],
    "yaml_syntax.mech.yaml": [
        "yaml_syntax.mech.yaml:4:3: error: YAML syntax error: expected ',' or '}', but got "
        "'<scalar>' (while parsing a flow mapping)",
    ],
}


def _messages(name: str) -> list[str]:
    text = "\n".join(d.format() for d in sort_diagnostics(validate_files([name])))
    return text.splitlines()


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_bad_file_messages(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(BAD)
    assert _messages(name) == EXPECTED[name]


def test_every_bad_file_is_covered() -> None:
    files = {p.name for p in BAD.glob("*.yaml")} - {"base.mech.yaml", "params.set.yaml"}
    assert files == set(EXPECTED)


def test_base_mechanism_is_valid(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(BAD)
    assert validate_files(["base.mech.yaml"]) == []


def test_set_sweep_names_checked_against_cases(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(BAD)
    lines = _messages("params.set.yaml")
    assert "params.set.yaml:3:9: error: sweep.crank_sped: unknown parameter 'crank_sped'" in lines
    assert "params.set.yaml:3:9: hint: did you mean 'crank_speed'?" in lines
    # the cases of the set are validated too
    assert any(line.startswith("references.case.yaml:4:15: error: loads[1]") for line in lines)


def test_load_case_raises_all_diagnostics(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(BAD)
    with pytest.raises(InputError) as raised:
        load_case("references.case.yaml")
    errors = [d for d in raised.value.diagnostics if d.severity == "error"]
    assert len(errors) == 6


def test_good_case_in_si(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(GOOD)
    case = load_case("slider-crank.case.yaml")
    mech = case.mechanism
    assert case.mechanism_path == "slider-crank.mech.yaml"
    assert mech.bodies["crank"].cm == pytest.approx((0.05, 0.0, 0.0))
    assert mech.points["slider_c"].at == pytest.approx((0.4, 0.0, 0.0))
    assert mech.joints["small"].axes[1] == pytest.approx((0.0, 1.0, 0.0))
    assert mech.forces["wire"].free_length == pytest.approx(0.85)  # mm file
    assert mech.forces["wire"].stiffness == pytest.approx(2.0e6)  # compound: SI
    assert mech.forces["latch"].angle0 == pytest.approx(math.pi / 2)
    assert mech.forces["rub"].pin_radius == pytest.approx(0.01)
    assert mech.forces["rub"].preload == pytest.approx(0.5)
    assert mech.tables["wind_moment"].x[1] == pytest.approx(math.radians(30))
    assert mech.contacts["stop"].geometry.radius == pytest.approx(0.01)
    assert mech.contacts["stop"].depth == pytest.approx(1.0e-4)
    assert mech.events["enough"].then[0].action == "stop"
    # case parameters override the mechanism's
    assert case.parameters["crank_speed"] == pytest.approx(4 * math.pi)
    # initial joint values by joint type, in the case file's units (SI here)
    assert case.case.initial["pivot"].value == pytest.approx(10.0)
    assert case.case.initial["pivot"].rate == pytest.approx(2.0)
    assert case.case.initial["guide"].value == pytest.approx(0.005)
    assert case.case.initial["rod"].velocity == pytest.approx((1.0, 0.0, 0.0))
    assert case.case.requests["wire_force"].quantity == "force"
    assert case.case.analysis.redundant == "error"
    assert len(case.input_sha256) == 64
    assert case.warnings == ()


def test_where_gives_file_line_column(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(GOOD)
    case = load_case("slider-crank.case.yaml")
    assert case.where("mechanism", "joints.guide") == ("slider-crank.mech.yaml", 23, 3)
    assert case.where("case", ("requests", "slider_pos")) == ("slider-crank.case.yaml", 20, 3)
    assert case.where("mechanism", "joints.small.axes[1]") == ("slider-crank.mech.yaml", 22, 89)


def test_inline_mechanism_and_units(tmp_path: Path) -> None:
    path = tmp_path / "inline.case.yaml"
    path.write_text(
        "case: inline\nunits: {length: mm}\nmechanism:\n  bodies:\n"
        "    arm: {mass: 1, cm: [10, 0, 0], inertia: [1, 1, 1]}\n"
        "analysis: {type: static}\n",
        encoding="utf-8",
    )
    case = load_case(path)
    assert case.mechanism_path is None
    assert case.mechanism.bodies["arm"].cm[0] == pytest.approx(0.01)  # inherits case units
    assert case.where("mechanism", "bodies.arm")[1:] == (5, 5)


def test_load_mechanism_and_set(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.chdir(GOOD)
    mech = load_mechanism("slider-crank.mech.yaml")
    assert mech.model.name == "slider-crank"
    for name in ("slider-crank.case.yaml", "slider-crank.mech.yaml"):  # a glob stays in
        shutil.copy(GOOD / name, tmp_path / name)  # the set's folder
    (tmp_path / "a.set.yaml").write_text(
        "set: s\ncases: ['*.case.yaml']\nsweep: {crank_speed: [1 rad/s, 2]}\n"
        "factors: {ultimate: 1.5}\nreport: {output: out.xlsx}\n",
        encoding="utf-8",
    )
    loaded = load_set(tmp_path / "a.set.yaml")
    assert [Path(p).name for p in loaded.case_paths] == ["slider-crank.case.yaml"]
    assert loaded.model.sweep["crank_speed"] == [1.0, 2.0]
    assert validate_files([tmp_path / "a.set.yaml"]) == []


def test_sets_sharing_a_case_validate_together(tmp_path: Path) -> None:
    """Two sets naming the same case, validated in one call: the second set's columns are
    checked against all its cases, the shared one included (it was once left out, so a
    request only it had was reported unknown, and a set whose cases were all left out was
    not checked at all), and the case's diagnostics come once."""
    for name in ("slider-crank.case.yaml", "slider-crank.mech.yaml"):
        shutil.copy(GOOD / name, tmp_path / name)
    request = next(iter(load_case(tmp_path / "slider-crank.case.yaml").case.requests))
    for name in ("a", "b"):
        (tmp_path / f"{name}.set.yaml").write_text(
            f"set: {name}\ncases: [slider-crank.case.yaml]\n"
            f"report: {{output: o.xlsx, charts: [{request}]}}\n",
            encoding="utf-8",
        )
    sets = [tmp_path / "a.set.yaml", tmp_path / "b.set.yaml"]
    assert validate_files(sets) == []
    (tmp_path / "b.set.yaml").write_text(
        "set: b\ncases: [slider-crank.case.yaml]\n"
        "report: {output: o.xlsx, charts: [no_such_request]}\n",
        encoding="utf-8",
    )
    assert [d.key for d in validate_files(sets)] == ["report.charts[0]"]


def test_file_kind(tmp_path: Path) -> None:
    """The suffix decides; a file without one of the suffixes is told by its top-level keys."""
    assert file_kind("x.case.yaml") == "case" and file_kind("X.SET.YML") == "set"
    assert file_kind("missing.mech.yaml") == "mechanism"  # the suffix alone: not read
    for text, kind in (
        ("set: a\n", "set"),
        ("bodies: {}\n", "mechanism"),
        ("case: c\n", "case"),
        ("foo: 1\n", None),
    ):
        (tmp_path / "x.yaml").write_text(text, encoding="utf-8")
        assert file_kind(tmp_path / "x.yaml") == kind, text
    with pytest.raises(InputError):
        file_kind(tmp_path / "missing.yaml")
