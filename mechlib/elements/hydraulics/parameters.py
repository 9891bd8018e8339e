"""Parameters of the hydraulic servo-actuator, SI units, with the library values.

The library values describe a small aerospace primary-flight-control actuator (3000 psi
supply, 10 cm^2 balanced piston, 100 mm stroke, 5 L/min servovalve rated at 70 bar valve
drop): typical magnitudes from docs/hydraulics.md, not the data of one product. The PI gains
are the seed thesis' (seed 004 section 6.2: K_p = 2 A/m, K_i = 0.02).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mechlib.elements.hydraulics.laws import chamber_volumes

__all__ = ["MU_0", "Controller", "Cylinder", "JetPipe", "ServoValve", "Supply", "TorqueMotor"]

BAR = 1.0e5  # Pa
MU_0 = 4.0e-7 * math.pi  # H/m, permeability of vacuum (the air gaps')


@dataclass(frozen=True)
class Supply:
    """Supply and return (tank) pressures, absolute (Pa); the vapour pressure that chamber
    pressures are floored at (Pa), smoothly over `floor_width` (Pa)."""

    pressure: float = 206.8 * BAR  # 3000 psi
    return_pressure: float = 5.0 * BAR
    vapour_pressure: float = 0.02 * BAR
    floor_width: float = 0.1 * BAR


@dataclass(frozen=True)
class Cylinder:
    """Double-acting cylinder. Chamber 1 (piston side, area_1, m^2) grows when the actuator
    extends, chamber 2 (rod side, area_2) shrinks. `stroke` (m): [retracted, extended]
    limits of the stroke x, measured from the design length (x = 0 there). Dead volumes
    (m^3) are the chamber volumes at the end of the stroke that empties them. `bulk_modulus`
    (Pa): the effective modulus of oil, hoses and cylinder. `leakage` (m^3/(s*Pa)): internal
    leakage across the piston. Friction: viscous (N*s/m) and Coulomb (N), the latter
    regularised as F_c tanh(v / coulomb_speed). End stops: one-sided spring (N/m) and damper
    (N*s/m) beyond the stroke limits."""

    area_1: float = 1.0e-3
    area_2: float = 1.0e-3
    stroke: tuple[float, float] = (-0.05, 0.05)
    dead_volume_1: float = 2.0e-5
    dead_volume_2: float = 2.0e-5
    bulk_modulus: float = 0.8e9
    leakage: float = 5.0e-13
    viscous_friction: float = 4000.0
    coulomb_friction: float = 0.0
    coulomb_speed: float = 1.0e-3
    stop_stiffness: float = 1.0e8
    stop_damping: float = 1.0e4

    def volumes(self, x: float) -> tuple[float, float]:
        """Chamber volumes (m^3) at stroke x (m), each at least a tenth of its dead volume
        (an end stop overrun never empties a chamber; laws.chamber_volumes)."""
        lo, hi = self.stroke
        a1, a2, d1, d2 = self.area_1, self.area_2, self.dead_volume_1, self.dead_volume_2
        return chamber_volumes(x, lo, hi, a1, a2, d1, d2)

    def hydraulic_stiffness(self, x: float) -> float:
        """k_h = beta (A1^2/V1 + A2^2/V2) (N/m): the oil columns with the valve closed."""
        v1, v2 = self.volumes(x)
        return self.bulk_modulus * (self.area_1**2 / v1 + self.area_2**2 / v2)


@dataclass(frozen=True)
class ServoValve:
    """Flow servovalve: rated flow (m^3/s) at rated current (A) and rated valve drop
    (Pa, both lands together), spool transfer function (frequency Hz, damping ratio), the
    pressure drop (Pa) below which the orifice law turns laminar (regularisation)."""

    rated_flow: float = 5.0 / 60000.0  # 5 L/min
    rated_pressure_drop: float = 70.0 * BAR  # 1000 psi
    rated_current: float = 0.01
    frequency: float = 100.0
    damping: float = 0.7
    transition_pressure: float = 1.0 * BAR

    @property
    def flow_gain(self) -> float:
        """K (m^3/(s*Pa^0.5)) of one land: Q = K x sr(dp), rated flow at half the rated drop."""
        return self.rated_flow / math.sqrt(0.5 * self.rated_pressure_drop)


@dataclass(frozen=True)
class Controller:
    """PI position controller: current i = sat(kp e + ki integral(e)) (A), e the stroke
    error (m); kp (A/m), ki (A/(m*s)); `current_limit` (A); anti-windup by conditional
    integration."""

    kp: float = 2.0
    ki: float = 0.02
    current_limit: float = 0.01


@dataclass(frozen=True)
class TorqueMotor:
    """Push-pull torque motor of a jet-pipe servovalve by its reluctance force (seed 004 eq.
    6.1, F = B^2 S / (2 mu0) per air gap): two gaps of `air_gap` g (m) and pole area
    `pole_area` S (m^2), polarised by a magnet of `magnet_mmf` M0 (A, ampere-turns), the
    control coils of `turns` N carrying the current i. The armature moves x = r x_j at the
    gaps (`gap_ratio` r, 1: from the jet tip x_j), closing one gap and opening the other:
    B1 = mu0 (M0 + N i) / (2 (g - x)), B2 = mu0 (M0 - N i) / (2 (g + x)) (Merritt,
    Hydraulic control systems, 1967, 5.2), and the force at the jet tip (virtual work)
    F = r S (B1^2 - B2^2) / (2 mu0) (N). About the centre it is k_i i + k_m x_j with
    k_i = r mu0 S M0 N / (2 g^2) (N/A) and the magnetic spring k_m = r^2 mu0 S M0^2 / (2 g^3)
    (N/m, negative stiffness)."""

    pole_area: float
    air_gap: float
    turns: float
    magnet_mmf: float
    gap_ratio: float = 1.0

    def force(self, current: float, jet: float) -> float:
        """Force (N) on the jet tip at coil current `current` (A) and jet deflection `jet`
        (m); the armature held off the poles at 0.99 of the gap (a touching pole would
        give an infinite flux density)."""
        g = self.air_gap
        x = min(max(self.gap_ratio * jet, -0.99 * g), 0.99 * g)
        b1 = MU_0 * (self.magnet_mmf + self.turns * current) / (2.0 * (g - x))
        b2 = MU_0 * (self.magnet_mmf - self.turns * current) / (2.0 * (g + x))
        return self.gap_ratio * self.pole_area * (b1 * b1 - b2 * b2) / (2.0 * MU_0)

    @property
    def current_gain(self) -> float:
        """k_i (N/A): dF/di at the centre."""
        g = self.air_gap
        return self.gap_ratio * MU_0 * self.pole_area * self.magnet_mmf * self.turns / (2 * g * g)

    @property
    def magnetic_stiffness(self) -> float:
        """k_m (N/m): dF/dx_j at the centre with no current (the force pulls outwards)."""
        r, g = self.gap_ratio, self.air_gap
        return r * r * MU_0 * self.pole_area * self.magnet_mmf**2 / (2.0 * g**3)


@dataclass(frozen=True)
class JetPipe:
    """Torque motor, jet pipe and spool of a jet-pipe servovalve (seed 004 eqs. 6.1-6.3).

    Jet pipe tip: equivalent mass `jet_mass` (kg), hinge stiffness `hinge_stiffness` (N/m)
    and damping `hinge_damping` (N*s/m); torque-motor force gain `motor_gain` (N/A, None:
    the gain that puts the spool at `rated_opening` at rated current); feedback wire
    `wire_stiffness` (N/m). Receiver: pressure gain `receiver_gain` (Pa/m) saturating at
    `receiver_pressure` (Pa). Spool: end area `spool_area` (m^2), mass `spool_mass` (kg),
    viscous friction `spool_damping` (N*s/m), opening at rated flow `rated_opening` (m);
    steady flow forces with discharge coefficient `discharge` and oil density `density`
    (kg/m^3). `torque_motor`: the reluctance law of the motor (`TorqueMotor`) instead of
    the linear k_t i."""

    jet_mass: float = 2.0e-3
    hinge_stiffness: float = 1.0e4
    hinge_damping: float = 8.0
    motor_gain: float | None = None
    wire_stiffness: float = 2.0e4
    receiver_gain: float = 2.0e11
    receiver_pressure: float = 100.0 * BAR
    spool_area: float = 2.0e-5
    spool_mass: float = 0.02
    spool_damping: float = 4000.0
    rated_opening: float = 5.0e-4
    discharge: float = 0.61
    density: float = 850.0
    torque_motor: TorqueMotor | None = None  # None: the linear law F = motor_gain * i
