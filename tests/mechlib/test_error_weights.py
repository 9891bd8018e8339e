"""Per-state error weights (issue 35 item 1): the scale of each state by its element's
data (mechlib.solvers.error_weights), and the local error estimate of element states
(mechlib.elements.states.ElementStates.local_error) against the trapezoidal rule's true
local error on a closed form."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import ClassVar

import numpy as np
import pytest

from mechlib.elements.contact.clearance import ClearanceJoint
from mechlib.elements.hydraulics import ServoActuator
from mechlib.elements.states import ElementStates
from mechlib.solvers.error_weights import element_state_scales, modal_scales


class _Decay:
    """dz/dt = (F0 - z) / tau: z(t + h) = F0 + (z(t) - F0) exp(-h / tau)."""

    n_states = 1
    tau, F0 = 0.1, 4.0
    output_units: ClassVar[dict[str, str]] = {}

    def initial_states(self) -> list[float]:
        return [0.0]

    def state_rates(self, view, z) -> list[float]:
        return [(self.F0 - z[0]) / self.tau]


def _exact(z: float, h: float) -> float:
    return _Decay.F0 + (z - _Decay.F0) * math.exp(-h / _Decay.tau)


@pytest.mark.parametrize(("k", "h"), [(0.001, 0.001), (0.0008, 0.0012), (0.0016, 0.0004)])
def test_state_local_error_estimate_matches_the_trapezoid_error(k: float, h: float) -> None:
    """After a step k, the estimate of a step h within 2 % of trial - exact (the trapezoid's
    true local error; the estimate's own error is O(h / tau) relative: measured within 1.1 %)."""
    states = ElementStates([_Decay()])
    states.start(None)
    states.advance(None, k)
    assert states.local_error(k) is None  # no history yet: no estimate
    states.accept(None)
    states.advance(None, h)
    true = states.trial[0] - _exact(states.z[0], h)
    estimate = states.local_error(h)
    assert estimate is not None
    assert estimate[0] / true == pytest.approx(1.0, abs=0.02)


def test_element_state_scales_come_from_the_element_data() -> None:
    """Valve servo: integral by the stroke span (m s), opening 1, its rate 2 pi f_v, both
    pressures by the supply pressure; a clearance joint's wear work (no force reads it) and
    an element without declared scales take no part (infinite)."""
    servo = ServoActuator("a", (("g", (0, 0, 0)), ("g", (1, 0, 0))), lambda t: 0.0)
    lo, hi = servo.cylinder.stroke
    w = 2.0 * math.pi * servo.valve.frequency
    p = servo.supply.pressure
    scales = element_state_scales([servo, _Decay()], 6)
    assert np.allclose(scales[:5], [hi - lo, 1.0, w, p, p])
    assert math.isinf(scales[5])
    assert ClearanceJoint.states_drive_forces is False
    clearance = SimpleNamespace(n_states=1, states_drive_forces=False, state_scales=lambda: [1.0])
    assert math.isinf(element_state_scales([clearance], 1)[0])


def test_modal_scale_is_the_body_mass_moved_by_the_mechanism_size() -> None:
    """A two-mode component of 4 kg in a 0.5 m mechanism: sqrt(4) x 0.5 = 1 kg^0.5 m per
    mode (a modal coordinate of mass-normalised modes moving the body's mass by the size)."""
    component = SimpleNamespace(frequencies=np.array([10.0, 40.0]), mass=4.0)
    assert np.allclose(modal_scales(component, 0.5), [1.0, 1.0])
