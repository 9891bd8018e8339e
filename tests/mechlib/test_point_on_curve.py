"""Point-on-curve joint. References: a bead on a circular wire is a simple pendulum (period
4 sqrt(R/g) K(sin(theta0/2)), normal force m (g cos(theta) + v^2/R) = m g (3 cos(theta) -
2 cos(theta0))); a bead on the parabola y = x^2 under gravity and a side force F rests
where the slope 2x = F / (m g). Tolerances per test."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ellipk

import mechlib as ml
from mechlib.model.curves import Curve

G, R, MASS = 9.81, 1.0, 0.5


def _bead_on(curve_points, start, gravity=(0.0, -G, 0.0), interpolation="cubic"):
    mech = ml.Mechanism(gravity=gravity)
    mech.add_body("bead", mass=MASS, cm=start, inertia=[1e-4, 1e-4, 1e-4])
    mech.add_point("bead_c", body="bead", at=start)
    mech.add_joint(
        "wire",
        "point_on_curve",
        bodies=("bead", "ground"),
        at=start,
        curve=curve_points,
        interpolation=interpolation,
    )
    return mech


def _circle(theta0: float):
    """Circle of radius R about the origin, angles from the bottom, every 5 deg over
    +-120 deg; the bead released at theta0."""
    angles = np.radians(np.arange(-120.0, 120.1, 5.0))
    points = [(R * math.sin(a), -R * math.cos(a), 0.0) for a in angles]
    return points, (R * math.sin(theta0), -R * math.cos(theta0), 0.0)


def test_curve_nearest_point_and_normals():
    """On a spline through a circle (5 deg spacing) the nearest point of (0.5, -0.5, 0.2)
    is along its ray (1e-6 m), n1 points along the radius and n2 along z (1e-6)."""
    points, _ = _circle(0.0)
    curve = Curve(points)
    u = curve.nearest(np.array([0.5, -0.5, 0.2]))
    assert curve.point(u) == pytest.approx([R / math.sqrt(2), -R / math.sqrt(2), 0.0], abs=1e-6)
    n1, n2 = curve.normals(u)
    assert abs(n1 @ np.array([1.0, -1.0, 0.0]) / math.sqrt(2)) == pytest.approx(1.0, abs=1e-6)
    assert abs(n2[2]) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.slow
def test_bead_on_a_circular_wire_is_a_pendulum():
    """Released at 60 deg: the period equals the elliptic-integral value within 2e-4
    (the spline of the circle and the integrator), and the wire's normal force at the
    bottom equals m g (3 - 2 cos 60 deg) = 2 m g within 1e-3; the bead stays on the circle
    (radius within 1e-6 m)."""
    theta0 = math.radians(60.0)
    points, start = _circle(theta0)
    period = 4.0 * math.sqrt(R / G) * ellipk(math.sin(theta0 / 2.0) ** 2)
    sol = ml.solve(
        _bead_on(points, start),
        ml.Dynamic(end=1.5 * period, step=1e-3, tolerance=1e-8),
        requests=[ml.PointKinematics("p", "bead_c"), ml.JointReaction("f", "wire")],
    )
    assert sol.ok, sol.message
    x, y = sol.channels["p.x"], sol.channels["p.y"]
    assert np.abs(np.hypot(x, y) - R).max() < 1e-6
    # period: between two downward crossings of x = 0
    t = sol.time
    crossings = [
        t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
        for i in range(len(x) - 1)
        if x[i] > 0.0 >= x[i + 1]
    ]
    assert len(crossings) >= 2
    assert crossings[1] - crossings[0] == pytest.approx(period, rel=2e-4)
    force = np.hypot(sol.channels["f.fx"], sol.channels["f.fy"])
    bottom = int(np.argmin(np.abs(x[: int(0.5 * len(x))])))
    assert force[bottom] == pytest.approx(2.0 * MASS * G, rel=1e-3)


def test_bead_on_a_parabola_rests_where_the_slope_balances():
    """Gravity -y and a side force F = 2 N along +x: the bead on y = x^2 (cubic spline
    through 41 points over |x| <= 1) rests at x = F / (2 m g) within 1e-5 m."""
    xs = np.linspace(-1.0, 1.0, 41)
    points = [(x, x * x, 0.0) for x in xs]
    mech = _bead_on(points, (0.0, 0.0, 0.0))
    # a static bead needs its free rotations held: nothing loads them
    mech.add_joint("upright", "orientation", bodies=("bead", "ground"), at=(0.0, 0.0, 0.0))
    mech.add_force(ml.PointForce("push", "bead", (0.0, 0.0, 0.0), lambda t, v: (2.0, 0.0, 0.0)))
    sol = ml.solve(mech, ml.Static(), requests=[ml.PointKinematics("p", "bead_c")])
    assert sol.ok, sol.message
    assert sol.channels["p.x"][0] == pytest.approx(2.0 / (2.0 * MASS * G), abs=1e-5)


def test_point_on_curve_from_yaml(tmp_path):
    """SPEC 1.2 keys (`curve` points in mm, `interpolation: akima`): a bead released on a
    coarse 8-point arc keeps its energy m g y + m v^2 / 2 within 1e-4 of m g R over 2 s
    (an ideal joint does no work) and its joint force is normal to its velocity (the
    power F . v within 1e-6 W)."""
    from loadcases.run import run_file

    case = tmp_path / "bead.case.yaml"
    case.write_text(
        """\
case: bead-on-wire
units: {length: mm}
mechanism:
  gravity: [0, -9.81, 0]
  bodies:
    bead: {mass: 0.5, cm: [866.025, -500, 0], inertia: [1.0e-4, 1.0e-4, 1.0e-4]}
  points:
    bead_c: {body: bead, at: [866.025, -500, 0]}
  joints:
    wire: {type: point_on_curve, bodies: [bead, ground], at: [866.025, -500, 0],
           curve: [[-866.025, -500, 0], [-707.107, -707.107, 0], [-500, -866.025, 0], [0, -1000, 0],
                   [500, -866.025, 0], [707.107, -707.107, 0], [866.025, -500, 0],
                   [965.926, -258.819, 0]],
           interpolation: akima}
analysis: {type: dynamic, end: 2.0, step: 0.01, tolerance: 1.0e-8}
requests:
  wire: {joint: wire, quantity: force}
  v: {point: bead_c, quantity: velocity}
  p: {point: bead_c, quantity: position}
""",
        encoding="utf-8",
    )
    (outcome,) = run_file(case, output_dir=tmp_path / "out")
    ch = outcome.solution.channels
    assert outcome.solution.ok
    speed2 = sum(ch[f"v.{c}"] ** 2 for c in "xyz")
    energy = MASS * G * ch["p.y"] + 0.5 * MASS * speed2
    assert np.ptp(energy) < 1e-4 * MASS * G * R
    power = sum(ch[f"wire.f{c}"] * ch[f"v.{c}"] for c in "xyz")
    assert np.abs(power).max() < 1e-6


def test_repeated_curve_point_is_an_input_error(tmp_path):
    """Two equal consecutive points: an input error at the second (file:line:col, exit 2
    from the command line), not an internal error."""
    from loadcases.run import check_case_file

    case = tmp_path / "bad.case.yaml"
    case.write_text(
        """\
case: bad-curve
mechanism:
  bodies:
    bead: {mass: 1, cm: [0, 0, 0], inertia: [1, 1, 1]}
  joints:
    wire: {type: point_on_curve, bodies: [bead, ground], at: [0, 0, 0],
           curve: [[0, 0, 0], [0, 0, 0], [1, 0, 0]]}
analysis: {type: static}
""",
        encoding="utf-8",
    )
    found = check_case_file(case)
    assert [(d.message, d.line) for d in found] == [
        ("point 1 repeats point 0: the curve needs distinct consecutive points", 7)
    ]
    assert found[0].key.endswith("curve[1]")
