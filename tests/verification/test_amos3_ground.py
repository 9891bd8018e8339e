"""AMOS-3-like wing on ground, full-flexible (loadcases/library/solar_array/
amos3_ground_flex.mech.yaml, seed 003 3.4.3): air loads at the panels' central nodes
(load points) and support brackets welded to the panels, checked by hand statics on the
deployed wing held at its latch angles (amos3_ground_flex_static.case.yaml).

By hand, deployed (yoke +90 deg about HL1 at (0, 40) mm, panel 1 at -90 deg, panel 2 at
+90 deg absolute): HL2 at (-20, 1640), HL3 at (0, 3240), the panels' centres at (-10, 2440)
and (-10, 4040), the brackets above them, the yoke's cm at (0, 840) mm. Each panel takes
p A = 10 Pa x 1.92 m^2 = 19.2 N along +x at its centre:
- forces, exact whatever the deflection (the loads keep their directions): the SADM
  reaction on the yoke is -2 p A along x, 0 along y and the whole weight M g along z
  (M = yoke rho A L + 2 (panel rho V + bracket)); HL2 passes both panels' air load; a
  bracket's weld carries its own weight m_b g (1e-9);
- moments about the hinge lines (z), by the design levers: sum -(y - y_hinge) p A of the
  panels outboard, and the deployment spring's torque k (theta - theta0) of that hinge
  line (the harness is 0 at the latch angles, the CCL strands slack): within 2e-3, the
  deflection's change of the levers (measured 3.1e-4, 1.3e-3 and 5.1e-4 at HL1-HL3; the
  panels' centres sit 0.5 and 1.5 mm nearer the SADM than by the design levers);
- the weight's moment about x at HL1, g sum m (y - 40 mm): within 1e-3 (measured 1.1e-4).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

CASE = (
    Path(__file__).resolve().parents[2]
    / "loadcases"
    / "library"
    / "solar_array"
    / "amos3_ground_flex_static.case.yaml"
)
G, AIR = 9.81, 10.0 * 1.6 * 1.2  # m/s^2, N per panel
M_YOKE = 5145.2 * 3.6442e-4 * 1.6  # kg, the beam's rho A L
M_PANEL, M_BRACKET = 110.417 * 1.6 * 1.2 * 0.025, 0.2  # kg
Y_HL1, Y_HL2, Y_HL3, Y_P1, Y_P2, Y_YOKE = 0.04, 1.64, 3.24, 2.44, 4.04, 0.84  # m, deployed


def _spring(k: float, angle: float, windup: float) -> float:
    """The deployment spring's torque k (theta - theta0) (N*m) at its latch angle (deg)."""
    return k * math.radians(angle - windup)


def test_air_loads_and_brackets_reach_the_supports_by_hand_statics() -> None:
    c = {k: float(v[-1]) for k, v in run_case(load_case(CASE)).solution.channels.items()}
    mass = M_YOKE + 2.0 * (M_PANEL + M_BRACKET)
    assert c["sadm.fx"] == pytest.approx(-2.0 * AIR, rel=1e-9)
    assert abs(c["sadm.fy"]) < 1e-9 * AIR
    assert c["sadm.fz"] == pytest.approx(mass * G, rel=1e-9)
    assert c["hl2_force.fx"] == pytest.approx(-2.0 * AIR, rel=1e-9)
    assert c["bracket_1.fz"] == pytest.approx(M_BRACKET * G, rel=1e-9)
    # the holding efforts: the air's moment about each hinge line and its spring's torque
    air_hl1 = AIR * ((Y_P1 - Y_HL1) + (Y_P2 - Y_HL1))
    air_hl2 = AIR * ((Y_P1 - Y_HL2) + (Y_P2 - Y_HL2))
    air_hl3 = AIR * (Y_P2 - Y_HL3)
    assert abs(c["hold_hl1.value"]) == pytest.approx(air_hl1 + _spring(0.5, 90.0, 270.0), rel=2e-3)
    assert abs(c["hold_hl2.value"]) == pytest.approx(
        air_hl2 + _spring(0.5, -180.0, -360.0), rel=2e-3
    )
    assert abs(c["hold_hl3.value"]) == pytest.approx(
        air_hl3 + _spring(0.25, 180.0, 360.0), rel=2e-3
    )
    weight_moment = G * (
        M_YOKE * (Y_YOKE - Y_HL1) + (M_PANEL + M_BRACKET) * (Y_P1 - Y_HL1 + Y_P2 - Y_HL1)
    )
    assert c["sadm.tx"] == pytest.approx(weight_moment, rel=1e-3)
