"""Parameters carry the dimension of their unit: checked where they are used (element
values, expressions of parameters in numeric fields, `--set`), unknown names named with a
hint, and expressions' dimensions inferred (sums, functions, powers)."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.expressions.dimensions import DimensionScope, infer_dimension
from loadcases.expressions.errors import ExpressionError
from loadcases.expressions.parser import parse_tree
from loadcases.foundation.diagnostics import InputError
from loadcases.foundation.units import quantity_dimension, unit_dimension
from loadcases.inputs.loader import load_case
from loadcases.inputs.overrides import parse_overrides

CASE = """\
case: dims
mechanism:
  parameters:
    airspeed: {airspeed}
    m: 2 kg
    r: 100 mm
    E: 210 GPa
    A: 10 mm^2
    L: 1 m
    mu_trunnion: 0.1
  bodies:
    arm: {{mass: m, cm: [0.5, 0, 0], inertia: ["0.5*m*r^2", "0.5*m*r^2", "m*r^2"]}}
    slider: {{mass: 1, cm: [0.5, 0, 0], inertia: [1, 1, 1]}}
  points:
    tip: {{body: arm, at: [1.0, 0, 0]}}
    s: {{body: slider, at: [1.0, 0, 0]}}
  joints:
    hinge: {{type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
    guide: {{type: prismatic, bodies: [slider, ground], at: [0, 0, 0], axis: [1, 0, 0]}}
  forces:
    bar: {{type: spring, points: [tip, s], stiffness: {stiffness}, free_length: 0.5}}
    rub: {{type: joint_friction, joint: hinge, mu: {mu}, pin_radius: 10 mm}}
    push: {{type: force, point: s, value: [{push}, 0, 0]}}
  contacts:
    stop:
      type: impact
      bodies: [slider, ground]
      geometry: {{shape: sphere_plane, center: [0.5, 0.01, 0], radius: 0.01,
                 plane_point: [0.5, 0, 0], normal: [0, 1, 0]}}
      stiffness: 1.0e7
      exponent: 1.5
      damping: 1000
      depth: 1.0e-4
      friction: {{mu_static: 0.3, mu_dynamic: 0.25, v_static: airspeed, v_dynamic: 1000}}
motions:
  lift: {{joint: hinge, value: "step(t, 0, 0, 1, 80*deg)"}}
analysis: {{type: kinematic, end: 1, step: 0.01}}
requests:
  a: {{joint: hinge, quantity: angle}}
"""
GOOD = {
    "airspeed": "250 knot",
    "stiffness": '"E*A/L"',
    "mu": "mu_trunnion",
    "push": "0",
}


def _write(tmp_path: Path, **changes: str) -> Path:
    path = tmp_path / "dims.case.yaml"
    path.write_text(CASE.format(**{**GOOD, **changes}), encoding="utf-8")
    return path


def _errors(path: Path, **kwargs) -> list[str]:
    with pytest.raises(InputError) as raised:
        load_case(path, **kwargs)
    return [
        f"{d.line}:{d.column}: {d.key}: {d.message}" + (f" | {d.hint}" if d.hint else "")
        for d in raised.value.diagnostics
        if d.severity == "error"
    ]


def test_expressions_of_parameters_in_numeric_fields_are_their_si_values(tmp_path):
    case = load_case(_write(tmp_path))
    arm = case.mechanism.bodies["arm"]
    # 0.5 m r^2 = 0.5 * 2 kg * (0.1 m)^2 = 0.01 kg m^2; m r^2 = 0.02
    assert arm.inertia == pytest.approx((0.01, 0.01, 0.02), rel=1e-12)
    # E A / L = 210e9 Pa * 10e-6 m^2 / 1 m = 2.1e6 N/m
    assert case.mechanism.forces["bar"].stiffness == pytest.approx(2.1e6, rel=1e-12)
    assert case.mechanism.contacts["stop"].friction.v_static == pytest.approx(250 * 1852 / 3600)


def test_a_parameter_of_another_dimension_is_an_error_at_the_key_naming_both(tmp_path):
    errors = _errors(_write(tmp_path, airspeed="250 kg"))
    assert errors == [
        "34:52: mechanism.contacts.stop.friction.v_static: expected a velocity, got "
        "parameter 'airspeed' = '250 kg' (a mass)"
    ]


def test_an_expression_of_parameters_of_another_dimension_is_an_error(tmp_path):
    errors = _errors(_write(tmp_path, stiffness='"E*A"'))
    assert errors == [
        "21:43: mechanism.forces.bar.stiffness: expected a stiffness, got 'E*A' (a force)"
    ]


def test_a_parameter_in_a_force_component_is_checked_as_a_force(tmp_path):
    errors = _errors(_write(tmp_path, push="m"))
    assert errors == [
        "23:43: mechanism.forces.push.value[0]: expected a force, got parameter 'm' = "
        "'2 kg' (a mass)"
    ]


def test_a_misspelt_parameter_is_named_with_the_closest_one(tmp_path):
    errors = _errors(_write(tmp_path, mu="mu_trunion", stiffness='"E*A/Lx"'))
    assert errors == [
        "21:43: mechanism.forces.bar.stiffness: unknown parameter 'Lx' | did you mean 'L'?",
        "22:47: mechanism.forces.rub.mu: unknown parameter 'mu_trunion' | "
        "did you mean 'mu_trunnion'?",
    ]


def test_set_values_carry_their_dimension_to_the_fields(tmp_path):
    path = _write(tmp_path, airspeed="100")  # bare: SI of an unknown dimension
    assert load_case(path).mechanism.contacts["stop"].friction.v_static == 100.0
    errors = _errors(path, what_if=parse_overrides(["airspeed=250 kg"]))
    assert errors == [
        "34:52: mechanism.contacts.stop.friction.v_static: expected a velocity, got "
        "'--set airspeed=250 kg' (a mass)"
    ]
    fine = load_case(path, what_if=parse_overrides(["airspeed=250 knot"]))
    assert fine.mechanism.contacts["stop"].friction.v_static == pytest.approx(128.611, 1e-5)


_PARAMETERS = {
    "rho": quantity_dimension("1.225 kg/m^3"),
    "v": quantity_dimension("250 knot"),
    "cda": quantity_dimension("0.45 m^2"),
    "n": None,
}


def _infer(text: str, coefficients: bool = False):
    def names(name: str):
        return _PARAMETERS[name] if name in _PARAMETERS else unit_dimension(name)

    return infer_dimension(parse_tree(text), DimensionScope(names, {}, coefficients))


@pytest.mark.parametrize(
    ("text", "dims"),
    [
        ("rho*v^2*cda", (("[length]", 1.0), ("[mass]", 1.0), ("[time]", -2.0))),
        ("0.5*rho*v^2*cda", None),  # a number may carry a unit
        ("sqrt(x(a)^2 + y(a)^2)", (("[length]", 1.0),)),
        ("angle(j) / deg", ()),
        ("omega(j)", (("[angle]", 1.0), ("[time]", -1.0))),
        ("atan2(y(a), x(a))", (("[angle]", 1.0),)),
        ("sin(2*pi*t) + cos(angle(j))", ()),
        ("sin(pi * t)", ()),  # pi, as any number, may carry a unit (here 1/s)
        ("x(a) + 0.1", (("[length]", 1.0),)),
        ("55*deg * t", None),
    ],
)
def test_inferred_dimensions(text, dims):
    assert _infer(text) == dims


def test_numbers_are_coefficients_in_numeric_fields():
    assert _infer("0.5*rho*v^2*cda", coefficients=True) == (
        ("[length]", 1.0),
        ("[mass]", 1.0),
        ("[time]", -2.0),
    )


@pytest.mark.parametrize(
    ("text", "message", "offset"),
    [
        ("x(a) + t", "cannot add a length and a time", 5),
        ("angle(j) >= x(a)", "cannot compare an angle with a length", 9),
        ("sin(t)", "the argument of 'sin' must be a plain number or an angle, not a time", 0),
        ("exp(v)", "the argument of 'exp' must be a plain number or an angle, not a velocity", 0),
        ("x(a)^n", "a power of a length needs a number as exponent", 4),
        ("max(x(a), t)", "'max' needs arguments of one dimension, not a length and a time", 0),
        ("2^x(a)", "an exponent must be a plain number or an angle, not a length", 1),
    ],
)
def test_mismatched_dimensions_are_errors_at_the_operator(text, message, offset):
    with pytest.raises(ExpressionError) as raised:
        _infer(text)
    assert (raised.value.message, raised.value.offset) == (message, offset)


EXPRESSIONS = """\
case: expression-dims
mechanism:
  parameters:
    k_t: 50 N*m/rad
    span: 2 m
  bodies:
    arm: {mass: 2.0, cm: [0.5, 0, 0], inertia: [0.001, 0.17, 0.17]}
  points:
    tip: {body: arm, at: [1.0, 0, 0]}
  joints:
    hinge: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
  tables:
    gust: {x: "[0, 1, 2] s", y: "[0, 5, 3] N", extrapolate: hold}
  forces:
    wind: {type: force, point: tip, value: [0, "table(gust, angle(hinge))", 0]}
    lever: {type: torque, body: arm, value: [0, 0, "-k_t * span"]}
motions:
  lift: {joint: hinge, value: "span * t"}
analysis: {type: kinematic, end: 1, step: 0.01}
requests:
  fine: {expression: "k_t * angle(hinge) + table(gust, t) * span"}
  sum: {expression: "angle(hinge) + x(tip)"}
  trig: {expression: "sin(t)"}
"""


def test_expressions_with_known_dimensions_that_disagree_are_errors_at_the_key(tmp_path):
    path = tmp_path / "expr.case.yaml"
    path.write_text(EXPRESSIONS, encoding="utf-8")
    assert _errors(path) == [
        "15:49: mechanism.forces.wind.value[1]: table 'gust' has x in a time, read at an angle",
        "16:52: mechanism.forces.lever.value[2]: expected a torque, got units of kg*m^3/(s^2*rad)",
        "22:35: requests.sum.expression: cannot add an angle and a length",
        "23:23: requests.trig.expression: the argument of 'sin' must be a plain number or an "
        "angle, not a time",
    ]


def test_a_motion_of_another_known_dimension_warns_and_one_with_units_does_not(tmp_path):
    path = tmp_path / "motion.case.yaml"
    text = (
        EXPRESSIONS.split("requests:")[0]
        .replace('"table(gust, angle(hinge))"', '"table(gust, t)"')
        .replace('"-k_t * span"', '"-k_t * angle(hinge)"')
    )
    path.write_text(text + "requests:\n  a: {joint: hinge, quantity: angle}\n", encoding="utf-8")
    warnings = [
        (d.line, d.column, d.key, d.message)
        for d in load_case(path).warnings
        if "expected" in d.message
    ]
    assert warnings == [(18, 24, "motions.lift.value", "expected an angle, got units of m*s")]
    path.write_text(
        text.replace('"span * t"', '"rate * t"').replace(
            "span: 2 m", "span: 2 m\n    rate: 2 deg/s"
        )
        + "requests:\n  a: {joint: hinge, quantity: angle}\n",
        encoding="utf-8",
    )
    assert not [d for d in load_case(path).warnings if "expected" in d.message]


def test_a_swept_value_of_another_dimension_is_an_error_at_its_item(tmp_path):
    from loadcases.inputs.loader import validate_files

    case = tmp_path / "dims.case.yaml"
    case.write_text(CASE.format(**GOOD), encoding="utf-8")
    good_set = tmp_path / "good.set.yaml"
    good_set.write_text(
        "set: s\ncases: [dims.case.yaml]\nsweep: {airspeed: [100 knot, 50 m/s]}\n",
        encoding="utf-8",
    )
    assert not [d for d in validate_files([good_set]) if d.severity == "error"]
    bad_set = tmp_path / "bad.set.yaml"
    bad_set.write_text(
        "set: s\ncases: [dims.case.yaml]\nsweep: {airspeed: [100 knot, 250 kg]}\n",
        encoding="utf-8",
    )
    errors = [
        (d.line, d.column, d.key, d.message)
        for d in validate_files([bad_set])
        if d.severity == "error"
    ]
    assert errors == [
        (
            3,
            30,
            "sweep.airspeed[1]",
            "expected a velocity (parameter 'airspeed' of case 'dims'), got '250 kg' (a mass)",
        )
    ]


UNITS = """\
case: units
mechanism:
  parameters:
    k_t: 50 N*m/rad
    lever: 0.2 m
  bodies:
    arm: {mass: 2.0, cm: [0.5, 0, 0], inertia: [0.001, 0.17, 0.17]}
  points:
    tip: {body: arm, at: [1.0, 0, 0]}
  joints:
    hinge: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
motions:
  lift: {joint: hinge, value: "step(t, 0, 0, 1, 80*deg)"}
analysis: {type: kinematic, end: 1, step: 0.1}
requests:
  spring_torque: {expression: "k_t * angle(hinge)"}
  handle: {expression: "effort(lift) / lever", unit: HANDLE}
  handle_inferred: {expression: "effort(lift) / lever"}
  height: {expression: "y(tip)"}
  in_degrees: {expression: "angle(hinge) / deg"}
  scaled: {expression: "2 * angle(hinge)"}
"""


def test_expression_columns_get_the_unit_given_or_inferred(tmp_path):
    from loadcases.build.model import build_run

    path = tmp_path / "units.case.yaml"
    # a parameter named like the unit (`N`) does not take its place
    text = UNITS.replace("HANDLE", "N").replace("lever: 0.2 m", "lever: 0.2 m\n    N: 3")
    path.write_text(text, encoding="utf-8")
    units = build_run(load_case(path)).column_units
    assert {k: v for k, v in units.items() if k.endswith(".value")} == {
        "spring_torque.value": "N*m",  # N*m/rad * rad
        "handle.value": "N",  # the dimension `N` names, in SI (the column stays SI)
        "handle_inferred.value": "N",  # effort of a revolute motion (N*m) over a length
        "height.value": "m",
        "in_degrees.value": "1",  # a plain number
        "scaled.value": "",  # a number may carry a unit: not known
    }


def test_a_unit_of_another_dimension_than_the_expression_is_an_error(tmp_path):
    path = tmp_path / "units.case.yaml"
    path.write_text(UNITS.replace("HANDLE", "kN").replace("effort(lift) / lever", "x(tip)"))
    assert _errors(path) == [
        "17:34: requests.handle.unit: the expression gives a length; unit 'kN' is a force"
    ]
    path.write_text(UNITS.replace("HANDLE", "kNx"), encoding="utf-8")
    assert _errors(path) == ["17:48: requests.handle.unit: unknown unit 'kNx'"]


PENDULUM = (
    Path(__file__).parents[2]
    / "loadcases"
    / "library"
    / "examples"
    / "flexible"
    / "flexible_pendulum.case.yaml"
)


def _density_warnings(tmp_path: Path, density: str) -> list[tuple]:
    path = tmp_path / "pendulum.case.yaml"
    text = PENDULUM.read_text(encoding="utf-8")
    assert "rho: 2700 kg/m^3" in text
    path.write_text(text.replace("rho: 2700 kg/m^3", f"rho: {density}"), encoding="utf-8")
    return [
        (d.line, d.column, d.key, d.message, d.hint)
        for d in load_case(path).warnings
        if "density" in d.message
    ]


def test_an_implausible_density_warns_with_the_unit_slip_and_a_steel_one_does_not(tmp_path):
    assert _density_warnings(tmp_path, "2700 kg/m^3") == []
    assert _density_warnings(tmp_path, "7.85e-9 t/mm^3") == []  # N-mm-t units: 7850 kg/m^3
    assert _density_warnings(tmp_path, "7850 kg/mm^3") == [
        (
            19,
            43,
            "mechanism.bodies.strip.flexible.beam.material.rho",
            "implausible density 7.85e+12 kg/m^3 (solids and liquids: 10 to 30,000 kg/m^3)",
            "written in kg/mm^3 where kg/m^3 was meant? 7850 kg/m^3 is 7.85e+12 kg/m^3 read "
            "as kg/mm^3 (steel: 7850 kg/m^3 = 7.85e-9 t/mm^3)",
        )
    ]


def test_table_items_of_different_dimensions_are_an_error_at_the_item(tmp_path):
    path = tmp_path / "expr.case.yaml"
    fine = EXPRESSIONS.replace('"table(gust, angle(hinge))"', '"table(gust, t)"').replace(
        '"-k_t * span"', '"0"'
    )
    mixed = fine.replace('x: "[0, 1, 2] s"', 'x: ["0 s", span, "3 s"]')
    path.write_text(mixed.split("requests:")[0] + "requests: {}\n", encoding="utf-8")
    assert _errors(path) == [
        "13:23: mechanism.tables.gust.x[1]: expected a time like item 1, got a length"
    ]
    path.write_text(
        mixed.replace("span: 2 m", "span: 2 s").split("requests:")[0] + "requests: {}\n",
        encoding="utf-8",
    )
    assert load_case(path).mechanism.tables["gust"].x == (0.0, 2.0, 3.0)


DRAG = """\
case: drag
mechanism:
  parameters:
    airspeed: AIRSPEED
    rho: 1.225 kg/m^3
    cda: 0.45 m^2
    m_payload: 50 kg
  bodies:
    leg: {mass: 180, cm: [0, 0, -1.3], inertia: [60, 62, 4]}
  points:
    axle: {body: leg, at: [0, 0, -1.8]}
  joints:
    trunnion: {type: revolute, bodies: [leg, ground], at: [0, 0, 0], axis: [0, -1, 0]}
  forces:
    drag: {type: force, point: axle, value: ["-0.5*rho*airspeed^2*cda*cos(angle(trunnion))", 0, 0]}
    payload: {type: force, point: axle, value: [0, 0, "-m_payload * 9.81*m/s^2"]}
    spin: {type: torque, body: leg, value: [0, "exp(-t/2)", "cos(angle(trunnion))"]}
motions:
  retract: {joint: trunnion, value: "step(t, 0, 0, 1, 90*deg)"}
analysis: {type: kinematic, end: 1, step: 0.1}
requests:
  a: {joint: trunnion, quantity: angle}
"""


def test_a_formula_with_a_wrong_parameter_unit_is_an_error_at_the_parameter(tmp_path):
    """The gear of issue 36: `airspeed: 250 kg` in a drag formula. Read with its number 0.5
    plain, the formula gives kg^3/m where a force is expected; the missing factor
    (m^2/(kg^2*s^2)) is no dimension a number written without its unit carries, and only
    `airspeed` as a velocity (sqrt(N/(kg/m^3 * m^2)) = m/s) makes it a force: exit 2 at
    `airspeed`'s key (line 4 of the case). Silent with the airspeed in knots."""
    path = tmp_path / "drag.case.yaml"
    path.write_text(DRAG.replace("AIRSPEED", "250 knot"), encoding="utf-8")
    assert [d for d in load_case(path).warnings if "plain coefficients" in d.message] == []
    path.write_text(DRAG.replace("AIRSPEED", "250 kg"), encoding="utf-8")
    assert _errors(path) == [
        "4:5: mechanism.parameters.airspeed: 'airspeed' is a mass, but "
        "mechanism.forces.drag.value[0] needs a velocity (m/s): with its numbers as plain "
        "coefficients this gives units of kg^3/m, where a force is expected | write "
        "'airspeed' in a unit of a velocity"
    ]


def test_a_formula_two_parameters_could_explain_is_an_error_at_the_formula(tmp_path):
    """`rho: 1.225 kg/m^2`: the drag reads as a torque; rho as a density or cda as a length
    would each make it a force, so the error stays at the formula (line 15, column 46)."""
    path = tmp_path / "drag.case.yaml"
    text = DRAG.replace("AIRSPEED", "250 knot").replace("1.225 kg/m^3", "1.225 kg/m^2")
    path.write_text(text, encoding="utf-8")
    assert _errors(path) == [
        "15:46: mechanism.forces.drag.value[0]: with its numbers as plain coefficients this "
        "gives a torque, where a force is expected | a parameter has the wrong unit, or a "
        "number carries one: write it with its unit (9.81*m/s^2) to have the formula checked"
    ]


def test_a_number_that_may_carry_a_named_unit_only_warns(tmp_path):
    """`m_payload * 9.81` in a force: 9.81 may be m/s^2 (the missing factor is an
    acceleration, a named dimension): a warning, not an error; a plain number (`exp(-t/2)`)
    is SI of a torque: silent."""
    path = tmp_path / "drag.case.yaml"
    text = DRAG.replace("AIRSPEED", "250 knot").replace("9.81*m/s^2", "9.81")
    path.write_text(text, encoding="utf-8")
    assert [
        (d.line, d.column, d.key, d.severity, d.message)
        for d in load_case(path).warnings
        if "plain coefficients" in d.message
    ] == [
        (
            16,
            55,
            "mechanism.forces.payload.value[2]",
            "warning",
            "with its numbers as plain coefficients this gives a mass, where a force is expected",
        )
    ]


def test_a_case_parameter_of_another_dimension_than_the_mechanisms_is_an_error(tmp_path):
    mechanism = tmp_path / "dims.mech.yaml"
    body = CASE.format(**GOOD).split("mechanism:\n")[1].split("motions:")[0]
    mechanism.write_text("\n".join(line[2:] for line in body.splitlines()) + "\n", "utf-8")
    rest = "motions:" + CASE.format(**GOOD).split("motions:")[1]
    path = tmp_path / "dims.case.yaml"
    path.write_text(
        "case: dims\nmechanism: dims.mech.yaml\nparameters: {airspeed: 250 kg}\n" + rest, "utf-8"
    )
    errors = _errors(path)
    assert errors[0] == (
        "3:14: parameters.airspeed: the mechanism's parameter of another dimension: "
        "expected a velocity like '250 knot', got a mass"
    )
    path.write_text(
        "case: dims\nmechanism: dims.mech.yaml\nparameters: {airspeed: 100 m/s}\n" + rest, "utf-8"
    )
    assert load_case(path).mechanism.contacts["stop"].friction.v_static == 100.0


def test_an_expression_of_parameters_that_cannot_be_computed_says_why(tmp_path):
    path = _write(tmp_path)
    path.write_text(path.read_text(encoding="utf-8").replace("L: 1 m", "L: 0 m"), "utf-8")
    assert _errors(path) == [
        "21:43: mechanism.forces.bar.stiffness: invalid expression 'E*A/L': division by zero"
    ]


def test_a_density_parameter_in_kg_per_mm3_warns_and_the_air_does_not(tmp_path):
    """The gear's air density written 1.225 kg/mm^3 (1.225e9 kg/m^3) validated silently and
    ended the retraction in a singular matrix: a warning at the parameter naming the slip;
    the air at sea level (1.225 kg/m^3) and at 30 km (0.018 kg/m^3) are silent."""
    path = tmp_path / "drag.case.yaml"

    def density_warnings(rho: str) -> list[tuple]:
        text = DRAG.replace("AIRSPEED", "250 knot").replace("1.225 kg/m^3", rho)
        path.write_text(text, encoding="utf-8")
        found = load_case(path).warnings
        return [(d.line, d.key, d.message) for d in found if "density" in d.message]

    assert density_warnings("1.225 kg/m^3") == []
    assert density_warnings("0.018 kg/m^3") == []
    assert density_warnings("1.225 kg/mm^3") == [
        (
            5,
            "mechanism.parameters.rho",
            "implausible density 1.225e+09 kg/m^3 (gases, liquids and solids: 0.001 to 30,000 "
            "kg/m^3)",
        )
    ]


def test_a_case_override_of_another_dimension_is_one_error_at_the_override(tmp_path):
    """`--set airspeed=250kg` on a mechanism that says 250 knot: one error, at the override;
    the drag formula's check does not blame the mechanism's parameter as well."""
    path = tmp_path / "drag.case.yaml"
    path.write_text(DRAG.replace("AIRSPEED", "250 knot"), encoding="utf-8")
    errors = _errors(path, what_if=parse_overrides(["airspeed=250kg"]))
    assert len(errors) == 1, errors
    assert "--set airspeed=250kg: expected a velocity" in errors[0]
