"""Schema: SI conversion during validation, unions on `type`, messages, JSON Schema."""

from __future__ import annotations

import json
import math

import pytest
from pydantic import ValidationError

from loadcases.schema import CaseModel, MechanismModel, SetModel, json_schema
from loadcases.schema.errors import validation_diagnostics
from loadcases.yamlfiles.source import Locator, parse_yaml

MM = {"units": {"length": "mm", "angle": "deg"}}


def _errors(model: type, text: str, context: dict | None = None) -> list[str]:
    tree = parse_yaml(text, "f.yaml")
    with pytest.raises(ValidationError) as raised:
        model.model_validate(tree.data, context=context or {})
    return [d.format() for d in validation_diagnostics(raised.value, model, Locator(tree))]


def test_mechanism_values_in_si_with_file_units() -> None:
    model = MechanismModel.model_validate(
        {
            "bodies": {"arm": {"mass": "500 g", "cm": [100, 0, "1 m"], "inertia": [1, 2, 2]}},
            "joints": {
                "s": {
                    "type": "screw",
                    "bodies": ["arm", "ground"],
                    "at": "[0, 0, 5] mm",
                    "axis": [0, 0, 1],
                    "pitch": 2,
                },
                "c": {"type": "gear", "joints": ["s", "s2"], "ratio": 2},
            },
            "forces": {
                "t": {"type": "torsion_spring", "joint": "s", "angle0": 90},
                "f": {"type": "force", "point": "p", "value": [0, "100 N", "2*t"]},
            },
        },
        context=MM,
    )
    assert model.bodies["arm"].mass == pytest.approx(0.5)
    assert model.bodies["arm"].cm == pytest.approx((0.1, 0.0, 1.0))
    assert model.joints["s"].at[2] == pytest.approx(0.005)
    assert model.joints["s"].pitch == pytest.approx(0.002)
    assert model.joints["c"].type == "gear"
    assert model.forces["t"].angle0 == pytest.approx(math.pi / 2)
    assert model.forces["f"].value == ("0.0", "100.0", "2*t")


def test_case_requests_discriminated_by_key() -> None:
    case = CaseModel.model_validate(
        {
            "case": "c",
            "mechanism": "m.mech.yaml",
            "analysis": {"type": "dynamic", "end": 1, "step": "1 ms"},
            "requests": {
                "a": {"joint": "j", "quantity": "force"},
                "b": {"motion": "m", "quantity": "torque"},
                "c": {"point": "p", "quantity": "velocity", "frame": "arm"},
                "d": {"force": "wire"},
                "e": {"contact": "stop", "quantity": "penetration"},
                "f": {"expression": "angle(j) * 2"},
            },
        }
    )
    kinds = {name: type(r).__name__ for name, r in case.requests.items()}
    assert kinds == {
        "a": "JointRequest",
        "b": "MotionRequest",
        "c": "PointRequest",
        "d": "ElementRequest",
        "e": "ContactRequest",
        "f": "ExpressionRequest",
    }
    assert case.analysis.step == pytest.approx(0.001)
    assert case.requests["a"].frame == "ground"


def test_set_model() -> None:
    model = SetModel.model_validate(
        {
            "set": "s",
            "cases": "a/*.case.yaml",
            "sweep": {"c": ["0.1 mm", 0.3]},
            "allowables": {"r.value": {"max": "12 kN", "min": "-8 kN"}},
        }
    )
    assert model.cases == ["a/*.case.yaml"]
    assert model.sweep["c"] == pytest.approx([1e-4, 0.3])
    assert model.allowables["r.value"].min == pytest.approx(-8000.0)


def test_messages_name_the_key() -> None:
    text = (
        "bodies:\n  door: {mas: 3, cm: [1, 2], inertia: [1, 1]}\n"
        "joints:\n  h: {type: revolute, bodies: [door, ground], at: [0, 0, 0]}\n"
        "events:\n  e: {when: 't > 1', then: [stip]}\n"
    )
    assert _errors(MechanismModel, text) == [
        "f.yaml:2:3: error: bodies.door.mass: required key is missing",
        "f.yaml:2:18: error: bodies.door.cm: expected 3 values, got 2",
        "f.yaml:2:30: error: bodies.door.inertia: expected 3 values [Ixx, Iyy, Izz] or 6 "
        "[Ixx, Iyy, Izz, Ixy, Ixz, Iyz], got 2",
        "f.yaml:2:10: error: bodies.door.mas: unknown key\nf.yaml:2:10: hint: did you mean 'mass'?",
        "f.yaml:4:3: error: joints.h.axis: required key is missing",
        "f.yaml:6:29: error: events.e.then[0]: unknown action 'stip': use activate, "
        "deactivate, release, lock or stop",
    ]


def test_case_messages() -> None:
    text = (
        "case: c\nmechanism: 5\nanalysis: {type: static}\nrequests:\n"
        "  a: {joint: x, quantity: forc}\n  b: {jont: x}\n"
    )
    assert _errors(CaseModel, text) == [
        "f.yaml:2:1: error: mechanism: expected a mechanism file name (relative to this file) "
        "or the mechanism as a mapping",
        "f.yaml:5:17: error: requests.a.quantity: expected 'force', 'angle', 'omega', "
        "'alpha', 'travel' or 'speed', got 'forc'\nf.yaml:5:17: hint: did you mean 'force'?",
        "f.yaml:6:3: error: requests.b: a request needs one of the keys joint, motion, point, "
        "force, limit, contact, flexible, section or expression, or is `quantity: energy`",
    ]


def test_exclusive_keys() -> None:
    text = "forces:\n  s: {type: spring, points: [a, b], free_length: 1, preload: 2}\n"
    assert _errors(MechanismModel, text) == [
        "f.yaml:2:3: error: forces.s: give 'free_length' or 'preload', not both"
    ]


def test_json_schema_covers_three_kinds() -> None:
    schema = json_schema()
    json.dumps(schema)
    assert {"MechanismModel", "CaseModel", "SetModel"} <= set(schema["$defs"])
    body = schema["$defs"]["Body"]
    assert body["additionalProperties"] is False
    assert "kg" in body["properties"]["mass"]["description"]
    joints = schema["$defs"]["MechanismModel"]["properties"]["joints"]
    assert "discriminator" in json.dumps(joints)


def test_analysis_output_key() -> None:
    """`analysis.output` is `steps` or `dense` (dense output, mechlib.solvers.dense); anything else
    is an error naming the key and its place; `dense` reaches the dynamic analysis."""
    text = "case: c\nmechanism: m.yaml\nanalysis: {type: dynamic, end: 1, step: 0.1, output: %s}\n"
    assert _errors(CaseModel, text % "sparse") == [
        "f.yaml:3:46: error: analysis.output: expected 'steps' or 'dense', got 'sparse'"
    ]
    case = CaseModel.model_validate(parse_yaml(text % "dense", "f.yaml").data, context={})
    assert case.analysis.output == "dense"
