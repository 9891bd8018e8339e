"""The bodies a force or torque of a case depends on (`state_bodies`, mechlib.system.fd_columns),
from the measures its value expressions read: a joint measure reads the joint's two bodies,
a point measure the point's body (a flexible body's interface node), `effort` reads the
multipliers and the whole Jacobian (unknown: evaluated in every column). On a flexible
cantilever the differenced stiffness, modal columns included, equals the one evaluating
every element in every column (round-off of the difference quotients: 4 eps sum |Q_e| / h).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import mechlib.solvers.static.balance
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case
from mechlib.solvers.static.balance import Balance
from mechlib.system.fd_columns import ColumnSkips, element_bodies
from mechlib.system.system import System
from tests.loadcases.test_flexible_yaml import CASE as FLEXIBLE
from tests.mechlib.test_fd_columns import EveryColumn, roundoff

CHAIN = """\
case: column-bodies
mechanism:
  bodies:
    arm: {mass: 1, cm: [0.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
    link: {mass: 1, cm: [1.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
    far: {mass: 1, cm: [2.5, 0, 0], inertia: [0.01, 0.1, 0.1]}
  points:
    on_arm: {body: arm, at: [0.5, 0.1, 0]}
    on_link: {body: link, at: [1.5, 0.1, 0]}
    on_far: {body: far, at: [2.5, 0.1, 0]}
  joints:
    h1: {type: revolute, bodies: [arm, ground], at: [0, 0, 0], axis: [0, 0, 1]}
    h2: {type: revolute, bodies: [link, arm], at: [1, 0, 0], axis: [0, 0, 1]}
    h3: {type: revolute, bodies: [far, link], at: [2, 0, 0], axis: [0, 0, 1]}
  forces:
    wire: {type: spring, points: [on_arm, on_far], stiffness: 100}
    twist: {type: torsion_spring, joint: h2, stiffness: 10}
    third: {type: force, point: on_far, value: [0, "10 * cos(angle(h1))", 0]}
    nested: {type: force, point: on_link, frame: arm,
             value: ["step(dist(on_arm, on_far), 2, 0, 3, 1)", "2 * vx(on_far) * t", 0]}
    plain: {type: torque, body: link, frame: far, value: [0, 0, "2 * t"]}
    pushed: {type: force, point: on_arm, value: [0, "0.1 * effort(hold)", 0]}
motions:
  hold: {joint: h1, value: "0.1 * t"}
analysis: {type: quasi-static, end: 1, step: 0.5}
requests:
  hold: {motion: hold, quantity: torque}
"""


def _system(tmp_path: Path, text: str) -> System:
    path = tmp_path / "bodies.case.yaml"
    path.write_text(text, encoding="utf-8")
    return System(build_run(load_case(path)).mechanism)


def test_bodies_from_the_value_expressions(tmp_path: Path) -> None:
    system = _system(tmp_path, CHAIN)
    arm, link, far, ground = (system.body_index(n) for n in ("arm", "link", "far", "ground"))
    expected = {
        "wire": {arm, far},
        "twist": {link, arm},
        "third": {far, arm, ground},  # angle(h1): a joint that does not touch far
        "nested": {link, arm, far},  # dist and vx inside step(); its frame's body arm
        "plain": {link, far},  # time only: its body and its frame's
        "pushed": None,  # effort(hold)
    }
    found = {name: element_bodies(e) for name, e in system.mechanism.forces.items()}
    assert found == {n: None if v is None else frozenset(v) for n, v in expected.items()}
    skips = ColumnSkips(system)
    forces = system.mechanism.forces
    assert id(forces["third"]) not in skips.skip(arm) and id(forces["third"]) in skips.skip(link)
    assert all(id(forces["pushed"]) not in skips.skip(b) for b in (arm, link, far))


def test_flexible_stiffness_with_modal_columns(tmp_path: Path, monkeypatch) -> None:
    """A force at the root node reading the tip node's height: both node bodies; the modal
    columns leave it out, and the stiffness is the same."""
    point = "  points:\n    tip_pt: {body: beam, at: [800, 0, 0]}\n"
    lift = '    lift: {type: force, point: beam.root, value: [0, "100 * z(tip_pt)", 0]}\n'
    text = FLEXIBLE.replace("{extra_body}\n", point).replace("  forces:\n", "  forces:\n" + lift)
    system = _system(tmp_path, text)
    lift = system.mechanism.forces["lift"]
    nodes = {system.point(p)[0] for p in ("beam.root", "tip_pt")}
    assert element_bodies(lift) == frozenset(nodes) and len(nodes) == 2
    assert id(lift) in ColumnSkips(system).skip(-1)
    rng = np.random.default_rng(3)
    q = system.design_q() + 1e-3 * rng.standard_normal(system.nq)
    lam = rng.standard_normal(system.phi(system.kin(q)).size)
    fast = Balance(system, 0.0, q).stiffness(q, lam)
    monkeypatch.setattr(mechlib.solvers.static.balance, "ColumnSkips", EveryColumn)
    full = Balance(system, 0.0, q).stiffness(q, lam)
    assert np.abs(fast - full).max() <= roundoff(system, system.kin(q), lam)
    assert np.abs(full[:, 7 * system.nb :]).max() > 0.0  # modal columns are there
