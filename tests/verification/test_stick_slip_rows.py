"""Output rows at joint-friction stick/slip switches (issue 37: single-row SADM force spikes
of the semi-flexible BepiColombo hot run at the holding friction's switches).

A wheel (I = 0.1 kg*m^2, no gravity) on an axle with a friction preload of 1 N*m (mu 0),
driven by T(t) = A sin(2 pi t) N*m: held until |T| = 1 N*m, then sliding against 1 N*m
until its rate is zero again, held there while |T| <= 1 N*m, and so on. A = 2 N*m: held to
t = 1/12 s, then it slides to the end (its rate reverses without a hold); A = 1.2 N*m: two
holds and two slides.

- Every row is the motion the integrator solved with the friction state of its step: a
  held row carries the drive (friction torque = T(t)), a sliding row the full 1 N*m. Rows
  of the step at whose end the joint let go were recorded after the switch and read 0 N*m
  (the regularised law at zero rate): 15 rows of 2 ms in the last held step.
- The let-go is located within the step (where |T| reaches the capacity), not at the end
  of the step that passes it: with A = 2 the joint was held 20 ms past t = 1/12 s, angle
  error 2.1 % of the peak, now 0.63 % against the exact stick/slip motion below; with
  A = 1.2, 13.8 % before, 4.6 % now. What is left is the start of each slide: the run's
  rate is 0.007 rad/s ahead of the exact one 3 ms after the let-go and stays so (the
  friction law's start of slip, not located here); guarded at the measured values. That
  error follows the steps taken at each slide's start, not the tolerance: at tolerances
  0.7, 0.85, 1, 1.2, 1.4 x 1e-6 (the case's 1e-6 in the middle) A = 2 gave 0.42, 0.46,
  0.62, 0.54, 0.58 % and A = 1.2 4.2, 4.6, 4.6, 5.5, 5.9 %; since a step change carries
  the integrator's own velocity with the step (rules.constraint_velocity) 0.42, 0.46,
  0.50, 0.54, 0.75 % and 3.9, 4.6, 5.0, 5.0, 5.4 % (means 0.52 -> 0.53 %, 5.0 -> 4.8 %).
  So A = 1.2 is bounded at 6 % (it read 4.6 % below the former 5 % at 1e-6 by luck).

Reference: an independent integration (SciPy DOP853, rtol 1e-12) with exact switching:
held while |T| <= 1 N*m, I w' = T - sign(w) 1 N*m while sliding, a stop where w = 0.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from loadcases.run import run_file

INERTIA, PRELOAD, END = 0.1, 1.0, 1.0  # kg*m^2, N*m, s

CASE = """\
case: wheel-stick-slip
mechanism:
  name: wheel
  gravity: [0, 0, 0]
  bodies:
    wheel: {mass: 10.0, cm: [0, 0, 0], inertia: [0.05, 0.05, 0.1]}
  joints:
    axle: {type: revolute, bodies: [wheel, ground], at: [0, 0, 0], axis: [0, 0, 1]}
  forces:
    drive: {type: torque, body: wheel, value: [0, 0, "AMPLITUDE*sin(2*pi*t)"], frame: ground}
    rub: {type: joint_friction, joint: axle, mu: 0, pin_radius: 0.05, preload: 1.0}
analysis: {type: dynamic, end: 1.0, step: 0.002, accuracy: off}
requests:
  a: {joint: axle, quantity: angle}
  w: {joint: axle, quantity: omega}
  rub: {force: rub}
"""


def _exact_angle(times: np.ndarray, amplitude: float) -> np.ndarray:
    """The angle (rad) at `times` with exact stick/slip switching (module docstring)."""

    def _drive(t):
        return amplitude * np.sin(2.0 * math.pi * t)

    out = np.zeros_like(times)
    t, x = 0.0, 0.0
    while t < END:
        grid = np.linspace(t, END, 20001)
        over = np.abs(_drive(grid)) > PRELOAD
        if not over.any():
            out[times >= t] = x
            break
        k = int(np.argmax(over))
        start = brentq(lambda s: abs(_drive(s)) - PRELOAD, grid[k - 1], grid[k]) if k else t
        out[(times >= t) & (times <= start)] = x
        way = math.copysign(1.0, _drive(start + 1e-9))

        def stop(s, y, way=way, start=start):
            return y[1] if s > start + 1e-9 else way

        stop.terminal, stop.direction = True, -way  # type: ignore[attr-defined]
        slide = solve_ivp(
            lambda s, y, way=way: [y[1], (_drive(s) - way * PRELOAD) / INERTIA],
            (start, END),
            [x, 0.0],
            events=stop,
            rtol=1e-12,
            atol=1e-14,
            dense_output=True,
            method="DOP853",
        )
        inside = (times >= start) & (times <= slide.t[-1])
        out[inside] = slide.sol(times[inside])[0]
        t, x = float(slide.t[-1]), float(slide.y[0, -1])
    return out


@pytest.mark.parametrize("amplitude, bound, measured", [(2.0, 0.01, 0.0050), (1.2, 0.06, 0.050)])
def test_rows_carry_the_friction_state_of_their_step_and_the_let_go_is_located(
    tmp_path: Path, amplitude: float, bound: float, measured: float
) -> None:
    path = tmp_path / "wheel.case.yaml"
    path.write_text(CASE.replace("AMPLITUDE", str(amplitude)), encoding="utf-8")
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    sol = outcome.solution
    assert sol.status == "ok", sol.message
    t = sol.time
    rate, friction = sol.channels["w.value"], sol.channels["rub.value"]
    held = np.abs(rate) < 1e-12
    assert held.sum() > 40 and (~held).sum() > 200  # both states are exercised
    # a held row carries the drive, within the capacity
    drive = amplitude * np.sin(2.0 * math.pi * np.asarray(t))
    np.testing.assert_allclose(friction[held], drive[held], atol=1e-9)
    assert np.abs(friction[held]).max() <= PRELOAD * (1.0 + 1e-6)
    # a sliding row carries the full friction, against its rate (after the first 2 ms of
    # each slide, where the regularised law is still within its threshold rate)
    sliding = ~held & (np.abs(rate) > 0.02)
    np.testing.assert_allclose(friction[sliding], PRELOAD * np.sign(rate[sliding]), atol=1e-9)
    # the motion against the exact stick/slip motion, relative to the peak angle
    angle = sol.channels["a.value"]
    exact = _exact_angle(np.asarray(t), amplitude)
    error = np.abs(angle - exact).max() / np.abs(exact).max()
    assert error < bound  # guard at the measured value (2026-11-29)
    assert error == pytest.approx(measured, rel=0.2)
