"""Bushing (6-DOF linear spring-damper). References: a free body on a bushing at its centre
of mass has the six uncoupled frequencies sqrt(k_i / m) and sqrt(kr_i / I_i) / (2 pi); a
bar on a torsionally stiff bushing sags by kr theta = m g L cos(theta) (root-found); a
damped vertical oscillation decays as exp(-c t / (2 m)). Tolerances per test."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import mechlib as ml
from mechlib.elements.bushing import rotation_vector

MASS, INERTIA = 2.0, (0.02, 0.03, 0.05)
K, KR = (4.0e4, 6.0e4, 9.0e4), (300.0, 500.0, 700.0)


def _mounted(cm=(0.0, 0.0, 0.0), gravity=(0.0, 0.0, 0.0), **bushing) -> ml.Mechanism:
    mech = ml.Mechanism(gravity=gravity)
    mech.add_body("box", mass=MASS, cm=cm, inertia=list(INERTIA))
    mech.add_point("box_c", body="box", at=cm)
    mech.add_force(ml.Bushing("mount", ("box", "ground"), (0.0, 0.0, 0.0), **bushing))
    return mech


def test_rotation_vector_of_a_known_rotation() -> None:
    """Axis times angle back from the matrix of a 0.7 rad turn about (1, 2, 2)/3 (1e-12)."""
    axis, angle = np.array([1.0, 2.0, 2.0]) / 3.0, 0.7
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rot = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    assert rotation_vector(rot) == pytest.approx(angle * axis, abs=1e-12)


def test_six_uncoupled_frequencies() -> None:
    """Modes of the body on the bushing at its centre of mass: the three translational
    and three rotational frequencies of the closed form, within 1e-6 relative."""
    sol = ml.solve(_mounted(stiffness=K, torsional_stiffness=KR), ml.Modes())
    expected = sorted(
        [math.sqrt(k / MASS) / (2 * math.pi) for k in K]
        + [math.sqrt(kr / i) / (2 * math.pi) for kr, i in zip(KR, INERTIA)]
    )
    assert list(sol.channels["mode.frequency"]) == pytest.approx(expected, rel=1e-6)


def test_bar_sags_on_torsional_stiffness() -> None:
    """cm 0.4 m out along x, gravity -z, bushing at the origin: static rotation about y
    solves kr_y theta = m g L cos(theta) (the translation kz dz = m g adds no moment about
    the bushing point); rotation vector within 1e-9 rad, dz = -m g / kz within 1e-9 m,
    reported force on the box = +m g up (1e-9 N)."""
    length, g = 0.4, 9.81
    sol = ml.solve(
        _mounted(
            cm=(length, 0.0, 0.0), gravity=(0.0, 0.0, -g), stiffness=K, torsional_stiffness=KR
        ),
        ml.Static(),
        requests=[ml.ElementOutput("b", "mount")],
    )
    theta = brentq(lambda a: KR[1] * a - MASS * g * length * math.cos(a), 0.0, 1.0)
    assert sol.ok
    # gravity turns the bar down: a positive rotation about +y takes +x towards -z
    assert sol.channels["b.ry"][0] == pytest.approx(theta, abs=1e-9)
    assert sol.channels["b.dz"][0] == pytest.approx(-MASS * g / K[2], abs=1e-9)
    assert sol.channels["b.fz"][0] == pytest.approx(MASS * g, abs=1e-9)
    assert sol.channels["b.ty"][0] == pytest.approx(-KR[1] * theta, abs=1e-6)


@pytest.mark.slow
def test_vertical_damping_decay() -> None:
    """Launched up at 0.1 m/s from rest position with damping c_z = 8 N*s/m: successive
    peaks of the vertical motion decay by exp(-c T_d / (2 m)) per damped period (log
    decrement of the damped oscillator), within 1 %; the twist stays zero (1e-12)."""
    c = 8.0
    mech = _mounted(stiffness=K, torsional_stiffness=KR, damping=(0.0, 0.0, c))
    sol = ml.solve(
        mech,
        ml.Dynamic(end=0.2, step=1.0e-4, tolerance=1e-9),
        initial=[ml.InitialBodyVelocity("box", velocity=(0.0, 0.0, 0.1))],
        requests=[ml.PointKinematics("p", "box_c"), ml.ElementOutput("b", "mount")],
    )
    assert sol.ok
    z = sol.channels["p.z"]
    peaks = [i for i in range(1, len(z) - 1) if z[i - 1] < z[i] >= z[i + 1] and z[i] > 0]
    assert len(peaks) >= 4
    wn = math.sqrt(K[2] / MASS)
    zeta = c / (2.0 * math.sqrt(K[2] * MASS))
    period = 2.0 * math.pi / (wn * math.sqrt(1.0 - zeta**2))
    ratio = math.exp(-c * period / (2.0 * MASS))
    measured = [z[b] / z[a] for a, b in itertools.pairwise(peaks)]
    assert measured == pytest.approx([ratio] * len(measured), rel=0.01)
    assert np.abs(sol.channels["b.rx"]).max() < 1e-12


def test_bushing_from_yaml(tmp_path) -> None:
    """The SPEC key set from a case file (mm): the static bushing force carries the weight
    (m g = 19.62 N, 1e-9) and its sag matches the mechlib model above."""
    from loadcases.run import run_file

    case = tmp_path / "bushing.case.yaml"
    case.write_text(
        """\
case: bushing-mount
units: {length: mm}
mechanism:
  gravity: [0, 0, -9.81]
  bodies:
    box: {mass: 2, cm: [400, 0, 0], inertia: [0.02, 0.03, 0.05]}
  forces:
    mount: {type: bushing, bodies: [box, ground], at: [0, 0, 0], stiffness: [4.0e4, 6.0e4, 9.0e4],
            torsional_stiffness: [300, 500, 700], damping: [5, 5, 5], torsional_damping: [1, 1, 1]}
analysis: {type: static}
requests:
  mount: {force: mount}
""",
        encoding="utf-8",
    )
    (outcome,) = run_file(case, output_dir=tmp_path / "out")
    ch = outcome.solution.channels
    theta = brentq(lambda a: KR[1] * a - MASS * 9.81 * 0.4 * math.cos(a), 0.0, 1.0)
    assert ch["mount.fz"][0] == pytest.approx(MASS * 9.81, abs=1e-9)
    assert ch["mount.ry"][0] == pytest.approx(theta, abs=1e-9)
