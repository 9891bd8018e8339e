"""Some rows of the constraint Jacobian without the others (mechlib.system.rows_jacobian):
the rows of a joint, of a motion (the coordinate block) and all rows equal System.phi_q's
bit for bit, at a bent, turning state of Kane's beam (a flexible body: its weld rows are
the groups left out); joint friction reads its reaction from them at the columns of a
differenced tangent."""

from __future__ import annotations

import numpy as np

from .test_stiffening_reactions import _spinning_system


def test_rows_equal_the_whole_jacobian_bit_for_bit():
    system, k, _ = _spinning_system(False)
    whole = system.phi_q(k)
    owners = system.owners
    for owner in ("hub", "spin"):
        rows = np.array([i for i, o in enumerate(owners) if o == owner])
        assert rows.size
        np.testing.assert_array_equal(system.phi_q_rows(k, rows), whole[rows])
    every = np.arange(len(owners))
    np.testing.assert_array_equal(system.phi_q_rows(k, every), whole)


def test_a_view_takes_the_rows_of_the_whole_jacobian_when_known():
    """With phi_q given, the view's rows are its rows; without, computed alike."""
    system, k, lam = _spinning_system(False)
    rows = system.joint_force_rows("hub")[0]
    given = system.view(k, lam, system.phi_q(k)).jacobian_rows(rows)
    np.testing.assert_array_equal(system.view(k, lam).jacobian_rows(rows), given)
    np.testing.assert_array_equal(
        system.view(k, lam).reaction_force("hub"),
        system.view(k, lam, system.phi_q(k)).reaction_force("hub"),
    )
