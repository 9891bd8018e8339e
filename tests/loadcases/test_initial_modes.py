"""A flexible body started deformed (issue 35 item 5): `initial: {BODY: {modes, rates}}`.

References (closed forms of the 0.8 m, 30 x 10 mm aluminium Timoshenko cantilever of
test_flexible_yaml.py, 5 N at its tip):
- the static tip deflection delta = P L^3/(3 E I) + P L/(k G A);
- released from that shape, the tip moves as the Euler-Bernoulli modal series
  w(L, t) = sum_n a_n phi_n(L) cos(omega_n t) of the static shape P x^2 (3 L - x) / (6 E I)
  (clamped-free modes, Blevins Table 8-1; six terms): its first zero crossing;
- started undeformed with the static shape's modal coordinates per second as rates, the
  tip's velocity is delta per second.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import null_space
from scipy.optimize import brentq

from loadcases.build.model import build_run
from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case
from mechlib.solvers.assembly import assemble
from mechlib.system.planar import make_system

E, G, WIDTH, HEIGHT, L, P, RHO = 70e9, 70e9 / 2.66, 0.03, 0.01, 0.8, 5.0, 2700.0
IY, AREA = WIDTH * HEIGHT**3 / 12.0, WIDTH * HEIGHT
DELTA = P * L**3 / (3 * E * IY) + P * L / (5.0 / 6.0 * G * AREA)
COUNT = 12 + 2 - 6  # modes: six per interface node and the fixed-interface ones, less six
BETA_L = (1.875104, 4.694091, 7.854757, 10.995541, 14.137168, 17.278760)  # clamped-free


def _series_crossing() -> float:
    """The first zero (s) of the Euler-Bernoulli tip series released from the static
    tip-load shape (a_n by quadrature of the shape on each mode)."""
    x = np.linspace(0.0, L, 4001)
    static = x**2 * (3 * L - x)
    terms = []
    for bl in BETA_L:
        b = bl / L
        sigma = (math.cosh(bl) + math.cos(bl)) / (math.sinh(bl) + math.sin(bl))
        phi = np.cosh(b * x) - np.cos(b * x) - sigma * (np.sinh(b * x) - np.sin(b * x))
        a = np.trapezoid(static * phi, x) / np.trapezoid(phi * phi, x)
        omega = bl**2 * math.sqrt(E * IY / (RHO * AREA * L**4))
        terms.append((a * phi[-1], omega))
    return float(
        brentq(lambda t: sum(c * math.cos(w * t) for c, w in terms), 1e-4, math.pi / terms[0][1])
    )


CASE = """\
case: flexible-cantilever
mechanism:
  units: {length: mm}
  bodies:
    beam:
      flexible:
        beam:
          start: [0, 0, 0]
          end: [800, 0, 0]
          section: {width: 30, height: 10}
          material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}
          elements: 4
          y_axis: [0, 1, 0]
        interface: {root: [0, 0, 0], tip: [800, 0, 0]}
        fixed_interface_modes: 2
        damping: 0
  joints:
{joints}
  forces:
    load: {type: force, point: beam.tip, value: [0, 0, 5]}
{case}
requests:
  tip: {point: beam.tip, quantity: position}
  tip_speed: {point: beam.tip, quantity: velocity}
  modal: {flexible: beam, quantity: modes}
"""


CLAMP = "    clamp: {type: fixed, bodies: [beam, ground], at: [0, 0, 0]}"


def _text(case: str, joints: str = CLAMP) -> str:
    return CASE.replace("{case}", case).replace("{joints}", joints)


def _run(tmp_path: Path, case: str, joints: str = CLAMP):
    path = tmp_path / "flex.case.yaml"
    path.write_text(_text(case, joints), "utf-8")
    return run_case(load_case(path)).solution


def _static_modes(tmp_path: Path) -> list[float]:
    channels = _run(tmp_path, "analysis: {type: static}").channels
    return [float(channels[f"modal.q{j}"][0]) for j in range(1, COUNT + 1)]


def _listed(values: list[float]) -> str:
    return "[" + ", ".join(repr(v) for v in values) + "]"


def test_released_from_its_static_shape(tmp_path: Path) -> None:
    """Tip at delta at t = 0 (measured 8.2e-5 off, the static run's own error) and at rest;
    its first zero crossing as the modal series' (measured 1.7e-4 late; a quarter of the
    first period would be 1.7 % late: the higher modes of the static shape)."""
    modes = _static_modes(tmp_path)
    quarter = _series_crossing()
    sol = _run(
        tmp_path,
        f"loads: []\ninitial:\n  beam: {{modes: {_listed(modes)}}}\n"
        f"analysis: {{type: dynamic, end: {1.5 * quarter:.6f}, step: 1e-4}}",
    )
    z, t = sol.channels["tip.z"], sol.time
    assert z[0] == pytest.approx(DELTA, rel=1e-3)
    assert abs(sol.channels["tip_speed.z"][0]) < 1e-9
    assert [float(sol.channels[f"modal.q{j}"][0]) for j in range(1, COUNT + 1)] == pytest.approx(
        modes, rel=1e-12, abs=1e-15
    )
    i = int(np.flatnonzero(z < 0.0)[0])
    crossing = t[i - 1] + (t[i] - t[i - 1]) * z[i - 1] / (z[i - 1] - z[i])
    assert crossing == pytest.approx(quarter, rel=1e-3)
    assert not [w for w in sol.warnings if "changed from" in w]


def test_rates_set_the_deformation_rate(tmp_path: Path) -> None:
    """The static shape's modal coordinates per second as rates: the undeformed tip moves
    at delta per second (measured 6.1e-5 off)."""
    modes = _static_modes(tmp_path)
    sol = _run(
        tmp_path,
        f"loads: []\ninitial:\n  beam: {{rates: {_listed(modes)}}}\n"
        "analysis: {type: dynamic, end: 1e-4, step: 1e-4}",
    )
    assert sol.channels["tip_speed.z"][0] == pytest.approx(DELTA, rel=1e-3)
    assert sol.channels["tip.z"][0] == pytest.approx(0.0, abs=1e-12)


def test_modes_the_constraints_contradict_are_reported(tmp_path: Path) -> None:
    """With its tip held as well, the static shape cannot be taken: the assembly projects
    the given modes onto the constraints and says so; with the tip free it says nothing."""
    modes = _static_modes(tmp_path)
    held = CLAMP + "\n    hold: {type: spherical, bodies: [beam.tip, ground], at: [800, 0, 0]}"
    sol = _run(
        tmp_path,
        f"loads: []\ninitial:\n  beam: {{modes: {_listed(modes)}}}\n"
        "analysis: {type: dynamic, end: 1e-4, step: 1e-4}",
        joints=held,
    )
    changed = [w for w in sol.warnings if "initial modal coordinate" in w]
    assert changed and "of body 'beam' changed from" in changed[0]
    assert abs(sol.channels["tip.z"][0]) < 1e-9


@pytest.mark.parametrize(
    "initial, key, message",
    [
        ("beam: {modes: [1, 2]}", "initial.beam.modes", "2 values given: body 'beam' has 8"),
        ("beam: {rates: [0, 0, 0]}", "initial.beam.rates", "3 values given"),
        ("clamp: {modes: [0]}", "initial.clamp.modes", "'clamp' is a joint"),
        ("beam: {value: 1}", "initial.beam", "'rates' and/or 'deformed'"),
        ("beam: {modes: [.nan]}", "initial.beam.modes", "finite"),
    ],
)
def test_modal_initial_errors(tmp_path: Path, initial: str, key: str, message: str) -> None:
    """Wrong counts and keys: an input error at the key's file, line and column."""
    case = f"initial:\n  {initial}\nanalysis: {{type: static}}"
    with pytest.raises(InputError) as raised:
        _run(tmp_path, case)
    (problem,) = [d for d in raised.value.diagnostics if d.key == key]
    assert message in problem.message
    line = _text(case).splitlines().index(f"  {initial}") + 1
    assert problem.file.endswith("flex.case.yaml") and problem.line == line


def test_an_interface_node_body_takes_a_velocity(tmp_path: Path) -> None:
    """`BODY.POINT` names the node body in `initial:` too (docs/flexible-bodies.md): the
    root node of a beam on a slider starts at the velocity given."""
    sol = _run(
        tmp_path,
        "loads: []\ninitial:\n  beam.root: {velocity: [0.5, 0, 0]}\n"
        "analysis: {type: dynamic, end: 1e-4, step: 1e-4}",
        joints="    slide: {type: prismatic, bodies: [beam.root, ground], at: [0, 0, 0], "
        "axis: [1, 0, 0]}",
    )
    assert sol.channels["tip_speed.x"][0] == pytest.approx(0.5, rel=1e-9)


def test_a_loaded_body_started_in_its_static_deflection_stays_there(tmp_path: Path) -> None:
    """The tip load on from t = 0: `deformed: static` starts the tip at delta (8.2e-5, the
    static run's own error) and it stays there (measured 2.1e-9 of delta over half a
    period since the step grows whenever the error law allows, 3e-12 before: round-off of
    the steps growing from rest); started straight, the same body swings to about 2 delta
    (1.97 measured)."""
    run = "analysis: {type: dynamic, end: 0.045, step: 5e-4}"
    still = _run(tmp_path, f"initial:\n  beam: {{deformed: static}}\n{run}").channels["tip.z"]
    swing = _run(tmp_path, run).channels["tip.z"]
    assert still[0] == pytest.approx(DELTA, rel=1e-3)
    assert np.abs(still - still[0]).max() < 1e-8 * DELTA
    assert swing.max() > 1.9 * DELTA


def test_modes_and_a_static_start_exclude_each_other(tmp_path: Path) -> None:
    case = "initial:\n  beam: {modes: [0, 0, 0, 0, 0, 0, 0, 0], deformed: static}\n"
    with pytest.raises(InputError, match="either 'modes' or 'deformed: static'"):
        _run(tmp_path, case + "analysis: {type: static}")


FREE = "    {}"  # no joints: the beam floats
_FREE_REQUESTS = """\
  root: {point: beam.root, quantity: position}
  root_speed: {point: beam.root, quantity: velocity}
  energy: {quantity: energy}
"""


@pytest.mark.parametrize("mode, ends, closeness", [(0, 1.0, 0.015), (1, -1.0, 0.03)])
def test_free_body_given_a_modal_rate_keeps_its_momentum(
    tmp_path: Path, mode: int, ends: float, closeness: float
) -> None:
    """A free beam given only a rate of 0.01 kg^0.5 m/s in its first (symmetric) or second
    (antisymmetric) free-free bending mode: no rigid motion joins it (its momentum and
    angular momentum stay zero), so the kinetic energy is the mode's own, rate^2 / 2 (the
    modes are mass-normalised), and the ends move alike (mode 1) or opposite (mode 2) at
    rate x 2 / sqrt(rho A L), the Euler-Bernoulli free-free mode's mass-normalised end
    value (Blevins Table 8-1; the 4-element Timoshenko beam measured 1.03 % and 2.10 % above
    it). Before the node bodies were left out of the initial velocities' norm, the first
    started with 2.8 times that energy and drifted 0.8 mm in 0.05 s, its end speed 0.0084."""
    rate = 0.01
    rates = [rate if j == mode else 0.0 for j in range(COUNT)]
    text = _text(
        f"loads: []\ninitial:\n  beam: {{rates: {_listed(rates)}}}\n"
        "analysis: {type: dynamic, end: 0.05, step: 1e-3}",
        FREE,
    ).replace("requests:\n", "requests:\n" + _FREE_REQUESTS)
    path = tmp_path / "free.case.yaml"
    path.write_text(text, "utf-8")
    channels = run_case(load_case(path)).solution.channels
    assert channels["energy.kinetic"][0] == pytest.approx(rate**2 / 2.0, rel=1e-9)
    root, tip = channels["root_speed.z"][0], channels["tip_speed.z"][0]
    assert tip == pytest.approx(ends * root, rel=1e-9)
    end_value = 2.0 / math.sqrt(RHO * AREA * L)
    assert abs(root) == pytest.approx(rate * end_value, rel=closeness)
    amplitude = rate * end_value / (22.373 / L**2 * math.sqrt(E * IY / (RHO * AREA)))
    assert abs(float(np.mean(channels["root.z"]))) < 0.05 * amplitude


TIP_MASS = """\
    mass: {mass: 5.0, cm: [850, 0, 0], inertia: [1.0e-4, 1.0e-4, 1.0e-4]}
"""


def test_free_body_with_a_rigid_mass_keeps_its_momentum(tmp_path: Path) -> None:
    """The free beam with a 5 kg mass welded at its tip, given only the first mode's rate:
    the mechanism's linear momentum is zero at the start and its kinetic energy the least
    the constraints and the given rate allow, computed here independently (the minimum of
    qd^T M qd over the null space of [phi_q; the modal rows], scipy's null_space). When
    only the flexible body's own mass counted, the frame and the tip mass split the tip's
    modal velocity equally: 3.7 times that energy and a drift of -6.2 mm/s."""
    rates = [0.01 if j == 0 else 0.0 for j in range(COUNT)]
    text = _text(
        f"loads: []\ninitial:\n  beam: {{rates: {_listed(rates)}}}\n"
        "analysis: {type: dynamic, end: 1e-3, step: 1e-3}",
        "    weld: {type: fixed, bodies: [mass, beam.tip], at: [800, 0, 0]}",
    ).replace("    beam:\n      flexible:", TIP_MASS + "    beam:\n      flexible:", 1)
    path = tmp_path / "tip_mass.case.yaml"
    path.write_text(text, "utf-8")
    built = build_run(load_case(path))
    system = make_system(built.mechanism)
    start = assemble(system, 0.0, built.initial)
    k = system.kin(start.q, None, 0.0)
    mass, jacobian = system.mass(k), system.phi_q(k)
    momentum = sum((mass @ start.qd)[7 * b : 7 * b + 3] for b in range(system.nb))
    assert np.abs(momentum).max() < 1e-9 * 5.0 * 0.01
    modal = np.zeros((COUNT, system.nq))
    modal[np.arange(COUNT), np.arange(system.nq - COUNT, system.nq)] = 1.0
    rows = np.vstack([jacobian, modal])
    given = np.concatenate([system.nu(k), rates])
    particular = np.linalg.lstsq(rows, given, rcond=None)[0]
    free = null_space(rows)
    least = particular + free @ np.linalg.solve(free.T @ mass @ free, -free.T @ mass @ particular)
    assert start.qd @ mass @ start.qd == pytest.approx(least @ mass @ least, rel=1e-9)
