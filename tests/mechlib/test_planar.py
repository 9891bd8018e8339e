"""Planar mechanisms (mechlib.system.planar) against the same model in 3-D.

The model: benchmarks.planar.fourbar_chain (four-bar loops of four revolutes about the
plane's normal). Oracles: the 3-D solution of the same model (redundant equations dropped),
whose in-plane results are determinate; the reduction itself against finite differences of
the map planar -> 3-D (T^T M3 T, phi_q3 T). Tolerances: 1e-9 of each column's peak for
kinematic and quasi-static runs (both exact to the Newton tolerance; measured 3e-15 and
2e-14) and for
Radau at tolerance 1e-9 (both integrations converged; measured 3e-13); 1e-7 for the finite
differences (step 1e-7, measured 5e-10); columns that are 0 compared to 1e-12 (SI).
"""

from __future__ import annotations

import numpy as np
import pytest

import mechlib as ml
from benchmarks.planar import fourbar_chain
from mechlib.model.plane import plane_axes
from mechlib.system.planar import make_system


class _Swing:
    """Crank angle A sin(2 pi t) (rad) and its exact rates: A = 0.6 rad stays clear of the
    loop's toggle positions (it is not a Grashof crank: the crank cannot turn round)."""

    amplitude, omega = 0.6, 2.0 * np.pi

    def value(self, t: float) -> float:
        return self.amplitude * np.sin(self.omega * t)

    def rate(self, t: float) -> float:
        return self.amplitude * self.omega * np.cos(self.omega * t)

    def accel(self, t: float) -> float:
        return -self.amplitude * self.omega**2 * np.sin(self.omega * t)


_REQUESTS = [
    ml.JointReaction("pin", "s0"),
    ml.JointReaction("pivot", "r1"),
    ml.PointKinematics("p", "p", "position"),
    ml.PointKinematics("v", "p", "velocity"),
    ml.PointKinematics("a", "p", "acceleration"),
    ml.JointCoordinate("rocker", "r1", "omega"),
]
_FLOOR = 1e-12  # SI: round-off of a column that is 0 (a revolute's moment about its axis)
_IN_PLANE = ("fx", "fy", "tz", "x", "y", "value")


def _driven(plane: str = "xy", planar: bool = True) -> ml.Mechanism:
    m = fourbar_chain(1, plane=plane, planar=planar)
    e1, e2, _ = plane_axes(plane)
    m.add_point("p", body="coupler0", at=tuple(0.1 * e1 - 0.2 * e2))
    m.add_motion("drive", joint="r0", function=_Swing())
    return m


def _solve(m: ml.Mechanism, analysis, **keys) -> ml.Solution:
    requests = _REQUESTS + ([ml.MotionEffort("torque", "drive")] if m.motions else [])
    return ml.solve(m, analysis, requests=requests, redundant="drop", **keys)


def _assert_same(planar: ml.Solution, space: ml.Solution, tol: float) -> None:
    """Every in-plane column (xy plane) within tol of its peak."""
    for name, column in space.channels.items():
        if name.rsplit(".", 1)[1] in _IN_PLANE:
            peak = np.abs(column).max()
            gap = np.abs(planar.channels[name] - column).max()
            assert gap <= tol * peak + _FLOOR, f"{name}: {gap:.3g} of peak {peak:.3g}"


def test_redundant_equations_3_per_loop_in_3d_none_planar() -> None:
    """Two loops of four revolutes: 3-D has 3 redundant equations per loop (out-of-plane
    translation and two tilts), the planar model none: 5 bodies x 3 - 14 equations = 1 DOF."""
    space = ml.inspect_mechanism(fourbar_chain(2, planar=False))
    planar = ml.inspect_mechanism(fourbar_chain(2))
    assert (len(space.redundant), space.equations) == (6, 35)
    assert (planar.redundant, planar.equations, planar.degrees_of_freedom) == ((), 14, 1)


def test_reduction_matches_finite_differences() -> None:
    """M = T^T M3 T and phi_q = phi_q3 T, with T = d(q3)/dq by central differences of the
    map at a generic state (angles within 2 pi); `state_of` inverts `kin`."""
    system = make_system(fourbar_chain(1))
    rng = np.random.default_rng(3)
    q = system.design_q() + 0.3 * rng.standard_normal(system.nq)
    k = system.kin(q)
    T = np.empty((7 * system.nb, system.nq))
    for j in range(system.nq):
        dq = np.zeros(system.nq)
        dq[j] = 1e-7
        T[:, j] = (system.kin(q + dq).x[:-1] - system.kin(q - dq).x[:-1]).ravel() / 2e-7
    space = system.space
    back = system.state_of(system.kin(q, q[::-1]))
    assert np.allclose(back[0], q, atol=1e-12) and np.allclose(back[1], q[::-1], atol=1e-12)
    assert np.allclose(system.mass(k), T.T @ space.mass(k) @ T, atol=1e-7, rtol=0)
    assert np.allclose(system.phi_q(k), space.phi_q(k) @ T, atol=1e-7, rtol=0)


def test_elements_in_a_static_equilibrium_match_3d() -> None:
    """A spring, a torsion spring and a joint friction loaded by the pin's reaction hold
    the four-bar under gravity: the planar equilibrium (angles, in-plane reactions, the
    friction moment) equals the 3-D one within 1e-9 of each peak (measured 3e-13)."""

    def held(planar: bool) -> ml.Solution:
        m = fourbar_chain(1, planar=planar)
        m.add_force(ml.JointFriction("friction", "s0", mu=0.3, pin_radius=0.01))
        ends = (("link1", (0.2, -0.1, 0.0)), ("ground", (0.4, -0.1, 0.0)))
        m.add_force(ml.Spring("spring", points=ends, stiffness=50.0))
        m.add_force(ml.TorsionSpring("coil", "r0", stiffness=0.2))
        requests = _REQUESTS[:2] + [ml.ElementOutput("friction", "friction")]
        return ml.solve(m, ml.Static(), requests=requests, redundant="drop")

    _assert_same(held(True), held(False), 1e-9)


@pytest.mark.parametrize("kind", ["kinematic", "quasi-static"])
def test_driven_four_bar_matches_3d(kind: str) -> None:
    """Positions, velocities, accelerations, rocker rate, in-plane reactions and the drive
    torque of the driven four-bar, planar against 3-D, within 1e-9 of each peak; the
    out-of-plane reaction components of the planar run are 0 and a note says so."""
    cls = ml.Kinematic if kind == "kinematic" else ml.QuasiStatic
    planar = _solve(_driven(), cls(end=0.5, step=0.05))
    space = _solve(_driven(planar=False), cls(end=0.5, step=0.05))
    _assert_same(planar, space, 1e-9)
    assert all(np.all(planar.channels[f"pin.{c}"] == 0.0) for c in ("fz", "tx", "ty"))
    assert any("out-of-plane reaction components (fz, tx, ty)" in w for w in planar.warnings)


def _swinging(planar: bool, analysis: ml.Dynamic) -> ml.Solution:
    """The free four-bar swinging under gravity from 2 rad/s at its crank."""
    m = fourbar_chain(1, planar=planar)
    m.add_point("p", body="coupler0", at=(0.1, -0.2, 0.0))
    return _solve(m, analysis, initial=[ml.InitialValue(joint="r0", rate=2.0)])


def test_swinging_four_bar_matches_3d() -> None:
    """Radau at tolerance 1e-9 over 0.05 s: every in-plane column (positions, velocities,
    accelerations, reactions) within 1e-9 of its peak (measured 3e-13): the planar
    equations of motion are the 3-D ones in the plane."""
    analysis = ml.Dynamic(end=0.05, step=0.01, tolerance=1e-9, integrator="radau")
    _assert_same(_swinging(True, analysis), _swinging(False, analysis), 1e-9)


def test_generalized_alpha_agrees_at_its_accuracy() -> None:
    """Generalized-alpha at the default tolerance (1e-6) over 0.2 s: the two integrations
    (different coordinates, different local errors) agree in position within 1e-6 of the
    peak (measured 2e-7) and in velocity within 1e-5 (measured 1.8e-6)."""
    analysis = ml.Dynamic(end=0.2, step=0.02)
    planar, space = _swinging(True, analysis), _swinging(False, analysis)
    for name, tol in (("p.x", 1e-6), ("p.y", 1e-6), ("v.x", 1e-5), ("v.y", 1e-5)):
        column = space.channels[name]
        assert np.abs(planar.channels[name] - column).max() <= tol * np.abs(column).max()


@pytest.mark.parametrize("plane", ["yz", "xz"])
def test_other_planes_give_the_same_results_rotated(plane: str) -> None:
    """The driven four-bar laid out in yz or xz (e1, e2 in place of x, y) gives the xy
    results with the components turned: x -> e1, y -> e2, tz -> t_n (1e-9 of the peak)."""
    reference = _solve(_driven(), ml.QuasiStatic(end=0.3, step=0.1))
    turned = _solve(_driven(plane), ml.QuasiStatic(end=0.3, step=0.1))
    e1, e2, n = (int(np.argmax(v)) for v in plane_axes(plane))
    for name, column in reference.channels.items():
        request, comp = name.rsplit(".", 1)
        axis = {"x": e1, "y": e2, "z": n}
        if comp in ("x", "y"):
            other = f"{request}.{'xyz'[axis[comp]]}"
        elif comp in ("fx", "fy"):
            other = f"{request}.f{'xyz'[axis[comp[1]]]}"
        elif comp == "tz":
            other = f"{request}.t{'xyz'[n]}"
        elif comp in ("value", "f", "t"):
            other = name
        else:
            continue
        peak = np.abs(column).max()
        assert np.abs(turned.channels[other] - column).max() <= 1e-9 * peak + _FLOOR, name


def test_refusals_name_the_joint() -> None:
    """A revolute whose axis is not the normal, and gravity along the normal, are refused
    before solving (ModelError naming the joint)."""
    m = fourbar_chain(1)
    m.add_joint(
        "tilted", "revolute", bodies=("coupler0", "link1"), at=(0.2, -0.15, 0.0), axis=(1, 0, 0)
    )
    with pytest.raises(ml.ModelError) as caught:
        make_system(m)
    assert caught.value.problems[0][0] == "tilted"
    m = fourbar_chain(1)
    m.gravity = (0.0, -9.81, 1.0)
    with pytest.raises(ml.ModelError, match="gravity has a component along z"):
        make_system(m)
