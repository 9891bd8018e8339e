"""`validate` reports every input error in one pass: the semantic checks run on the valid
part of a file whose schema check failed (loadcases.inputs.partial)."""

from __future__ import annotations

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case, load_mechanism

CASE = """\
case: several
mechanism:
  parameters:
    mu_trunnion: 0.1
    k_arm: 20 N/mm
  bodies:
    arm: {mass: -2.0, cm: [0.5, 0, 0], inertia: [0.001, 0.17, 0.17]}
  points:
    tip: {body: arm, at: [1.0, 0, 0]}
  joints:
    hinge: {type: revolute, bodies: [arm, grund], at: [0, 0, 0], axis: [0, 0, 1]}
  forces:
    rub: {type: joint_friction, joint: hinge, mu: mu_trunion, pin_radius: 10 mm}
    coil: {type: torsion_spring, joint: hinge, stiffness: k_arm}
motions:
  lift: {joint: hinge, value: "step(t, 0, 0, 1, 80*deg)"}
analysis: {type: kinematic, end: 1, step: 0.01}
requests:
  a: {expression: "angle(hinge) + x(tip)"}
  b: {expression: "crank_sped * t"}
  rub_torque: {force: rub, quantity: force}
"""


def _errors(error: InputError) -> list[str]:
    found = sorted(
        (d.line, d.column, d.key, d.message) for d in error.diagnostics if d.severity == "error"
    )
    return [f"{line}:{column}: {key}: {message}" for line, column, key, message in found]


def test_schema_and_semantic_errors_of_a_case_are_reported_together(tmp_path):
    path = tmp_path / "several.case.yaml"
    path.write_text(CASE, encoding="utf-8")
    with pytest.raises(InputError) as raised:
        load_case(path)
    # before: the two schema errors alone (rub.mu, coil.stiffness); the rest needed two
    # more passes. The request of the invalid force `rub` is not reported as unknown.
    assert _errors(raised.value) == [
        "7:11: mechanism.bodies.arm.mass: mass must be positive",
        "11:43: mechanism.joints.hinge.bodies[1]: unknown body 'grund'",
        "13:47: mechanism.forces.rub.mu: unknown parameter 'mu_trunion'",
        "14:48: mechanism.forces.coil.stiffness: expected a torsional stiffness, got "
        "parameter 'k_arm' = '20 N/mm' (a stiffness)",
        "19:33: requests.a.expression: cannot add an angle and a length",
        "20:20: requests.b.expression: unknown name 'crank_sped' in expression",
    ]


def test_a_mechanism_file_with_an_invalid_item_is_still_checked(tmp_path):
    path = tmp_path / "arm.mech.yaml"
    body = CASE.split("mechanism:\n")[1].split("motions:")[0]
    path.write_text("\n".join(line[2:] for line in body.splitlines()) + "\n", encoding="utf-8")
    with pytest.raises(InputError) as raised:
        load_mechanism(path)
    assert [e.split(": ", 1)[1] for e in _errors(raised.value)] == [
        "bodies.arm.mass: mass must be positive",
        "joints.hinge.bodies[1]: unknown body 'grund'",
        "forces.rub.mu: unknown parameter 'mu_trunion'",
        "forces.coil.stiffness: expected a torsional stiffness, got parameter 'k_arm' = "
        "'20 N/mm' (a stiffness)",
    ]


def test_a_wrong_required_key_still_reports_the_other_file_part(tmp_path):
    path = tmp_path / "analysis.case.yaml"
    path.write_text(
        CASE.replace("type: kinematic", "type: kinematik").replace("mass: -2.0", "mass: 2.0"),
        encoding="utf-8",
    )
    with pytest.raises(InputError) as raised:
        load_case(path)
    keys = [e.split(": ")[1] for e in _errors(raised.value)]
    assert "analysis.type" in keys and "mechanism.joints.hinge.bodies[1]" in keys


def test_loads_validate_prints_every_error_of_the_file_once_with_exit_2(tmp_path):
    from typer.testing import CliRunner

    from cli.app import app

    path = tmp_path / "several.case.yaml"
    path.write_text(CASE, encoding="utf-8")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2, result.output
    errors = [
        line.split("several.case.yaml:")[1]
        for line in result.output.splitlines()
        if ": error: " in line
    ]
    assert errors == [
        "7:11: error: mechanism.bodies.arm.mass: mass must be positive",
        "11:43: error: mechanism.joints.hinge.bodies[1]: unknown body 'grund'",
        "13:47: error: mechanism.forces.rub.mu: unknown parameter 'mu_trunion'",
        "14:48: error: mechanism.forces.coil.stiffness: expected a torsional stiffness, got "
        "parameter 'k_arm' = '20 N/mm' (a stiffness)",
        "19:33: error: requests.a.expression: cannot add an angle and a length",
        "20:20: error: requests.b.expression: unknown name 'crank_sped' in expression",
    ]
    assert "hint: did you mean 'mu_trunnion'?" in result.output
