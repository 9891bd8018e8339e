"""Issue 39 item 2: expressions and quantity texts are bounded. Towers of powers, huge
integers and long or deep texts end, promptly, in an input error at their key (exit 2),
never in a hang, a RecursionError or an `internal error`."""

from __future__ import annotations

import time

import pytest

from loadcases.expressions import ExpressionError, parse
from loadcases.flexible.values import FileFormatError, nastran_real
from loadcases.foundation.limits import MAX_EXPRESSION_CHARS, MAX_EXPRESSION_DEPTH
from loadcases.foundation.units import UnitError, to_si
from loadcases.inputs.overrides import OverrideError, parse_overrides
from tests.hardening.conftest import has_line, loads

MASS = "crank: {mass: 1.0,"
DRIVE = 'value: "speed * t"'  # the case's line 4; the key at column 25, its text at 33


def _validate(crank, **change: tuple[str, str]):
    started = time.perf_counter()
    result = loads("validate", crank(**change))
    return result, time.perf_counter() - started


def _refused(result, expected: str) -> None:
    assert result.exit_code == 2, result.output
    assert "internal error" not in result.output and "Traceback" not in result.output
    assert has_line(result.output, expected), result.output


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("10**10**10 kg", "a number out of range"),
        ("9^9^9 kg", "a number out of range"),
        ("1 kg**(2**1000)", "a number out of range"),
        ("2**(2**20) kg", "a number out of range"),
        ("1" + "0" * 400 + " kg", "longer than 100 characters"),
        ("1 min**99*min**99*min**99 * kg", "a number out of range"),
        ("2(50 kg", "unbalanced parentheses"),
        ("2) kg", "unbalanced parentheses"),
        ("1 m" + "*m" * 60, "longer than 100 characters"),
        ("1 " + "(" * 60 + "kg" + ")" * 60, "longer than 100 characters"),
        ("0x10 kg", "unknown unit 'x10'"),
        ("1_000 kg", "'1_000' is not a decimal number"),
        ("1,5 kg", "',' is not part of a quantity: write 1500 for 1,500 and 1.5 for 1,5"),
        ("1:30 kg", "':' is not part of a quantity"),
        ("1 kg # 2", "'#' is not part of a quantity"),
    ],
)
def test_a_quantity_text_out_of_bounds_is_refused_at_its_key(crank, text, reason) -> None:
    result, seconds = _validate(crank, mech=(MASS, f'crank: {{mass: "{text}",'))
    shown = text if len(text) <= 80 else text[:77] + "..."
    _refused(
        result, f"crank.mech.yaml:5:11: error: bodies.crank.mass: cannot read '{shown}': {reason}"
    )
    assert seconds < 10


def test_quantity_texts_are_read_in_floats_promptly() -> None:
    """No integer arithmetic without bound inside the unit parser: each of these takes a
    fraction of a second (a tower of integer powers would not end)."""
    for text in ("10**10**10 kg", "9**9**9**9 kg", "1 m**99**99", "1 * (((10**100)**100)**100) kg"):
        started = time.perf_counter()
        with pytest.raises(UnitError, match="out of range"):
            to_si(text, "mass" if "kg" in text else "any")
        assert time.perf_counter() - started < 0.5, text
    # the usual texts read as before, integer exponents of units kept
    assert to_si("110 mm", "length") == 0.11
    assert to_si("2 * 3 m", "length") == 6.0
    assert to_si("12 N*m/rad", "torsional_stiffness") == 12.0
    assert to_si("9.81 m/s^2", "acceleration") == 9.81
    assert to_si("1 kg*m^2", "inertia") == 1.0
    assert to_si("3 m**-1 * m**2", "length") == 3.0
    assert to_si("2 m²", "area") == 2.0
    with pytest.raises(UnitError, match="expected a length, got '1 m\\*\\*2' \\(an area\\)"):
        to_si("1 m**2", "length")


def test_expression_longer_than_the_limit_is_refused(crank) -> None:
    text = "+".join(["1"] * (MAX_EXPRESSION_CHARS // 2 + 1))
    result, seconds = _validate(crank, case=(DRIVE, f'value: "{text}"'))
    _refused(
        result,
        "crank.case.yaml:4:33: error: motions.drive.value: invalid expression: "
        f"longer than {MAX_EXPRESSION_CHARS:,} characters ({len(text):,})",
    )
    assert seconds < 10


@pytest.mark.parametrize(
    ("text", "offset"),
    [
        # a sum: one level per operator; the operator that passes the limit is reported
        ("+".join(["t"] * (MAX_EXPRESSION_DEPTH + 1)), 2 * MAX_EXPRESSION_DEPTH - 1),
        ("+".join(["t"] * 1000), 2 * MAX_EXPRESSION_DEPTH - 1),
        ("*".join(["t"] * 3000), 2 * MAX_EXPRESSION_DEPTH - 1),
        # nested calls, negations, parentheses, powers: where the level past it starts
        ("sin(" * 1000 + "t" + ")" * 1000, 4 * MAX_EXPRESSION_DEPTH),
        ("-" * 5000 + "t", MAX_EXPRESSION_DEPTH),
        ("(" * 1000 + "t" + ")" * 1000, MAX_EXPRESSION_DEPTH),
        ("**".join(["t"] * 1000), 3 * MAX_EXPRESSION_DEPTH),
    ],
)
def test_expression_nested_too_deeply_is_refused_at_its_key(crank, text, offset) -> None:
    result, seconds = _validate(crank, case=(DRIVE, f'value: "{text}"'))
    _refused(
        result,
        f"crank.case.yaml:4:{33 + offset}: error: motions.drive.value: invalid expression: "
        f"nested more than {MAX_EXPRESSION_DEPTH} levels deep",
    )
    assert seconds < 10


def test_expressions_at_the_limits_compile_with_their_derivatives() -> None:
    """What the limits let through is compiled, differentiated twice and evaluated."""
    depth = MAX_EXPRESSION_DEPTH
    texts = [
        "+".join(["t"] * depth),
        "sin(" * (depth - 1) + "t" + ")" * (depth - 1),
        "(" * (depth - 1) + "t" + ")" * (depth - 1),
        "-" * (depth - 1) + "t",
        "**".join(["t"] * (depth // 2)),
        "atan(" * (depth - 1) + "t" + ")" * (depth - 1),
    ]
    for text in texts:
        compiled = parse(text).compile()
        second = compiled.derivative().derivative()
        assert isinstance(compiled(0.5) + second(0.5), float), text


def test_constant_folding_stays_in_floats_and_is_prompt() -> None:
    for text in ("10**10**10", "9**9**9**9", "2**(2**1000)", "exp(exp(exp(10)))"):
        started = time.perf_counter()
        with pytest.raises(ExpressionError, match="overflow"):
            parse(text + "*t").compile()
        assert time.perf_counter() - started < 0.5, text


# A run of digits that a reader does not take whole: each reader had a number pattern that
# could split it in every way (`[0-9]+\.?[0-9]*`), quadratic in its length (fuzzing found a
# `--set` value of 2.7 million digits and an `=` that ran for hours; 40 000 digits: 23 s).
DIGITS = "2" * 100_000


@pytest.mark.parametrize(
    ("read", "error", "words"),
    [
        (lambda: parse_overrides([f"speed={DIGITS}=1"]), OverrideError, "longer than 100"),
        (lambda: to_si(f"{DIGITS}=", "any"), UnitError, "longer than 100"),
        (lambda: nastran_real(f"{DIGITS}X"), FileFormatError, "expected a real number"),
    ],
)
def test_a_long_digit_run_is_refused_promptly(read, error, words: str) -> None:
    started = time.perf_counter()
    with pytest.raises(error, match=words):
        read()
    assert time.perf_counter() - started < 1.0


def test_a_long_digit_run_in_an_expression_field_is_refused_promptly(crank) -> None:
    result, seconds = _validate(crank, case=(DRIVE, f'value: "{DIGITS}t"'))
    assert result.exit_code == 2, result.output
    assert "internal error" not in result.output and "Traceback" not in result.output
    assert "crank.case.yaml:4:33: error: motions.drive.value:" in result.output, result.output
    assert seconds < 5
