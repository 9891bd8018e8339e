"""Tests of the expression language: values, derivatives, measures, tables and errors."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from loadcases.expressions import CompiledExpression, Expression, ExpressionError, parse

DEG = math.pi / 180.0
UNITS = {"deg": DEG, "mm": 1.0e-3, "kN": 1.0e3, "rad": 1.0, "s": 1.0}


def units(name: str) -> float | None:
    """A stand-in for loadcases.foundation.units.unit_constant."""
    return UNITS.get(name)


def compile_text(text: str, parameters=None, tables=None) -> CompiledExpression:
    return parse(text).compile(parameters or {}, tables or {}, unit_lookup=units)


def value(text: str, t: float = 0.0, state=None, **parameters: float) -> float:
    return compile_text(text, parameters)(t, state)


def cubic_step(x, x0, h0, x1, h1):
    """Reference: the Adams cubic step, written out."""
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    s = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * s**2 * (3 - 2 * s)


class FakeState:
    """The state-measure protocol of mechlib.StateView, with fixed numbers."""

    def angle(self, joint: str) -> float:
        return {"hinge": 0.5, "hl2": 1.7}[joint]

    def omega(self, joint: str) -> float:
        return {"hinge": -2.0}[joint]

    def travel(self, joint: str) -> float:
        return {"guide": 0.125}[joint]

    def speed(self, joint: str) -> float:
        return {"guide": 3.0}[joint]

    def dist(self, a: str, b: str) -> float:
        return {("eye", "frame"): 0.85}[(a, b)]

    def x(self, point: str) -> float:
        return {"p": 3.0}[point]

    def y(self, point: str) -> float:
        return {"p": 4.0}[point]

    def z(self, point: str) -> float:
        return {"p": -1.0}[point]


# ----------------------------------------------------------------------------- values
@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1 + 2 * 3", 7.0),
        ("(1 + 2) * 3", 9.0),
        ("10 - 4 - 3", 3.0),
        ("2 / 4 / 2", 0.25),
        ("2 ** 3", 8.0),
        ("2 ^ 3", 8.0),
        ("2 ** 3 ** 2", 512.0),
        ("-2 ** 2", -4.0),
        ("2 ** -1", 0.5),
        ("-3 * -2", 6.0),
        ("+4 - -1", 5.0),
        ("1.5e3 + .5 + 2.", 1502.5),
        ("1E-3", 1.0e-3),
        ("pi", math.pi),
        ("90 * deg", math.pi / 2),
        ("5*mm + 2*kN/1000", 2.005),
        ("sin(pi/6)", 0.5),
        ("cos(pi/3)", 0.5),
        ("tan(pi/4)", 1.0),
        ("asin(1)", math.pi / 2),
        ("acos(-1)", math.pi),
        ("atan(1)", math.pi / 4),
        ("atan2(1, -1)", 3 * math.pi / 4),
        ("sqrt(2)", math.sqrt(2)),
        ("abs(-3.5)", 3.5),
        ("min(3, -1, 2)", -1.0),
        ("max(3, -1, 2, 7)", 7.0),
        ("sign(-0.1) + 10*sign(0) + 100*sign(4)", 99.0),
        ("exp(1)", math.e),
        ("log(exp(2.5))", 2.5),
        ("1 < 2", 1.0),
        ("2 < 1", 0.0),
        ("2 <= 2", 1.0),
        ("3 > 4", 0.0),
        ("4 >= 4", 1.0),
        ("1 == 1", 1.0),
        ("1 != 1", 0.0),
        ("1 and 0", 0.0),
        ("1 and 2", 1.0),
        ("0 or 0", 0.0),
        ("0 or -3", 1.0),
        ("not 0", 1.0),
        ("not 5", 0.0),
        ("not 1 < 0", 1.0),
        ("1 < 2 and 3 < 4", 1.0),
        ("1 + 1 == 2 or 0", 1.0),
        ("(1 < 2) < 3", 1.0),
        ("2 * (3 > 1)", 2.0),
    ],
)
def test_constant_values(text, expected):
    compiled = compile_text(text)
    assert compiled.is_constant
    assert compiled.value == pytest.approx(expected, rel=1e-14, abs=1e-15)
    assert compiled(123.0) == pytest.approx(expected, rel=1e-14, abs=1e-15)


@pytest.mark.parametrize("t", [-0.3, 0.0, 0.25, 1.0, 2.7])
@pytest.mark.parametrize(
    ("text", "reference"),
    [
        ("crank_speed * t", lambda t: 6.0 * t),
        ("sin(2*pi*t)", lambda t: math.sin(2 * math.pi * t)),
        ("amp * cos(3*t + 0.5) ^ 2", lambda t: 0.2 * math.cos(3 * t + 0.5) ** 2),
        ("exp(-t) * t**3 - 4/(1 + t*t)", lambda t: math.exp(-t) * t**3 - 4 / (1 + t * t)),
        (
            "atan2(t, 2) + atan(t) - asin(t/3) + acos(t/4)",
            lambda t: math.atan2(t, 2) + math.atan(t) - math.asin(t / 3) + math.acos(t / 4),
        ),
        (
            "sqrt(1 + t^2) + log(2 + t) + tan(t/3)",
            lambda t: math.sqrt(1 + t**2) + math.log(2 + t) + math.tan(t / 3),
        ),
        (
            "abs(t - 1) + sign(t - 0.25) + min(t, 1 - t) + max(t, 0.5, t*t)",
            lambda t: abs(t - 1) + np.sign(t - 0.25) + min(t, 1 - t) + max(t, 0.5, t * t),
        ),
        ("(t > 0.5) * 10 + (t <= 0) * 100", lambda t: 10.0 * (t > 0.5) + 100.0 * (t <= 0)),
        ("step(t, 0, 0, 2, 90*deg)", lambda t: cubic_step(t, 0, 0, 2, math.pi / 2)),
        ("step(sin(t), -0.5, 3, 0.5, -1)", lambda t: cubic_step(math.sin(t), -0.5, 3, 0.5, -1)),
        ("step(t, t - 1, 0, 2, 1)", lambda t: cubic_step(t, t - 1, 0, 2, 1)),
    ],
)
def test_time_values(text, reference, t):
    compiled = compile_text(text, {"crank_speed": 6.0, "amp": 0.2})
    assert compiled.time_only and not compiled.is_constant and compiled.value is None
    assert compiled(t) == pytest.approx(reference(t), rel=1e-13, abs=1e-14)
    array = compiled.evaluate_array(np.array([t, t]))
    assert array.shape == (2,)
    assert array == pytest.approx([reference(t)] * 2, rel=1e-13, abs=1e-14)


@pytest.mark.parametrize(
    ("x", "expected"),
    [
        (-1.0, 2.0),
        (0.5, 2.0),
        (1.0, 2.0),
        (1.5, 2.0 + 3.0 * 0.5),
        (1.25, None),
        (2.0, 5.0),
        (9.0, 5.0),
    ],
)
def test_step_values(x, expected):
    compiled = compile_text("step(t, 0.5 + 0.5, 2, 2, 5)")
    s = (x - 1.0) / 1.0
    reference = 2.0 + 3.0 * s * s * (3 - 2 * s) if expected is None else expected
    assert compiled(x) == pytest.approx(reference, rel=1e-15)


def test_names_resolve_in_order_parameters_pi_units_and_t_is_time():
    # A parameter wins over pi and over a unit name; `t` is always the time.
    assert value("pi + mm", pi=1.0, mm=2.0) == 3.0
    assert compile_text("t", {"t": 99.0})(4.0) == 4.0
    assert compile_text("2 * deg").value == pytest.approx(2 * DEG)


def test_parameters_are_folded_into_constants():
    compiled = compile_text(
        "step(t, 0, 0, t_end, angle_max) + 2*k*mm", {"t_end": 2.0, "angle_max": 1.5, "k": 3.0}
    )
    assert compiled(1.0) == pytest.approx(0.75 + 6.0e-3)
    assert compile_text("2 * k * sin(pi/2)", {"k": 4}).value == 8.0


# ------------------------------------------------------------------------ derivatives
TIME_FUNCTIONS = [
    "crank_speed * t",
    "sin(2*pi*t)",
    "3*t^4 - 2*t^2 + t - 7",
    "exp(-0.3*t) * cos(5*t)",
    "tan(t/2) + atan(t) + atan2(t, 2 + t*t)",
    "asin(t/4) - acos(t/5) + sqrt(1 + t*t) + log(3 + t)",
    "2 ** t + t ** t + (1 + t) ** 1.5",
    "(t*t + 1) / (t + 3)",
    "abs(t - 0.9) + sign(t) + min(t, 1.2 - t, 0.1) + max(t*t, 0.3)",
    "step(t, 0, 0, 2, 90*deg)",
    "step(t, 0.5, -1, 1.5, 3) * sin(t)",
    "step(sin(t), -0.5, t, 0.5, t*t)",
    "step(t*t, t - 2, 0, 2, 1)",
    "-(t > 1) + 3*(t <= 0.4 or t > 2) + not t",
]


@pytest.mark.parametrize("text", TIME_FUNCTIONS)
@pytest.mark.parametrize("t", [0.15, 0.7, 1.3, 1.85, 2.6])
def test_derivatives_match_finite_differences(text, t):
    compiled = compile_text(text, {"crank_speed": 6.0})
    first, second = compiled.derivative(), compiled.derivative().derivative()
    h = 1.0e-5  # central differences: truncation ~h^2, round-off ~1e-16/h (1e-11)
    fd_first = (compiled(t + h) - compiled(t - h)) / (2 * h)
    fd_second = (first(t + h) - first(t - h)) / (2 * h)
    assert first(t) == pytest.approx(fd_first, rel=1e-6, abs=1e-6)
    assert second(t) == pytest.approx(fd_second, rel=1e-6, abs=1e-6)


def test_second_derivatives_analytic():
    speed = compile_text("crank_speed * t", {"crank_speed": 6.0})
    assert speed.derivative().is_constant and speed.derivative().value == 6.0
    assert speed.derivative().derivative().value == 0.0
    wave = compile_text("sin(2*pi*t)")
    for t in (0.0, 0.1, 0.37):
        w = 2 * math.pi
        assert wave.derivative()(t) == pytest.approx(w * math.cos(w * t), rel=1e-14)
        assert wave.derivative().derivative()(t) == pytest.approx(
            -w * w * math.sin(w * t), rel=1e-13, abs=1e-12
        )
    cubic = compile_text("t^3")
    assert cubic.derivative().derivative().derivative().value == 6.0


def test_step_derivatives_are_the_adams_ones():
    # d/dx = (h1-h0) 6 s (1-s) / (x1-x0); d2/dx2 = (h1-h0)(6-12 s)/(x1-x0)^2 inside.
    compiled = compile_text("step(t, 1, 2, 3, 10)")
    d1, d2 = compiled.derivative(), compiled.derivative().derivative()
    for t in (1.2, 2.0, 2.9):
        s = (t - 1) / 2
        assert d1(t) == pytest.approx(8 * 6 * s * (1 - s) / 2, rel=1e-14)
        assert d2(t) == pytest.approx(8 * (6 - 12 * s) / 4, rel=1e-14)
    for t in (0.0, 1.0, 3.0, 4.0):
        assert d1(t) == 0.0 and d2(t) == 0.0
    assert d2.derivative()(2.0) == pytest.approx(8 * -12 / 8)
    assert d2.derivative().derivative().value == 0.0


def test_piecewise_derivatives():
    assert compile_text("abs(t)").derivative()(-2.0) == -1.0
    assert compile_text("abs(t)").derivative()(2.0) == 1.0
    assert compile_text("sign(t) + (t > 1)").derivative().value == 0.0
    maximum = compile_text("max(2*t, 1, -t)").derivative()
    assert [maximum(t) for t in (-3.0, 0.1, 2.0)] == [-1.0, 0.0, 2.0]
    minimum = compile_text("min(t*t, 1)").derivative().derivative()
    assert [minimum(t) for t in (0.5, 2.0)] == [2.0, 0.0]


def test_derivative_is_cached_and_keeps_text():
    compiled = compile_text("t*t")
    assert compiled.derivative() is compiled.derivative()
    assert compiled.derivative().text == "t*t" and compiled.derivative().order == 1


def test_evaluate_array_of_derivatives_and_constants():
    compiled = compile_text("step(t, 0, 0, 2, 90*deg)")
    times = np.linspace(-1.0, 3.0, 41)
    expected = [compiled.derivative()(t) for t in times]
    assert compiled.derivative().evaluate_array(times) == pytest.approx(expected, rel=1e-14)
    constant = compile_text("2*kN").evaluate_array(times)
    assert constant.shape == (41,) and np.all(constant == 2000.0)
    minimum = compile_text("min(t, 1 - t)").derivative().evaluate_array(np.array([0.2, 0.8]))
    assert minimum.tolist() == [1.0, -1.0]
    assert np.isnan(compile_text("sqrt(t)").evaluate_array(np.array([-1.0]))[0])


# ------------------------------------------------------------------- measures, tables
def test_state_measures_via_state_object():
    state = FakeState()
    text = "angle(hinge) + 10*omega(hinge) + travel(guide) * speed(guide) + dist(eye, frame)"
    compiled = compile_text(text)
    assert not compiled.time_only
    assert compiled(0.0, state) == pytest.approx(0.5 - 20.0 + 0.375 + 0.85)
    assert compile_text("sqrt(x(p)^2 + y(p)^2) + z(p)")(0.0, state) == 4.0
    event = compile_text("angle(hl2) >= 90*deg")
    assert event(0.0, state) == 1.0


def test_state_measure_without_state():
    with pytest.raises(ExpressionError) as info:
        compile_text("t + angle(hinge)")(1.0)
    assert (info.value.message, info.value.offset) == ("angle(hinge) needs the mechanism state", 4)


def test_measures_are_not_differentiated():
    compiled = compile_text("2*t + dist(a, b)")
    for action in (compiled.derivative, lambda: compiled.evaluate_array(np.zeros(2))):
        with pytest.raises(ExpressionError) as info:
            action()
        assert info.value.offset == 6
        assert "not one using dist(a, b)" in info.value.message


def test_tables():
    wind = lambda x: 120.0 * x  # noqa: E731  (a table given as a plain callable)
    compiled = compile_text("table(wind_moment, angle(hinge)) + 1", tables={"wind_moment": wind})
    assert compiled(0.0, FakeState()) == pytest.approx(61.0)
    profile = compile_text("table(profile, 2*t)", tables={"profile": lambda x: x**3})
    assert profile(1.5) == pytest.approx(27.0)
    # Without `derivative()` the table is differentiated by central differences.
    assert profile.derivative()(1.5) == pytest.approx(2 * 3 * 9.0, rel=1e-7)
    assert profile.derivative().derivative()(1.5) == pytest.approx(4 * 6 * 3.0, rel=1e-6)
    assert profile.evaluate_array(np.array([0.5, 1.0])).tolist() == [1.0, 8.0]


def test_table_with_exact_derivative():
    xs = np.linspace(0.0, 4.0, 9)
    spline = CubicSpline(xs, np.sin(xs))
    compiled = compile_text("table(lift, t*t)", tables={"lift": spline})
    t = 1.3
    assert compiled.derivative()(t) == pytest.approx(spline(t * t, 1) * 2 * t, rel=1e-14)
    second = spline(t * t, 2) * (2 * t) ** 2 + spline(t * t, 1) * 2
    assert compiled.derivative().derivative()(t) == pytest.approx(second, rel=1e-13)


def test_names_measures_tables():
    expression = parse(
        "table(wind, angle(hinge)) * k + dist(eye, frame) - step(t, 0, 0, 2, 90*deg) + pi"
    )
    assert expression.names() == {"k", "t", "deg", "pi"}
    assert expression.measures() == {("angle", ("hinge",)), ("dist", ("eye", "frame"))}
    assert expression.tables() == {"wind"}
    assert expression.text.startswith("table(wind")
    assert isinstance(expression, Expression) and expression == parse(expression.text)


def test_pickle_round_trip_keeps_values_and_derivatives():
    compiled = compile_text("k * step(t, 0, 0, 2, 90*deg)", {"k": 3.0, "unused": 1.0})
    copy = pickle.loads(pickle.dumps(compiled.derivative()))
    assert copy.order == 1 and copy(0.7) == compiled.derivative()(0.7)
    assert pickle.loads(pickle.dumps(parse("1 + t"))) == parse("1 + t")


# ------------------------------------------------------------------------------ errors
@pytest.mark.parametrize(
    ("text", "message", "offset"),
    [
        ("", "empty expression", 0),
        ("   ", "empty expression", 0),
        ("sine(t)", "unknown function 'sine'", 0),
        ("2 * f(t)", "unknown function 'f'", 4),
        ("sin(t", "expected ')'", 5),
        ("(1 + 2", "expected ')'", 6),
        ("step(t, 0, 0, 2", "expected ')'", 15),
        ("1 +", "expected an expression", 3),
        ("()", "expected an expression", 1),
        ("* 2", "expected an expression", 0),
        ("not", "expected an expression", 3),
        ("(1 + 2))", "unexpected ')'", 7),
        ("1, 2", "unexpected ','", 1),
        ("1 not 2", "unexpected 'not'", 2),
        ("5mm", "missing operator before 'mm'", 1),
        ("2 (t)", "missing operator before '('", 2),
        ("1 < t < 3", "chained comparisons are not allowed; use 'and'", 6),
        ("sin(1, 2)", "'sin' takes 1 argument, got 2", 0),
        ("sin()", "'sin' takes 1 argument, got 0", 0),
        ("atan2(1)", "'atan2' takes 2 arguments, got 1", 0),
        ("min(1)", "'min' takes at least 2 arguments, got 1", 0),
        ("t + step(t, 0, 1)", "'step' takes 5 arguments, got 3", 4),
        ("angle(hinge + 1)", "argument of 'angle' must be a joint name", 6),
        ("dist(a, 2*b)", "argument of 'dist' must be a point name", 8),
        ("dist(a)", "'dist' takes 2 arguments, got 1", 0),
        ("x(p, q)", "'x' takes 1 argument, got 2", 0),
        ("table(1, t)", "first argument of 'table' must be a table name", 6),
        ("table(wind)", "'table' takes 2 arguments, got 1", 0),
        ("1 % 2", "unexpected character '%'", 2),
        ("{1}", "unexpected character '{'", 0),
        ("a = 1", "'=' is not allowed; use '==' to compare", 2),
        ("!a", "use 'not' instead of '!'", 0),
        ("a && b", "use 'and' instead of '&'", 2),
        ("a || b", "use 'or' instead of '|'", 2),
    ],
)
def test_syntax_errors(text, message, offset):
    with pytest.raises(ExpressionError) as info:
        parse(text)
    assert (info.value.message, info.value.offset) == (message, offset)
    assert info.value.text == text


@pytest.mark.parametrize(
    ("text", "message", "offset"),
    [
        ("__import__('os')", "'__import__' is not allowed", 0),
        ("t + __builtins__", "'__builtins__' is not allowed", 4),
        ("lambda x: x", "'lambda' is not allowed", 0),
        ("import os", "'import' is not allowed", 0),
        ("1 if t else 2", "'if' is not allowed", 2),
        ("True", "'True' is not allowed", 0),
        ("eval(t)", "'eval' is not allowed", 0),
        ("open(t)", "'open' is not allowed", 0),
        ("getattr(t, 1)", "'getattr' is not allowed", 0),
        ("os.system", "attribute access is not allowed", 2),
        ("t.real", "attribute access is not allowed", 1),
        ("(1).real", "attribute access is not allowed", 3),
        ("sin(t).__class__", "attribute access is not allowed", 6),
        ("a[0]", "subscripts are not allowed", 1),
        ("[1, 2]", "subscripts are not allowed", 0),
        ("'abc'", "strings are not allowed", 0),
        ('t + "x"', "strings are not allowed", 4),
        ("angle(__class__)", "'__class__' is not allowed", 6),
    ],
)
def test_forbidden_python(text, message, offset):
    with pytest.raises(ExpressionError) as info:
        parse(text)
    assert (info.value.message, info.value.offset) == (message, offset)


def test_unknown_function_and_name_hints():
    with pytest.raises(ExpressionError) as info:
        parse("sine(t)")
    assert info.value.hint == "did you mean 'sin'?"
    with pytest.raises(ExpressionError) as info:
        parse("2 * crank_sped * t").compile({"crank_speed": 1.0}, unit_lookup=units)
    error = info.value
    assert (error.message, error.offset) == ("unknown name 'crank_sped'", 4)
    assert error.hint == "did you mean 'crank_speed'?"
    assert str(error) == (
        "unknown name 'crank_sped' at offset 4 of '2 * crank_sped * t' "
        "(did you mean 'crank_speed'?)"
    )


@pytest.mark.parametrize(
    ("text", "message", "offset"),
    [
        ("1 + furlong", "unknown name 'furlong'", 4),
        ("table(wnd, t)", "unknown table 'wnd'", 0),
        ("t + 1/0", "division by zero", 5),
        ("sqrt(-1) * t", "math domain error in 'sqrt'", 0),
        ("t + log(0)", "math domain error in 'log'", 4),
        ("t * exp(1000)", "overflow in 'exp'", 4),
        ("(-8) ** (1/3) + t", "math domain error in '**'", 5),
        ("step(t, 2, 0, 1, 1)", "step needs x0 < x1", 0),
        ("t + step(t, 1, 0, 1, 1)", "step needs x0 < x1", 4),
    ],
)
def test_compile_errors(text, message, offset):
    with pytest.raises(ExpressionError) as info:
        parse(text).compile({"k": 1.0}, {"wind": abs}, unit_lookup=units)
    assert (info.value.message, info.value.offset) == (message, offset)
    assert info.value.text == text


@pytest.mark.parametrize(
    ("text", "t", "message", "offset"),
    [
        ("1 / (t - 1)", 1.0, "division by zero", 2),
        ("2 + sqrt(t)", -1.0, "math domain error in 'sqrt'", 4),
        ("acos(t)", 2.0, "math domain error in 'acos'", 0),
        ("t ^ 0.5", -4.0, "math domain error in '**'", 2),
        ("exp(t)", 1.0e4, "overflow in 'exp'", 0),
    ],
)
def test_runtime_math_errors(text, t, message, offset):
    compiled = compile_text(text)
    with pytest.raises(ExpressionError) as info:
        compiled(t)
    assert (info.value.message, info.value.offset) == (message, offset)


def test_derivative_domain_error_points_at_the_function():
    with pytest.raises(ExpressionError) as info:
        compile_text("1 + sqrt(t)").derivative()(0.0)
    assert (info.value.message, info.value.offset) == ("division by zero", 4)


def test_unit_lookup_is_only_asked_for_unknown_names():
    asked: list[str] = []

    def lookup(name: str) -> float | None:
        asked.append(name)
        return UNITS.get(name)

    parse("k * t + pi + 3*mm").compile({"k": 2.0}, unit_lookup=lookup)
    assert asked == ["mm"]


def test_deep_nesting_is_an_error_not_a_crash():
    """Nesting is bounded (issue 39): the level past the limit is reported where it starts."""
    assert compile_text("(" * 63 + "t" + ")" * 63)(2.0) == 2.0
    for text, offset in (("-" * 5000 + "1", 64), ("+".join(["t"] * 5000), 127)):
        with pytest.raises(ExpressionError) as info:
            parse(text).compile()
        assert (info.value.message, info.value.offset) == (
            "nested more than 64 levels deep",
            offset,
        )


def test_parsed_text_reused_and_errors_raised_every_time() -> None:
    """A text parsed before gives the same (frozen) tree; a text that does not parse is
    refused each time with its message and offset (errors are not kept)."""
    a, b = parse("2 * angle(hinge) + k"), parse("2 * angle(hinge) + k")
    assert a.tree is b.tree and a == b
    for _ in range(2):
        with pytest.raises(ExpressionError) as caught:
            parse("2 * (t + ")
        assert caught.value.offset == 9
