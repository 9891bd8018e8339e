"""Joint limits and planar contacts from case files: statics resting on a limit (the
reaction by hand), a ball bouncing on a floor in a planar mechanism (closed-form impact),
and a lock-up whose peak follows the impact energy over a friction sweep."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

G = 9.81

_BAR = """
name: bar-on-stop
plane: xy
units: {angle: deg}
gravity: [0, -9.81, 0]
bodies:
  bar: {mass: 2, cm: [0.5, 0, 0], inertia: [1e-4, 0.1666667, 0.1666667]}
  block: {mass: 3, cm: [2, 0, 0], inertia: [0.01, 0.01, 0.01]}
joints:
  hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
  slide: {type: prismatic, bodies: [block, ground], at: [2, 0, 0], axis: [0, 1, 0]}
limits:
  stop: {joint: hinge, min: 0, max: 30, stiffness: 1.0e4, exponent: 1.5, damping: 50, depth: 0.1}
  floor: {joint: slide, min: -5 mm, stiffness: 1.0e7 N/m, exponent: 1}
"""


def _solve(tmp_path: Path, mechanism: str, case: str):
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    (tmp_path / "m.mech.yaml").write_text(mechanism)
    (tmp_path / "c.case.yaml").write_text("mechanism: m.mech.yaml\n" + case)
    outcome = run_case(load_case(tmp_path / "c.case.yaml"))
    assert outcome.solution.ok, outcome.solution.message
    return outcome


def test_static_rests_on_its_limits(tmp_path: Path) -> None:
    """The bar rests on its lower stop: k x^1.5 = m g L/2 cos x (x = 9.8726e-3 rad, read
    from the angle: the motion), the stop carrying m g L/2 cos x = 9.8095 N*m; the block
    rests on its travel stop at -5 mm with m g = 29.43 N, 2.943e-6 m deep. By hand
    (brentq); measured to 1e-12, asserted to 1e-9."""
    outcome = _solve(
        tmp_path,
        _BAR,
        """case: rest
analysis: {type: static}
requests:
  a: {joint: hinge, quantity: angle}
  s: {joint: slide, quantity: travel}
  stop: {limit: stop}
  floor: {force: floor}
""",
    )
    ch = outcome.solution.channels
    x = brentq(lambda x: 1.0e4 * x**1.5 - 2.0 * G * 0.5 * math.cos(x), 0.0, 0.1, xtol=1e-15)
    moment = 2.0 * G * 0.5 * math.cos(x)
    assert -ch["a.value"][0] == pytest.approx(x, rel=1e-9)
    assert ch["stop.value"][0] == pytest.approx(moment, rel=1e-9)
    assert ch["stop.penetration"][0] == pytest.approx(x, rel=1e-9)
    assert -5e-3 - ch["s.value"][0] == pytest.approx(3.0 * G / 1.0e7, rel=1e-6)
    assert ch["floor.value"][0] == pytest.approx(3.0 * G, rel=1e-9)
    # a limit's load is charted among the loads, named as {limit:} or {force:}
    assert outcome.request_kinds["stop"] == outcome.request_kinds["floor"] == "contact"


_BALL = """
name: ball-floor
plane: {plane}
gravity: {gravity}
bodies:
  ball: {{mass: 0.5, cm: [0, 0.1, 0], inertia: [1e-4, 1e-4, 1e-4]}}
contacts:
  floor: {{type: impact, bodies: [ball, ground], stiffness: 1.0e6, exponent: 1,
          geometry: {{shape: sphere_plane, center: [0, 0.1, 0], radius: 0.01,
                     plane_point: [0, 0, 0], normal: [0, 1, 0]}}}}
"""


@pytest.mark.parametrize("plane", ["xy", "yz"])
def test_planar_ball_bounces_as_a_linear_oscillator(tmp_path: Path, plane: str) -> None:
    """A 0.5 kg ball dropped 0.09 m onto a linear floor (1e6 N/m, no damping) in a planar
    mechanism: impact speed v = sqrt(2 g h) = 1.3288 m/s; in contact an oscillator about
    the static deflection d = m g / k (w = sqrt(k/m), amplitude A = sqrt(d^2 + (v/w)^2)):
    deepest d + A = 0.9445 mm (read from the ball's height: the motion), contact
    (pi + 2 asin(d / A)) / w = 2.23 ms, rebound at v, peak force k (d + A). Tolerances 2e-3
    (sampling every 2e-5 s)."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    mech = _BALL.format(plane=plane, gravity="[0, -9.81, 0]")
    text = mech + "points:\n  c: {body: ball, at: [0, 0.1, 0]}\n"
    (tmp_path / "m.mech.yaml").write_text(text)
    (tmp_path / "c.case.yaml").write_text(
        "mechanism: m.mech.yaml\ncase: drop\n"
        "analysis: {type: dynamic, end: 0.14, step: 2.0e-5, tolerance: 1.0e-7, accuracy: off}\n"
        "requests:\n  c: {point: c, quantity: position}\n  v: {point: c, quantity: velocity}\n"
        "  f: {contact: floor, quantity: force}\n"
    )
    sol = run_case(load_case(tmp_path / "c.case.yaml")).solution
    assert sol.ok, sol.message
    y, vy = sol.channels["c.y"], sol.channels["v.y"]
    v, w, d = math.sqrt(2.0 * G * 0.09), math.sqrt(1.0e6 / 0.5), 0.5 * G / 1.0e6
    amplitude = math.hypot(d, v / w)
    inside = np.flatnonzero(y < 0.01)
    assert np.all(np.diff(inside) == 1), "one contact"
    assert 0.01 - y.min() == pytest.approx(d + amplitude, rel=2e-3)
    duration = (math.pi + 2.0 * math.asin(d / amplitude)) / w
    assert sol.time[inside[-1]] - sol.time[inside[0]] == pytest.approx(duration, abs=4e-5)
    assert vy[inside[-1] + 1] == pytest.approx(v, rel=2e-3)
    assert sol.channels["f.normal"].max() == pytest.approx(1.0e6 * (d + amplitude), rel=2e-3)


def test_modes_linearise_an_engaged_limit(tmp_path: Path) -> None:
    """The bar resting on a linear limit (k = 1e4 N*m/rad, 3-D: modes need it) swings on
    it at sqrt(K / I) / (2 pi), K = k + m g L/2 sin x (gravity at the rest angle -x,
    k x = m g L/2 cos x), I = m L^2 / 3 + 1e-7 (the inertia as written): 19.4924 Hz.
    Measured 6e-9 relative, asserted to 1e-6."""
    mech = (
        _BAR.replace("plane: xy\n", "")
        .replace("units: {angle: deg}\n", "")
        .replace(", max: 30", "")
        .replace("exponent: 1.5, damping: 50, depth: 0.1", "exponent: 1")
    )
    outcome = _solve(tmp_path, mech, "case: modes\nanalysis: {type: modes}\n")
    x = brentq(lambda x: 1.0e4 * x - G * math.cos(x), 0.0, 0.1, xtol=1e-15)
    inertia = 0.1666667 + 2.0 * 0.25
    expected = math.sqrt((1.0e4 + G * math.sin(x)) / inertia) / (2.0 * math.pi)
    assert outcome.solution.channels["mode.frequency"][0] == pytest.approx(expected, rel=1e-6)


def test_a_limit_switched_on_by_an_event_from_a_case_file(tmp_path: Path) -> None:
    """`limits:` with `active: false` and an event `activate`: the bar falls 0.1 rad from
    rest onto a linear undamped limit (k = 1e4 N*m/rad) switched on as it reaches it.
    Energy by hand: (1/2) k x^2 = m g L/2 (sin(0.1) + sin x) solved for the deepest x
    (brentq, gravity work included), peak k x; read from the angle and the limit's value:
    measured -8.9e-6 in 184 steps, asserted to 2e-5 (output every 1e-4 s). The block beside
    it bounces on its undamped travel stop: the steps fall to 0.1 ms at each of its
    contacts. While a step change carried the integrator's own velocity whole, its
    velocity-constraint violation (O(h^2) of the long step) read as an acceleration
    H/h times too large in the short ones: an index-3 transient in the bar's acceleration
    (+-3.3 rad/s^2 on its 14.7) that the next 3.4 ms step turned into 1.5e-3 of the bar's
    energy, +7.2e-4 of x in 183 steps (pinned to 1e-3 then). Carried with the step since
    (rules.constraint_velocity). Without the block: -1.0e-5 (the rows' sampling).
    `effects: {contact: false}`
    removes the limit: its request is then an error at its key."""
    mech = _BAR.replace(
        "max: 30, stiffness: 1.0e4, exponent: 1.5, damping: 50, depth: 0.1",
        "stiffness: 1.0e4, exponent: 1, active: false",
    )
    mech = mech.replace(
        "plane: xy\n",
        "plane: xy\nevents:\n  touch: {when: 'angle(hinge) <= 0', then: [{activate: stop}]}\n",
    )
    case = """case: fall
initial: {hinge: {value: 0.1 rad}}
analysis: {type: dynamic, end: 0.25, step: 1.0e-4, tolerance: 1.0e-7, accuracy: off}
requests:
  a: {joint: hinge, quantity: angle}
  stop: {limit: stop}
"""
    ch = _solve(tmp_path, mech, case).solution.channels
    torque = 2.0 * G * 0.5
    # work of gravity from +0.1 down to -x (bar along x, gravity -y): torque (sin 0.1 + sin x)
    x = brentq(
        lambda x: 0.5e4 * x**2 - torque * (math.sin(0.1) + math.sin(x)), 1e-6, 0.5, xtol=1e-14
    )
    assert -ch["a.value"].min() == pytest.approx(x, rel=2e-5)
    assert ch["stop.value"].max() == pytest.approx(1.0e4 * x, rel=2e-5)
    assert ch["stop.value"][ch["a.value"] > 0].max() == 0.0  # off until it is reached

    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    (tmp_path / "c.case.yaml").write_text(
        "mechanism: m.mech.yaml\n" + case + "effects: {contact: false}\n"
    )
    with pytest.raises(InputError) as caught:
        run_case(load_case(tmp_path / "c.case.yaml"))
    assert [d.key for d in caught.value.diagnostics] == ["requests.stop.limit"]


def test_a_limit_at_a_parameter_keeps_the_parameters_unit(tmp_path: Path) -> None:
    """`min: lock` with `lock: 10 deg` in a file whose bare angles are degrees: the limit is
    at 10 deg (the parameter's SI value is not read again in the file's unit), and a set's
    value (`--set lock=20deg`, a case parameter here) moves it. The bar rests on it:
    k x = m g L/2 cos(lock - x) (brentq), to 1e-9."""
    mech = """
units: {angle: deg}
gravity: [0, -9.81, 0]
parameters: {lock: 10 deg}
bodies:
  bar: {mass: 2, cm: [0.5, 0, 0], inertia: [1e-4, 0.1666667, 0.1666667]}
joints:
  hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0], axis: [0, 0, 1]}
limits:
  stop: {joint: hinge, min: lock, stiffness: 1.0e4, exponent: 1}
"""
    for lock, case in ((10.0, ""), (20.0, "parameters: {lock: 20 deg}\n")):
        (tmp_path / str(lock)).mkdir()
        ch = _solve(
            tmp_path / str(lock),
            mech,
            case + "case: rest\nanalysis: {type: static}\n"
            "requests:\n  a: {joint: hinge, quantity: angle}\n",
        ).solution.channels
        at = math.radians(lock)
        x = brentq(lambda x, at=at: 1.0e4 * x - G * math.cos(at - x), 0.0, 0.1, xtol=1e-15)
        assert ch["a.value"][0] == pytest.approx(at - x, rel=1e-9)
