"""Issue 39 item 5: every physical parameter of an element has its admissible range checked
by `loads validate` (and so `loads run`): exit 2 with the key, its position and the range.
Before, these values gave `ok` results or internal errors (division by zero, LAPACK)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.hardening.conftest import has_line, loads

LIBRARY = Path(__file__).parents[2] / "loadcases" / "library" / "verification"
SERVO = LIBRARY / "elements" / "servo_actuator.case.yaml"
SOCKET = LIBRARY / "ball_in_socket.case.yaml"
CYLINDER = "cylinder: {area_1: 10 cm^2, area_2: 10 cm^2, bulk_modulus: 0.8 GPa}"
VALVE = "valve: {rated_flow: 5 L/min, rated_pressure_drop: 70 bar, rated_current: 10 mA"
SUPPLY = "supply: {pressure: 206.8 bar, return_pressure: 5 bar}"
KEY = "error: mechanism.forces.actuator."


def _write(source: Path, tmp_path: Path, old: str, new: str) -> Path:
    text = source.read_text(encoding="utf-8")
    assert old in text, old
    case = tmp_path / source.name
    case.write_text(text.replace(old, new), encoding="utf-8")
    return case


@pytest.mark.parametrize(
    "old,new,expected",
    [
        (
            CYLINDER,
            CYLINDER.replace("0.8 GPa", "-0.8 GPa"),
            "30:52: " + KEY + "cylinder.bulk_modulus: must be > 0, got '-0.8 GPa'",
        ),
        (
            CYLINDER,
            CYLINDER.replace("}", ", leakage: -1e-12}"),
            "30:75: " + KEY + "cylinder.leakage: must be >= 0, got -1e-12",
        ),
        (
            CYLINDER,
            CYLINDER.replace("area_1: 10", "area_1: 0"),
            "30:18: " + KEY + "cylinder.area_1: must be > 0, got '0 cm^2'",
        ),
        (
            VALVE,
            VALVE.replace("5 L/min", "0 L/min"),
            "32:15: " + KEY + "valve.rated_flow: must be > 0, got '0 L/min'",
        ),
        (
            VALVE,
            VALVE.replace("70 bar", "0 bar"),
            "32:36: " + KEY + "valve.rated_pressure_drop: must be > 0, got '0 bar'",
        ),
        (
            VALVE,
            VALVE.replace("10 mA", "0 mA"),
            "32:65: " + KEY + "valve.rated_current: must be > 0, got '0 mA'",
        ),
        (
            "frequency: 100 Hz",
            "frequency: -100 Hz",
            "32:87: " + KEY + "valve.frequency: must be > 0, got '-100 Hz'",
        ),
        (
            SUPPLY,
            SUPPLY.replace("5 bar", "250 bar"),
            "31:16: " + KEY + "supply.pressure: supply pressure must be > return pressure, "
            "got 2.068e+07 <= 2.5e+07 Pa",
        ),
        (
            "frame_eye: {body: ground, at: [-500, 0, 0]}",
            "frame_eye: {body: ground, at: [0, 0, 0]}",
            "26:7: " + KEY + "points: the attachment points must be distinct, 'rod_eye' and "
            "'frame_eye' coincide at design",
        ),
        (
            "fidelity: valve",
            "fidelity: jet_pipe\n      jet_pipe: {jet_mass: 0}",
            "28:18: " + KEY + "jet_pipe.jet_mass: must be > 0, got 0",
        ),
        (
            "fidelity: valve",
            "fidelity: jet_pipe\n      jet_pipe: {density: -850}",
            "28:18: " + KEY + "jet_pipe.density: must be > 0, got -850",
        ),
    ],
)
@pytest.mark.parametrize("command", ["validate", "run"])
def test_servo_actuator_out_of_range(
    tmp_path: Path, command: str, old: str, new: str, expected: str
) -> None:
    case = _write(SERVO, tmp_path, old, new)
    args = ["-o", tmp_path / "out"] if command == "run" else []
    result = loads(command, case, *args)
    assert result.exit_code == 2, result.output
    assert has_line(result.output, f"{SERVO.name}:{expected}"), result.output


CONTACT = "materials: {E: [210 GPa, 210 GPa], nu: [0.3, 0.3]}"
CONTACT_KEY = "error: mechanism.contacts.rod_end."


@pytest.mark.parametrize(
    "old,new,expected",
    [
        (CONTACT, "stiffness: 0", "23:7: " + CONTACT_KEY + "stiffness: must be > 0, got 0"),
        (
            CONTACT,
            "stiffness: -1e9",
            "23:7: " + CONTACT_KEY + "stiffness: must be > 0, got -1e+09",
        ),
        (
            CONTACT,
            CONTACT.replace("[210 GPa, 210 GPa]", "[210 GPa, -210 GPa]"),
            "23:32: " + CONTACT_KEY + "materials.E[1]: must be > 0, got -2.1e+11 Pa",
        ),
        (
            CONTACT,
            CONTACT.replace("nu: [0.3, 0.3]", "nu: [0.7, 0.3]"),
            "23:47: " + CONTACT_KEY + "materials.nu[0]: must be in (-1, 0.5], got 0.7",
        ),
    ],
)
def test_contact_out_of_range(tmp_path: Path, old: str, new: str, expected: str) -> None:
    case = _write(SOCKET, tmp_path, old, new)
    result = loads("validate", case)
    assert result.exit_code == 2, result.output
    assert has_line(result.output, f"{SOCKET.name}:{expected}"), result.output


ELEMENTS = """\
name: e
bodies:
  arm: {mass: 1.0, cm: [0.1, 0, 0], inertia: [0.001, 0.001, 0.001]}
points:
  tip: {body: arm, at: [0.2, 0, 0]}
  base: {body: ground, at: [0.2, 0.1, 0]}
joints:
  pivot: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
forces:
  spring: {type: spring, points: [tip, base], stiffness: 100, damping: -1}
  hinge: {type: torsion_spring, joint: pivot, stiffness: -5}
  friction: {type: joint_friction, joint: pivot, mu: -0.1, pin_radius: 0}
  brake: {type: damper, joint: pivot, damping: -2}
  mount: {type: bushing, bodies: [arm, ground], at: [0, 0, 0], stiffness: [1, -1, 1]}
"""


def test_element_parameters_out_of_range(tmp_path: Path) -> None:
    mech = tmp_path / "e.mech.yaml"
    mech.write_text(ELEMENTS, encoding="utf-8")
    result = loads("validate", mech)
    assert result.exit_code == 2, result.output
    for expected in (
        "e.mech.yaml:10:63: error: forces.spring.damping: must be >= 0, got -1",
        "e.mech.yaml:11:47: error: forces.hinge.stiffness: must be >= 0, got -5",
        "e.mech.yaml:12:50: error: forces.friction.mu: must be >= 0, got -0.1",
        "e.mech.yaml:12:60: error: forces.friction.pin_radius: must be > 0, got 0",
        "e.mech.yaml:13:39: error: forces.brake.damping: must be >= 0, got -2",
    ):
        assert has_line(result.output, expected), result.output


def test_bushing_stiffness_component_out_of_range(tmp_path: Path) -> None:
    mech = tmp_path / "e.mech.yaml"
    lines = ELEMENTS.splitlines(keepends=True)
    mech.write_text("".join(lines[:9] + lines[13:]), encoding="utf-8")
    result = loads("validate", mech)
    assert result.exit_code == 2, result.output
    assert has_line(
        result.output, "e.mech.yaml:10:79: error: forces.mount.stiffness[1]: must be >= 0, got -1"
    ), result.output
