"""Structure and hinge in series (seed 003 eq. 2.7).

- linear hinge: K_tot = (1/K_s + 1/K_h)^-1 exactly (1e-12);
- a tabulated hinge law: the moment M returned for a turn phi splits phi into a hinge turn
  h with table(h) = M and a structure turn M / K_s (1e-12 rad), for a stiffening law;
- through a case: a rotor on a latch spring with `series_stiffness` has the mode
  sqrt(K_tot / I) / (2 pi), linear hinge and a linear table alike (1e-9 relative).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechlib.elements.series import SeriesLaw, series_stiffness
from mechlib.model.tables import Table


def test_linear_in_series() -> None:
    law = SeriesLaw(lambda h: 300.0 * h, 1200.0)
    for turn in (-0.1, 0.0, 0.02, 0.3):
        assert law(turn) == pytest.approx(
            series_stiffness(1200.0, 300.0) * turn, rel=1e-12, abs=1e-15
        )
    assert series_stiffness(1200.0, 300.0) == pytest.approx(240.0, rel=1e-15)


def test_stiffening_table_splits_the_turn() -> None:
    table = Table(
        "hinge", [-0.1, 0.0, 0.01, 0.03, 0.1], [-80.0, 0.0, 2.0, 20.0, 150.0], "linear", "error"
    )
    law = SeriesLaw(table, 2000.0)
    for turn in (-0.05, 0.005, 0.02, 0.06):
        moment = law(turn)
        hinge_turn = turn - moment / 2000.0
        assert table(hinge_turn) == pytest.approx(moment, rel=1e-12, abs=1e-9)
        assert abs(hinge_turn) <= abs(turn)


@pytest.mark.parametrize(
    "spring",
    [
        'stiffness: "300 N*m/rad", series_stiffness: "1200 N*m/rad"',
        'law: hinge, series_stiffness: "1200 N*m/rad"',
    ],
)
def test_mode_of_a_series_latch(tmp_path, spring: str) -> None:
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    case = tmp_path / "rotor.case.yaml"
    case.write_text(f"""\
case: series-rotor
mechanism:
  tables:
    hinge: {{x: [-1, 1], y: [-300, 300], interpolation: linear}}
  bodies:
    disc: {{mass: 1, cm: [0, 0, 0], inertia: [0.5, 0.5, 0.5]}}
  joints:
    hinge_joint: {{type: revolute, bodies: [disc, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
  forces:
    latch: {{type: torsion_spring, joint: hinge_joint, {spring}}}
analysis: {{type: modes}}
""")
    solution = run_case(load_case(case)).solution
    assert solution.ok, solution.message
    expected = math.sqrt(240.0 / 0.5) / (2 * math.pi)
    assert np.asarray(solution.channels["mode.frequency"])[0] == pytest.approx(expected, rel=1e-9)
