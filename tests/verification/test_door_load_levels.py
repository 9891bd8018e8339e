"""Door set (seed 000, thesis 4.2): the 1334 N handle jam load is an ultimate load, so the
jam cases are `level: ultimate` and the set's `ultimate: 1.5` must not multiply them again:
P7P10's ultimate load in the envelope is its computed value (not 1.5 x it), its limit load
the computed value / 1.5. Reference: the run's own computed peak (the 1.5 must not appear);
tolerance 1e-15 relative (one division and one multiplication by 1.5)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import estimate_off

from loadcases.inputs.loader import load_case, load_set
from loadcases.report.sizing import size_runs
from loadcases.results.saved import saved_run_of
from loadcases.run import run_case

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"


def test_jam_loads_are_factored_once():
    cf = estimate_off(load_case(DOOR / "jam_outer_handle.case.yaml"))
    assert cf.case.level == "ultimate"
    outcome = run_case(cf, abscissa=True)
    assert outcome.solution.ok, outcome.solution.message
    run = saved_run_of(outcome)
    computed = float(run.channels["rod_p7p10.f"].max())
    assert computed == pytest.approx(8183.0, rel=1e-3)  # README: 8183 N at 0 deg, gravity on
    model = load_set(DOOR / "door.set.yaml").model
    assert model.factors["ultimate"] == 1.5
    row = next(r for r in size_runs([run], model).rows if r.column == "rod_p7p10.f")
    assert row.ultimate_max == pytest.approx(computed, rel=1e-15)  # not 1.5 x 8183 = 12275 N
    assert row.max == pytest.approx(computed / 1.5, rel=1e-15)
    assert row.max_level == "ultimate"


def test_every_jam_case_of_the_door_set_is_ultimate_and_no_other():
    """The set's cases at ultimate level are exactly the jam cases (the handle load 1334 N)."""
    for path in sorted(DOOR.glob("*.case.yaml")):
        level = load_case(path).case.level
        assert level == ("ultimate" if path.name.startswith("jam_") else "limit"), path.name
