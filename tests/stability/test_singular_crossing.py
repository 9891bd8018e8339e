"""Through singular positions: the N-four-bar of the IFToMM multibody benchmark library
(problem A02: N parallelogram loops of 2N+1 links, 1 m and 1 kg each, gravity -y) crossing
its horizontal position, where the constraint Jacobian loses N ranks (the mechanism has
N+1 degrees of freedom there, 1 elsewhere); and a run that cannot progress (stall).

Reference: with parallelogram loops every crank turns by the same angle theta (from +x)
and every coupler translates, so the chain moves as one pendulum:
  I theta'' = -G cos theta,  I = (N+1)/3 + N (kg m^2),  G = g ((N+1)/2 + N) (N m),
solved by scipy's DOP853 at rtol = atol = 1e-12 (error below 1e-10 rad).
Each loop is crank i - spherical - coupler i - universal - crank i+1 (no redundant
equation), cranks on revolutes about z. The chain starts at theta0 = 0.4 rad turning at
-4 rad/s: it crosses the horizontal (theta = 0) at about t = 0.09 s.
"""

from __future__ import annotations

import math
import re
import time

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mechlib
from mechlib.solvers.assembly import InitialValue

from ..mechlib._models import G, Ramp, slider_crank

N = 3
THETA0, RATE0 = 0.4, -4.0
END = 0.2


def parallelogram_chain(n: int = N, theta0: float = THETA0) -> mechlib.Mechanism:
    """A02's N-four-bar with its cranks at theta0 (rad from +x); cranks a_i pinned at
    (i, 0, 0), couplers joining their tips (1 m apart)."""
    m = mechlib.Mechanism(name=f"n_four_bar_{n}", gravity=(0.0, -G, 0.0))
    c, s = math.cos(theta0), math.sin(theta0)
    for i in range(n + 1):
        m.add_body(f"crank{i}", mass=1.0, cm=(i + c / 2, s / 2, 0.0), inertia=[1 / 12] * 3)
        m.add_joint(
            f"a{i}", "revolute", bodies=(f"crank{i}", "ground"), at=(i, 0, 0), axis=(0, 0, 1)
        )
    for i in range(n):
        m.add_body(f"coupler{i}", mass=1.0, cm=(i + 0.5 + c, s, 0.0), inertia=[1 / 12] * 3)
        m.add_joint(f"b{i}", "spherical", bodies=(f"coupler{i}", f"crank{i}"), at=(i + c, s, 0))
        m.add_joint(
            f"c{i}",
            "universal",
            bodies=(f"crank{i + 1}", f"coupler{i}"),
            at=(i + 1 + c, s, 0),
            axes=((0, 0, 1), (0, 1, 0)),
        )
    return m


def pendulum_reference(times: np.ndarray, n: int = N) -> np.ndarray:
    """theta(t) (rad) of the one-degree-of-freedom chain (module docstring)."""
    inertia, moment = (n + 1) / 3 + n, G * ((n + 1) / 2 + n)
    sol = solve_ivp(
        lambda t, y: [y[1], -moment / inertia * math.cos(y[0])],
        (0.0, float(times[-1])),
        [THETA0, RATE0],
        t_eval=times,
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
    )
    return sol.y[0]


def _crossing(integrator: str, tolerance: float) -> tuple[mechlib.Solution, float]:
    requests = [mechlib.JointCoordinate(f"a{i}", f"a{i}", "angle") for i in range(N + 1)]
    start = time.process_time()
    sol = mechlib.solve(
        parallelogram_chain(),
        mechlib.Dynamic(end=END, step=0.01, tolerance=tolerance, integrator=integrator),
        requests=requests,
        initial=[InitialValue("a0", rate=RATE0)],
        throw=False,
    )
    return sol, time.process_time() - start


# measured maxima of |theta - reference| (rad) over the run, guarded at about 3x
@pytest.mark.parametrize(
    ("integrator", "tolerance", "bound"),
    [
        ("generalized-alpha", 1e-5, 3e-3),
        ("generalized-alpha", 1e-10, 3e-6),
        ("radau", 1e-5, 3e-5),
        ("radau", 1e-7, 1e-5),
    ],
)
def test_chain_crosses_its_horizontal_position(integrator, tolerance, bound) -> None:
    """Both integrators carry the chain through theta = 0 (Jacobian rank N short) at the
    loosest and tightest tolerances: the run finishes, every crank turns alike (the
    parallelogram branch is kept, spread < 1e-6 rad), the crank angle follows the
    one-degree-of-freedom reference within `bound`, and the crossing was warned as a
    near-singular position."""
    sol, _cpu = _crossing(integrator, tolerance)
    assert sol.ok, sol.message
    theta = THETA0 + sol.channels["a0.value"]
    assert theta.min() < -0.1 < 0.1 < theta.max()  # crossed, well past
    spread = max(
        np.abs(sol.channels[f"a{i}.value"] - sol.channels["a0.value"]).max()
        for i in range(1, N + 1)
    )
    assert spread < 1e-6
    error = np.abs(theta - pendulum_reference(sol.time)).max()
    assert error < bound, error
    assert any("near-singular" in w for w in sol.warnings), sol.warnings


@pytest.mark.parametrize("integrator", ["generalized-alpha", "radau"])
def test_motion_beyond_a_dead_point_stalls_with_the_joints_named(integrator) -> None:
    """A slider-crank (crank 0.1 m, rod 0.3 m) whose slider is pushed at 0.5 m/s cannot
    pass x = r + l, reached at t* = (0.4 - sqrt(0.08)) / 0.5 = 0.2343 s: the run fails
    there (not at its end, 0.4 s) naming the time, the motion and the loop's joints, and
    keeps the rows before t*."""
    mech, xs = slider_crank(0.1, 0.3)
    mech.add_motion("push", joint="D", function=Ramp(0.0, 0.5))
    t_star = (0.4 - xs) / 0.5
    sol = mechlib.solve(
        mech,
        mechlib.Dynamic(end=0.4, step=0.01, tolerance=1e-6, integrator=integrator),
        requests=[mechlib.JointCoordinate("x", "D", "travel")],
        throw=False,
    )
    assert sol.status == "failed"
    t_fail = float(re.search(r"at t = ([0-9.e+-]+) s", sol.message).group(1))
    assert abs(t_fail - t_star) < 0.011, sol.message
    assert all(name in sol.message for name in ("push", "A", "B", "C")), sol.message
    assert len(sol.time) == 24 and sol.time[-1] == pytest.approx(0.23)
    assert np.abs(sol.channels["x.value"] - 0.5 * sol.time).max() < 1e-9


def test_a_long_chain_crosses_at_a_tolerance_near_round_off() -> None:
    """N = 20 at tolerance 2.44e-10 (the fourth halving of `accuracy` from 1e-6): at the
    crossing Newton's increments stagnate at round-off amplified by the near-singular
    iteration matrix (1e-12 of the coordinates' scale, the same at every step size), which
    failed the convergence test tied to the tolerance: the run stalled at t = 0.089 s with
    steps below 5e-13 s. Round-off now counts as converged: the run finishes, and the crank
    angle follows the one-degree-of-freedom reference (measured 1.34e-6 rad, guarded at
    4e-6: the truncation error of 447 steps)."""
    sol = mechlib.solve(
        parallelogram_chain(20),
        mechlib.Dynamic(end=END, step=0.01, tolerance=1e-6 / 8**4),
        requests=[mechlib.JointCoordinate("a0", "a0", "angle")],
        initial=[InitialValue("a0", rate=RATE0)],
        throw=False,
    )
    assert sol.ok, sol.message
    theta = THETA0 + sol.channels["a0.value"]
    assert theta.min() < -0.1 < 0.1 < theta.max()
    assert np.abs(theta - pendulum_reference(sol.time, 20)).max() < 4e-6
