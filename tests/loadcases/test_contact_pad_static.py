"""The user path of a static analysis on a contact: tests/loadcases/contact/pad_static.case.yaml
(a 1 kg ball on an impact pad k x^1.5, k = 9.81e6 N/m^1.5) through `loadcases.run.run_file`,
starting touching and 10 mm (100 static deflections) apart. Reference (force balance):
penetration (m g / k)^(1/1.5) = 0.1 mm, contact force m g; tolerance 1e-9 relative (brief
1e-6; measured below 1e-10, mechlib's static Newton stopping at 1e-10 of the weight).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.run import run_file

CASE = Path(__file__).resolve().parent / "contact" / "pad_static.case.yaml"
DEFLECTION = 1.0e-4  # m


@pytest.mark.parametrize("gap", [0.0, 10.0])
def test_ball_rests_on_the_pad_at_its_static_deflection(tmp_path: Path, gap: float) -> None:
    """`gap` (mm) between the ball and the pad at design."""
    path = tmp_path / "pad_static.case.yaml"
    text = CASE.read_text(encoding="utf-8")
    path.write_text(
        text.replace("{pad_height: 0 mm}", f"{{pad_height: {-gap} mm}}"), encoding="utf-8"
    )
    sol = run_file(path, output_dir=tmp_path / "out")[0].solution
    assert sol.ok, sol.message
    assert sol.channels["pad_penetration.value"][0] == pytest.approx(DEFLECTION, rel=1e-9)
    assert sol.channels["pad_force.normal"][0] == pytest.approx(9.81, rel=1e-9)
    assert sol.channels["centre.z"][0] == pytest.approx(0.01 - gap * 1e-3 - DEFLECTION, abs=1e-13)
