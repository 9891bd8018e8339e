"""Force elements in the compiled runs (mechlib.elements.compiled_forces,
mechlib.solvers.genalpha.run): the packed loads equal the elements' own, and mechanisms with
springs, dampers and joint friction are solved in the compiled whole run, against closed
forms of their motion."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechlib
import mechlib.solvers.dense as dense
from mechlib.elements.compiled_forces import CompiledForces, element_wrenches
from mechlib.kinematics import constraint_arrays as ca
from mechlib.solvers.genalpha import run as genalpha_run
from mechlib.system.system import System

MASS, INERTIA = 10.0, 0.1  # kg, kg*m^2 about the axle (z)


def _disc(**forces) -> mechlib.Mechanism:
    """A disc on a revolute axle along z through its centre, no gravity."""
    mech = mechlib.Mechanism(name="disc", gravity=(0.0, 0.0, 0.0))
    mech.add_body("disc", mass=MASS, cm=(0, 0, 0), inertia=[0.05, 0.05, INERTIA])
    mech.add_joint("axle", "revolute", bodies=("disc", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    for element in forces.values():
        mech.add_force(element)
    return mech


def _kernel_steps(mech, analysis, initial, requests, monkeypatch, runner=None) -> tuple:
    """(solution, the steps taken in compiled runs: `runner`'s, StepRun's by default)."""
    taken = {"steps": 0}
    runner = runner or genalpha_run.StepRun
    original = runner.run

    def run(self, s, *args):
        before = self.stepper.stats.steps
        out = original(self, s, *args)
        taken["steps"] += self.stepper.stats.steps - before
        return out

    with monkeypatch.context() as patch:
        patch.setattr(runner, "run", run)
        sol = mechlib.solve(mech, analysis, initial=initial, requests=requests)
    assert sol.ok, sol.message
    return sol, taken["steps"]


def test_packed_loads_equal_the_elements_own() -> None:
    """At a moving state with reactions, the packed springs, torsion springs, dampers and
    frictions (with mu > 0: loaded by the reaction) load the bodies as their own `apply`
    does (the Python path), to round-off."""
    mech = mechlib.Mechanism(name="pair", gravity=(0.0, -9.81, 0.0))
    mech.add_body("a", mass=2.0, cm=(0.2, 0, 0), inertia=[0.01, 0.02, 0.03])
    mech.add_body("b", mass=1.0, cm=(0.5, 0.1, 0), inertia=[0.01, 0.01, 0.02])
    mech.add_point("tip", body="b", at=(0.6, 0.1, 0.0))
    mech.add_point("post", body="ground", at=(0.3, -0.4, 0.1))
    mech.add_joint("h", "revolute", bodies=("a", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_joint("k", "revolute", bodies=("b", "a"), at=(0.4, 0, 0), axis=(0, 0, 1))
    ends = (("b", (0.6, 0.1, 0.0)), ("ground", (0.3, -0.4, 0.1)))
    spring = mechlib.Spring("s", ends, stiffness=300.0, damping=2.0, free_length=0.3, preload=5.0)
    mech.add_force(spring)
    mech.add_force(mechlib.TorsionSpring("t", "k", stiffness=4.0, damping=0.3, angle0=0.2))
    mech.add_force(mechlib.RotationalDamper("d", "h", damping=0.7))
    mech.add_force(mechlib.JointFriction("f", "h", 0.2, 0.02, 0.1))
    mech.add_force(mechlib.JointFriction("g", "k", 0.0, 0.0, 0.05))
    system = System(mech)
    rng = np.random.default_rng(3)
    q = system.design_q()
    qd = rng.standard_normal(system.nq)
    k = system.kin(q, qd, 0.0)
    jac = system.phi_q(k)
    lam = 50.0 * rng.standard_normal(size=(jac.shape[0],))
    packed = CompiledForces.of(system)
    assert packed is not None and len(packed.frictions) == 2
    packed.refresh(system)
    F, N = system.wrenches(k, lam, (), jac)
    arrays = system.packed_constraints()
    assert arrays is not None
    ints, floats = arrays.packed()
    x, xd = ca.state_arrays(q, qd, system.nb)
    nall = ints[0] + 3 * ints[1] + ints[2] + ints[3] + ints[6]
    full, rows = np.empty(nall), np.zeros((nall, system.nq + 7))
    active, _ = ca.constraint_rows(
        x, ints, floats, arrays.functions(0.0), arrays.references(), full, rows
    )
    F2, N2 = np.empty_like(F), np.empty_like(N)
    element_wrenches(x, xd, np.zeros(0), packed.args, rows, active, lam, F2, N2)
    scale = np.abs(N).max() + np.abs(F).max()
    assert scale > 1.0
    np.testing.assert_allclose(F2[:-1], F[:-1], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(N2[:-1], N[:-1], rtol=0, atol=1e-12 * scale)


def test_spring_damped_disc_in_the_compiled_run(monkeypatch) -> None:
    """A disc on a torsion spring (k = 4 N*m/rad) with a rotational damper (c = 0.12
    N*m*s/rad) released at 0.3 rad: theta = e^(-zeta w t) (A cos(wd t) + B sin(wd t)),
    w = sqrt(k / I), zeta = c / (2 sqrt(k I)). Solved in compiled runs (all but the first
    steps), within 2e-4 rad of the closed form at tolerance 1e-7 (measured 6.2e-5)."""
    k, c, theta0 = 4.0, 0.12, 0.3
    mech = _disc(
        spring=mechlib.TorsionSpring("coil", "axle", stiffness=k),
        damper=mechlib.RotationalDamper("brake", "axle", damping=c),
    )
    analysis = mechlib.Dynamic(end=2.0, step=0.01, tolerance=1e-7)
    sol, in_kernel = _kernel_steps(
        mech, analysis, [mechlib.InitialValue("axle", value=theta0)],
        [mechlib.JointCoordinate("a", "axle")], monkeypatch,
    )  # fmt: skip
    assert in_kernel >= sol.stats.steps - 3
    w = math.sqrt(k / INERTIA)
    zeta = c / (2.0 * math.sqrt(k * INERTIA))
    wd = w * math.sqrt(1.0 - zeta**2)
    t = np.asarray(sol.time)
    exact = theta0 * np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))
    assert np.abs(sol.channels["a.value"] - exact).max() < 2e-4


@pytest.mark.parametrize("mu", [0.0, 0.2])
def test_friction_disc_spins_down_in_the_compiled_run(mu: float, monkeypatch) -> None:
    """A disc spinning at 10 rad/s against a pin friction (preload 0.3 N*m, and mu 0.2 on
    a 0.05 m pin under a 50 N side load): constant deceleration T / I, T = mu r F +
    preload (before it stops at omega0 I / T, past the end). With mu = 0 the slide is
    solved in compiled runs (all but the first step); with the side load (a point force,
    no compiled form) in Python steps with the compiled Newton loop loaded by the
    reaction. The rate within 3e-3 rad/s of the closed form (measured 8.9e-4 and 1.8e-3)."""
    preload, pin, side = 0.3, 0.05, 50.0
    mech = _disc(rub=mechlib.JointFriction("rub", "axle", mu, pin, preload))
    if mu:  # a side load (no compiled form: Python steps, their Newton loop compiled)
        mech.add_force(mechlib.PointForce("push", "disc", (0, 0, 0), lambda t, v: (side, 0, 0)))
    torque = mu * pin * side + preload
    analysis = mechlib.Dynamic(end=0.5, step=0.01, tolerance=1e-6)
    sol, in_kernel = _kernel_steps(
        mech, analysis, [mechlib.InitialBodyVelocity("disc", omega=(0, 0, 10.0))],
        [mechlib.JointCoordinate("a", "axle", "omega")], monkeypatch,
    )  # fmt: skip
    t = np.asarray(sol.time)
    expected = np.maximum(10.0 - torque / INERTIA * t, 0.0)
    np.testing.assert_allclose(sol.channels["a.value"], expected, atol=3e-3)
    if mu == 0.0:
        assert in_kernel > 0.8 * sol.stats.steps


def test_spring_damped_disc_in_compiled_dense_rows(monkeypatch) -> None:
    """The spring-damped disc above with dense output, step by step: its rows projected
    in the compiled rows' kernel with the packed torsion spring and damper (a step's rows
    in one call; all rows but the first) equal the Python rows to 1e-9 of the angle's peak
    (measured: bit for bit, the same 491 steps), and meet the closed form within 2e-4 rad
    (measured 8.1e-5)."""
    k, c, theta0 = 4.0, 0.12, 0.3
    runs, kernel_rows = {}, {"done": 0}
    original = dense.HermiteRows.block

    def block(self, start, end, times, z0, z1):
        got = original(self, start, end, times, z0, z1)
        kernel_rows["done"] += got.rows if got is not None else 0
        return got

    for compiled in ("steps", "python"):
        mech = _disc(
            spring=mechlib.TorsionSpring("coil", "axle", stiffness=k),
            damper=mechlib.RotationalDamper("brake", "axle", damping=c),
        )
        analysis = mechlib.Dynamic(end=2.0, step=0.01, tolerance=1e-7, dense=True)
        analysis = dataclasses.replace(analysis, compiled=compiled)
        with monkeypatch.context() as patch:
            patch.setattr(dense.HermiteRows, "block", block)
            runs[compiled] = mechlib.solve(
                mech, analysis, initial=[mechlib.InitialValue("axle", value=theta0)],
                requests=[mechlib.JointCoordinate("a", "axle")],
            )  # fmt: skip
        assert runs[compiled].ok, runs[compiled].message
        if compiled == "steps":
            assert kernel_rows["done"] >= len(runs[compiled].time) - 1
    fast, slow = runs["steps"], runs["python"]
    assert fast.stats.steps == slow.stats.steps
    angle = slow.channels["a.value"]
    assert np.abs(fast.channels["a.value"] - angle).max() < 1e-9 * np.abs(angle).max()
    w = math.sqrt(k / INERTIA)
    zeta = c / (2.0 * math.sqrt(k * INERTIA))
    wd = w * math.sqrt(1.0 - zeta**2)
    t = np.asarray(fast.time)
    exact = theta0 * np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))
    assert np.abs(fast.channels["a.value"] - exact).max() < 2e-4
