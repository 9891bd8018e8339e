"""Cable loop (seed 003 eqs. 2.3-2.6), eddy-current damper, gear coupler, seal springs."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib

from .._models import Ramp

R1, R2, K, T0 = 0.05, 0.04, 1.0e4, 200.0  # m, m, N/m per strand, N (both strands taut)
TH1, TH2 = math.radians(10.0), math.radians(5.0)


def _held(value: float) -> Ramp:
    return Ramp(value, 0.0)


def _ccl(th1: float = TH1, guided: bool = False) -> mechlib.Mechanism:
    """Yoke hinged to ground at A = 0, panel hinged to the yoke at B = (1, 0, 0); pulley 1
    (r1) on ground at A, pulley 2 (r2) on the panel at B; both joints held by motions."""
    mech = mechlib.Mechanism(name="ccl", gravity=(0.0, 0.0, 0.0))
    mech.add_body("yoke", mass=1.0, cm=(0.5, 0.0, 0.0), inertia=[0.01, 0.1, 0.1])
    mech.add_body("panel", mass=1.0, cm=(1.5, 0.0, 0.0), inertia=[0.01, 0.1, 0.1])
    mech.add_joint("hl1", "revolute", bodies=("yoke", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_joint("hl2", "revolute", bodies=("panel", "yoke"), at=(1, 0, 0), axis=(0, 0, 1))
    mech.add_force(mechlib.CableLoop("ccl", ("hl1", "hl2"), (R1, R2), K, T0, guided=guided))
    mech.add_motion("m1", joint="hl1", function=_held(th1))
    mech.add_motion("m2", joint="hl2", function=_held(TH2))
    return mech


@pytest.mark.parametrize("th1", [TH1, math.radians(40.0)], ids=["taut", "strand-a-slack"])
@pytest.mark.parametrize(
    "analysis",
    [
        mechlib.Static(),
        mechlib.Kinematic(end=0.5, step=0.25),
        mechlib.QuasiStatic(end=0.5, step=0.25),
    ],
    ids=["static", "kinematic", "quasi-static"],
)
def test_cable_loop_loads_by_hand(th1: float, analysis) -> None:
    """Pulley rotations relative to the yoke: phi1 = -th1 (pulley 1 is on ground, body 2
    of hl1), phi2 = +th2 (pulley 2 is the panel, body 1 of hl2); e = r1 phi1 - r2 phi2;
    F_a = T0 + k e, F_b = T0 - k e (the hinge distance D = 1 m is fixed by the yoke);
    T1 = r1 (F_b - F_a), T2 = r2 (F_a - F_b), F_ax = (F_a + F_b) L / D,
    F_lat = (F_a - F_b)(r1 - r2)/D with L = sqrt(D^2 - (r1 - r2)^2). The motions hold the
    loop (no gravity): their efforts are +T1 (on th1 = -phi1) and -T2; the panel's hinge
    carries the cable's pull on pulley 2, F_ax along B->A and |F_lat| across. At th1 =
    40 deg strand a is slack (F_a = max(0, T0 + k e) = 0). In static, kinematic and
    quasi-static analyses (the joints held: no inertia). Tolerance 1e-9 relative."""
    e = R1 * (-th1) - R2 * TH2
    fa, fb = max(0.0, T0 + K * e), max(0.0, T0 - K * e)
    d = 1.0
    length = math.sqrt(d * d - (R1 - R2) ** 2)
    sol = mechlib.solve(
        _ccl(th1),
        analysis,
        requests=[
            mechlib.ElementOutput("ccl", "ccl"),
            mechlib.MotionEffort("m1", "m1"),
            mechlib.MotionEffort("m2", "m2"),
            mechlib.JointReaction("hl2", "hl2"),
        ],
    )
    assert sol.ok, sol.message
    c = {k: v[-1] for k, v in sol.channels.items()}  # the joints held: every row alike
    expected = {
        "t1": R1 * (fb - fa),
        "t2": R2 * (fa - fb),
        "f_axial": (fa + fb) * length / d,
        "f_lateral": (fa - fb) * (R1 - R2) / d,
        "tension_a": fa,
        "tension_b": fb,
    }
    for key, value in expected.items():
        assert c[f"ccl.{key}"] == pytest.approx(value, rel=1e-9)
    assert c["m1.value"] == pytest.approx(expected["t1"], rel=1e-9)
    assert c["m2.value"] == pytest.approx(-expected["t2"], rel=1e-9)
    # reaction on the panel from the yoke balances the cable's force on pulley 2
    u = np.array([math.cos(th1), math.sin(th1), 0.0])  # A -> B
    force = np.array([c["hl2.fx"], c["hl2.fy"], c["hl2.fz"]])
    assert force @ u == pytest.approx(expected["f_axial"], rel=1e-9)
    assert abs(np.cross(u, force)[2]) == pytest.approx(abs(expected["f_lateral"]), rel=1e-9)


@pytest.mark.parametrize("th1", [TH1, math.radians(40.0)], ids=["taut", "strand-a-slack"])
def test_guided_cable_loop_torque_on_the_yoke_by_hand(th1: float) -> None:
    """Guided strands (seed 003 fig. 2.2.5-4), the loop of the test above held statically.
    By hand: the strands run parallel to AB, so F_a, F_b are those of e alone (D fixed),
    F_ax = F_a + F_b along AB and no lateral force; the pulleys take T1 = r1 (F_b - F_a)
    (ground) and T2 = r2 (F_a - F_b) (panel), the yoke the rest of the cable's balance,
    T_yoke = -(T1 + T2) = (F_a - F_b)(r1 - r2) about +z in the sense of phi, i.e. -T_yoke
    about +z here (phi1 = -theta1: pulley 1 is ground, body 2 of hl1). Free bodies: the
    panel's hinge carries only F_ax (no lateral component); the yoke, with the hl2 reaction
    and motion m2's effort from the panel, T_yoke from the guides and the hl1 reaction and
    effort from ground, closes; the whole wing (yoke + panel) needs -T1 from m1 (the cable's
    net moment on ground is T1 and the cable is in equilibrium). Tolerance 1e-9 relative."""
    e = R1 * (-th1) - R2 * TH2
    fa, fb = max(0.0, T0 + K * e), max(0.0, T0 - K * e)
    t1, t2, t_yoke = R1 * (fb - fa), R2 * (fa - fb), (fa - fb) * (R1 - R2)
    sol = mechlib.solve(
        _ccl(th1, guided=True),
        mechlib.Static(),
        requests=[
            mechlib.ElementOutput("ccl", "ccl"),
            mechlib.MotionEffort("m1", "m1"),
            mechlib.MotionEffort("m2", "m2"),
            mechlib.JointReaction("hl2", "hl2"),
            mechlib.JointReaction("hl1", "hl1"),
        ],
    )
    assert sol.ok, sol.message
    c = {k: v[-1] for k, v in sol.channels.items()}
    expected = {"t1": t1, "t2": t2, "f_axial": fa + fb, "f_lateral": 0.0, "t_yoke": t_yoke}
    for key, value in expected.items():
        assert c[f"ccl.{key}"] == pytest.approx(value, rel=1e-9, abs=1e-9)
    assert abs(t_yoke) > 1.0  # the check has teeth: 2.4 N*m taut, 1.2 N*m slack
    # the whole wing: m1 holds the cable's net moment on yoke + panel, -(T2 + T_yoke) = T1
    assert c["m1.value"] == pytest.approx(t1, rel=1e-9)
    assert c["m2.value"] == pytest.approx(-t2, rel=1e-9)
    u = np.array([math.cos(th1), math.sin(th1), 0.0])  # A -> B
    hl2 = np.array([c["hl2.fx"], c["hl2.fy"], c["hl2.fz"]])
    assert hl2 @ u == pytest.approx(fa + fb, rel=1e-9)
    assert abs(np.cross(u, hl2)[2]) < 1e-9 * (fa + fb)  # no lateral force on the panel
    # the wing's force balance: ground's reaction on the yoke equals the panel's pull
    hl1 = np.array([c["hl1.fx"], c["hl1.fy"], c["hl1.fz"]])
    np.testing.assert_allclose(hl1, hl2, rtol=1e-9, atol=1e-9 * (fa + fb))


def test_damper_decays_a_free_rotor() -> None:
    """A rotor (I = 0.1 kg m^2, no gravity) spun at 2 rad/s with c = 0.05 N*m*s/rad:
    omega = 2 exp(-c t / I). Tolerance 1e-3 relative (integrator at its default tolerance;
    3.3e-4 measured)."""
    mech = mechlib.Mechanism(name="rotor", gravity=(0.0, 0.0, 0.0))
    mech.add_body("rotor", mass=1.0, cm=(0, 0, 0), inertia=[0.05, 0.05, 0.1])
    mech.add_joint("axle", "revolute", bodies=("rotor", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_force(mechlib.RotationalDamper("eddy", "axle", 0.05))
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=2.0, step=0.1),
        initial=[mechlib.InitialBodyVelocity("rotor", omega=(0, 0, 2.0))],
        requests=[mechlib.ElementOutput("eddy", "eddy")],
    )
    assert sol.ok, sol.message
    expected = 2.0 * np.exp(-0.05 * sol.time / 0.1)
    np.testing.assert_allclose(sol.channels["eddy.omega"], expected, rtol=1e-3)
    np.testing.assert_allclose(sol.channels["eddy.value"], 0.05 * expected, rtol=1e-3)


def test_gear_ratio_transmits_angle_and_torque() -> None:
    """Gear th2 = 3 th1 between two shafts on ground; a torsion spring k = 4 N*m/rad on
    shaft 2; driving shaft 1 to 0.1 rad quasi-statically: th2 = 0.3 rad and, by virtual
    work, the drive torque = ratio * k th2 = 3.6 N*m; the gear's own effort (the mesh torque
    on each shaft) by statics of each shaft. Tolerance 1e-9."""
    mech = mechlib.Mechanism(name="gear", gravity=(0.0, 0.0, 0.0))
    for name, x in (("s1", 0.0), ("s2", 0.2)):
        mech.add_body(name, mass=1.0, cm=(x, 0, 0), inertia=[0.01] * 3)
        mech.add_joint(
            f"j{name[1]}", "revolute", bodies=(name, "ground"), at=(x, 0, 0), axis=(0, 0, 1)
        )
    mech.add_joint("g", "gear", bodies=("ground", "ground"), joints=("j1", "j2"), ratio=3.0)
    mech.add_force(mechlib.TorsionSpring("k", "j2", stiffness=4.0))
    mech.add_motion("drive", joint="j1", function=Ramp(0.0, 0.1))
    sol = mechlib.solve(
        mech,
        mechlib.QuasiStatic(end=1.0, step=0.5),
        requests=[
            mechlib.JointCoordinate("a2", "j2"),
            mechlib.MotionEffort("drive", "drive"),
            mechlib.CouplerEffort("mesh", "g"),
        ],
    )
    assert sol.ok, sol.message
    assert sol.channels["a2.value"][-1] == pytest.approx(0.3, abs=1e-9)
    assert sol.channels["drive.value"][-1] == pytest.approx(3.6, abs=1e-9)
    # the gear holds the spring on shaft 2 (k th2 = 1.2 N*m) and takes ratio times that
    # from shaft 1, against the drive: output = +1.2, input = -3.6 = -ratio * output
    assert sol.channels["mesh.output"][-1] == pytest.approx(1.2, abs=1e-9)
    assert sol.channels["mesh.input"][-1] == pytest.approx(-3.6, abs=1e-9)


def _seal_force(count: int, exponent: float) -> float:
    """Total seal force (N) on a door hinged on ground about z at the origin, its knife
    along x from 0.2 m to 1.0 m on a seal of normal +y; turned by -0.01 rad the door
    presses in: penetration x(s) = s sin(0.01) at distance s from the hinge."""
    mech = mechlib.Mechanism(name="door", gravity=(0.0, 0.0, 0.0))
    mech.add_body("door", mass=5.0, cm=(0.5, 0.0, 0.0), inertia=[0.1, 0.5, 0.5])
    mech.add_joint("hinge", "revolute", bodies=("door", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_force(
        mechlib.Seal(
            "seal",
            ("door", "ground"),
            (0.2, 0, 0),
            (1.0, 0, 0),
            (0, 1, 0),
            count=count,
            stiffness=2.0e5,
            exponent=exponent,
        )
    )
    mech.add_motion("close", joint="hinge", function=_held(-0.01))
    sol = mechlib.solve(
        mech,
        mechlib.Static(),
        requests=[mechlib.ElementOutput("seal", "seal"), mechlib.MotionEffort("close", "close")],
    )
    assert sol.ok, sol.message
    return sol.channels["seal.normal"][0]


@pytest.mark.parametrize("exponent", [1.0, 1.5])
def test_seal_force_3_vs_7_springs(exponent: float) -> None:
    """Exact line integral F = int_a^b k (g s)^e ds, g = sin(0.01); the N springs are the
    midpoint rule with spacing h = (b - a)/N, error <= (b - a) h^2 max|f''| / 24 with
    f'' = k e (e - 1) g^2 (g s)^(e - 2) (zero for e = 1: exact, tolerance 1e-9 relative).
    3 and 7 springs agree within the sum of their two bounds."""
    a, b, k, g = 0.2, 1.0, 2.0e5, math.sin(0.01)
    exact = k * g**exponent * (b ** (exponent + 1) - a ** (exponent + 1)) / (exponent + 1)
    f2 = (
        k * exponent * (exponent - 1) * g**2 * (g * a) ** (exponent - 2) if exponent != 1 else 0.0
    )  # |f''| is largest at s = a for 1 < e < 2
    bound = {n: (b - a) * ((b - a) / n) ** 2 * abs(f2) / 24 + 1e-9 * exact for n in (3, 7)}
    forces = {n: _seal_force(n, exponent) for n in (3, 7)}
    for n, force in forces.items():
        assert abs(force - exact) <= bound[n]
    assert abs(forces[3] - forces[7]) <= bound[3] + bound[7]


def test_gear_effort_from_yaml(tmp_path) -> None:
    """`{joint: g, quantity: force}` on a gear gives its input / output efforts in N*m
    (same model as above, from a case file)."""
    from loadcases.run import run_file

    case = tmp_path / "gear.case.yaml"
    case.write_text(
        """\
case: gear-mesh
mechanism:
  gravity: [0, 0, 0]
  bodies:
    s1: {mass: 1, cm: [0, 0, 0], inertia: [0.01, 0.01, 0.01]}
    s2: {mass: 1, cm: [0.2, 0, 0], inertia: [0.01, 0.01, 0.01]}
  joints:
    j1: {type: revolute, bodies: [s1, ground], at: [0, 0, 0], axis: [0, 0, 1]}
    j2: {type: revolute, bodies: [s2, ground], at: [0.2, 0, 0], axis: [0, 0, 1]}
    g: {type: gear, joints: [j1, j2], ratio: 3}
  forces:
    k: {type: torsion_spring, joint: j2, stiffness: 4}
motions:
  drive: {joint: j1, value: "0.1 * t"}
analysis: {type: quasi-static, end: 1.0, step: 0.5}
requests:
  mesh: {joint: g, quantity: force}
""",
        encoding="utf-8",
    )
    (outcome,) = run_file(case, output_dir=tmp_path / "out")
    ch = outcome.solution.channels
    assert ch["mesh.output"][-1] == pytest.approx(1.2, abs=1e-9)
    assert ch["mesh.input"][-1] == pytest.approx(-3.6, abs=1e-9)
    header = (tmp_path / "out" / "gear-mesh.csv").read_text().splitlines()[0]
    assert header.split(",")[1:] == ["mesh.input", "mesh.output"]


@pytest.mark.parametrize("moving", [True, False])
def test_seal_wrench_with_friction(moving: bool) -> None:
    """The seal's wrench on a door sliding along its knife, in closed form: a knife of
    0.8 m along x on body `door` (cm (0.5, 0, 0)) over a seal of normal +y on ground, 4
    springs at x = 0.3, 0.5, 0.7, 0.9 m, pre-compressed 1 mm (gap -1 mm) at 2e5 N/m^2: each
    spring 0.2 m x 200 N/m = 40 N along +y on the door. Sliding at +0.5 m/s (moving) or
    2e-6 m from its slip anchor at rest (both beyond the thresholds 1e-3 m/s, 1e-6 m), each
    spring's friction is -mu 40 N along x (mu 0.3: -12 N). Door: F = (-48, 160, 0) N,
    moment about its cm N_z = 40 N x (-0.2 + 0 + 0.2 + 0.4) m = 16 N*m; ground: the reverse
    force, moment about the origin -40 N x 2.4 m = -96 N*m. Tolerance 1e-9 N."""
    from mechlib.system.system import System

    mech = mechlib.Mechanism(name="door", gravity=(0.0, 0.0, 0.0))
    mech.add_body("door", mass=5.0, cm=(0.5, 0.0, 0.0), inertia=[0.1, 0.5, 0.5])
    seal = mechlib.Seal(
        "seal", ("door", "ground"), (0.2, 0, 0), (1.0, 0, 0), (0, 1, 0), count=4,
        stiffness=2.0e5, gap=-1e-3, mu=0.3,
    )  # fmt: skip
    mech.add_force(seal)
    system = System(mech)
    q = system.design_q()
    qd = np.zeros(system.nq)
    if moving:
        qd[0] = 0.5
        k = system.kin(q, qd, 0.0)
    else:
        q[0] += 2e-6  # anchored at the design position by bind
        k = system.kin(q, None, 0.0)
    F, N = np.zeros((2, 3)), np.zeros((2, 3))
    seal.apply(system.view(k), F, N)
    shift = 0.0 if moving else 2e-6  # the arms move with the door at rest
    assert np.allclose(F, [[-48.0, 160.0, 0.0], [48.0, -160.0, 0.0]], rtol=0, atol=1e-9)
    assert np.allclose(N[0], [0.0, 0.0, 16.0], rtol=0, atol=1e-9)
    assert np.allclose(N[1], [0.0, 0.0, -40.0 * (2.4 + 4 * shift)], rtol=0, atol=1e-9)


def test_seal_without_a_friction_band_is_plain_coulomb() -> None:
    """v_threshold 0 (no regularisation band): full friction -mu F at any sliding speed,
    none at rest relative to the seal (closed form of test_seal_wrench_with_friction at
    0.5 m/s: -12 N per spring along x; at 0 m/s: 0 N)."""
    from mechlib.system.system import System

    for speed, friction in ((0.5, -48.0), (0.0, 0.0)):
        mech = mechlib.Mechanism(name="door", gravity=(0.0, 0.0, 0.0))
        mech.add_body("door", mass=5.0, cm=(0.5, 0.0, 0.0), inertia=[0.1, 0.5, 0.5])
        seal = mechlib.Seal(
            "seal", ("door", "ground"), (0.2, 0, 0), (1.0, 0, 0), (0, 1, 0), count=4,
            stiffness=2.0e5, gap=-1e-3, mu=0.3, v_threshold=0.0,
        )  # fmt: skip
        mech.add_force(seal)
        system = System(mech)
        qd = np.zeros(system.nq)
        qd[0] = speed
        F, N = np.zeros((2, 3)), np.zeros((2, 3))
        seal.apply(system.view(system.kin(system.design_q(), qd, 0.0)), F, N)
        assert np.allclose(F[0], [friction, 160.0, 0.0], rtol=0, atol=1e-9)


@pytest.mark.parametrize("moving", [True, False])
def test_compiled_seal_equals_its_stations(moving: bool) -> None:
    """The power-law seal's one compiled call (seal_kernels.seal_apply) against its
    stations taken one by one (Seal._parts, the kernels the output request reads) and
    their wrench: a door turned and moving (or displaced from its slip anchor at rest),
    exponent 1.5, friction on; forces and moments to 1e-12 relative, and the door's force
    equal to the output's resultant."""
    from mechlib.elements.seal_kernels import seal_wrench
    from mechlib.system.system import System

    mech = mechlib.Mechanism(name="door", gravity=(0.0, 0.0, 0.0))
    mech.add_body("door", mass=5.0, cm=(0.5, 0.0, 0.0), inertia=[0.1, 0.5, 0.5])
    seal = mechlib.Seal(
        "seal", ("door", "ground"), (0.2, 0, 0), (1.0, 0, 0), (0, 1, 0), count=5,
        stiffness=3.0e6, exponent=1.5, gap=-1e-3, mu=0.3,
    )  # fmt: skip
    mech.add_force(seal)
    system = System(mech)
    q = system.design_q().copy()
    q[3:7] = [math.cos(0.002), 0.0, 0.0, math.sin(0.002)]  # 4 mrad about z: uneven pressure
    q[0] += 2e-6
    qd = np.zeros(system.nq)
    if moving:
        qd[0], qd[1], qd[6] = 0.4, -0.01, 0.05
    view = system.view(system.kin(q, qd if moving else None, 0.0))
    F, N = np.zeros((2, 3)), np.zeros((2, 3))
    seal.apply(view, F, N)
    p1, n, normal, friction, x = seal._parts(view)
    assert (x > 0).sum() >= 3 and len(set(np.round(normal, 6))) > 1
    F_ref, N_ref = np.zeros((2, 3)), np.zeros((2, 3))
    seal_wrench(view.kin.x, 0, 1, p1, n, normal, friction, F_ref, N_ref)
    scale = np.abs(F_ref).max()
    np.testing.assert_allclose(F, F_ref, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(N, N_ref, rtol=0, atol=1e-12 * scale)
    out = seal.output(view)
    np.testing.assert_allclose(F[0], [out["fx"], out["fy"], out["fz"]], atol=1e-12 * scale)
    assert np.abs(friction).max() > 0.0
