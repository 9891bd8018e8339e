"""The flexible benchmark's models (benchmarks.flexible) are the ones the docs describe: the
slider-crank's rod reduced to 34 modes between 460 Hz and 40 kHz and one degree of freedom
(driven: the modes left), and Kane's beam the same as tests/mechlib/test_flexible_stiffening.py's
(first clamped frequency 3.80 rad/s, within 1e-3 of 3.516 sqrt(E I / (rho A L^4))). No
timing."""

from __future__ import annotations

import math

import pytest

from benchmarks.flexible import SpinUp, flexible_slider_crank, spin_up_beam
from mechlib.checks.model_check import inspect_mechanism


def test_flexible_slider_crank_model():
    mech = flexible_slider_crank()
    comp = mech.flexible["rod"].component
    assert comp.count == 34
    hz = comp.frequencies / (2 * math.pi)
    assert hz[0] == pytest.approx(460.0, rel=1e-3) and hz[-1] == pytest.approx(39890.0, rel=1e-3)
    check = inspect_mechanism(mech)
    assert check.assembled and not check.redundant
    assert check.degrees_of_freedom == comp.count  # the modes: the drive takes the crank's


def test_spin_up_beam_model():
    comp = spin_up_beam(True).flexible["beam"].component
    assert comp.geometric is not None and comp.count == 4
    ei, rho_a, length = 7e10 * 2e-7, 3000.0 * 4e-4, 10.0
    held = 3.516 * math.sqrt(ei / (rho_a * length**4))
    assert comp.held_frequency == pytest.approx(held, rel=1e-3)
    assert SpinUp().rate(15.0) == pytest.approx(4.0) and SpinUp().accel(20.0) == 0.0
