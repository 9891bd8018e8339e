"""Pydantic model of the hydraulic servo-actuator force element (issue 12; equations and
library values in docs/hydraulics.md). Absent keys take the library values of
mechlib.elements.hydraulics.parameters."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from loadcases.schema.types import (
    Damping,
    Dimensionless,
    Force,
    Length,
    Mass,
    NamePair,
    Pressure,
    Stiffness,
    Strict,
    Velocity,
    describe,
    expression,
    quantity,
    vector,
)

__all__ = ["ServoActuator"]

_Area = quantity("area")
_Volume = quantity("volume")
_Flow = quantity("flow")
_Current = quantity("current")
_Frequency = quantity("frequency")
_Rate = quantity("frequency")  # 1/s


class CylinderInput(Strict):
    """Cylinder: chamber 1 (piston side) grows as the actuator extends."""

    area_1: _Area | None = Field(None, gt=0, description=describe("piston-side area A1", "area"))
    area_2: _Area | None = Field(None, gt=0, description=describe("rod-side area A2", "area"))
    dead_volumes: vector("volume", None) | None = Field(
        None, description=describe("[V1, V2] at the stroke end that empties each", "volume")
    )
    bulk_modulus: Pressure | None = Field(
        None, gt=0, description=describe("effective bulk modulus beta_e", "pressure")
    )
    leakage: quantity("leakage") | None = Field(
        None, ge=0, description=describe("internal leakage coefficient C_ip", "leakage")
    )
    viscous_friction: Damping | None = Field(None, ge=0, description=describe("gamma", "damping"))
    coulomb_friction: Force | None = Field(None, ge=0, description=describe("F_c", "force"))
    coulomb_speed: Velocity | None = Field(
        None, gt=0, description=describe("speed of full Coulomb friction (tanh)", "velocity")
    )
    stop_stiffness: Stiffness | None = Field(
        None, ge=0, description=describe("end stops", "stiffness")
    )
    stop_damping: Damping | None = Field(None, ge=0, description=describe("end stops", "damping"))


class SupplyInput(Strict):
    """Supply, return and vapour pressures (absolute)."""

    pressure: Pressure | None = Field(None, gt=0, description=describe("supply p_s", "pressure"))
    return_pressure: Pressure | None = Field(
        None, ge=0, description=describe("return p_r", "pressure")
    )
    vapour_pressure: Pressure | None = Field(
        None, ge=0, description=describe("floor of the chamber pressures", "pressure")
    )


class ValveInput(Strict):
    """Servovalve: rated flow at rated current and valve drop; spool dynamics."""

    rated_flow: _Flow | None = Field(None, gt=0, description=describe("Q_R", "flow"))
    rated_pressure_drop: Pressure | None = Field(
        None, gt=0, description=describe("dp_R (both lands)", "pressure")
    )
    rated_current: _Current | None = Field(None, gt=0, description=describe("i_R", "current"))
    frequency: _Frequency | None = Field(
        None, gt=0, description=describe("spool natural frequency", "frequency")
    )
    damping: Dimensionless | None = Field(None, ge=0, description="spool damping ratio [1]")
    transition_pressure: Pressure | None = Field(
        None, gt=0, description=describe("laminar transition dp_tr of the orifice law", "pressure")
    )


class ControllerInput(Strict):
    """PI position controller with saturated current."""

    kp: quantity("current_gain") | None = Field(None, description=describe("K_p", "current_gain"))
    ki: quantity("integral_gain") | None = Field(None, description=describe("K_i", "integral_gain"))
    current_limit: _Current | None = Field(None, gt=0, description=describe("i_max", "current"))


class TorqueMotorInput(Strict):
    """Push-pull torque motor by its reluctance force B^2 S / (2 mu0) per air gap (seed 004
    eq. 6.1; docs/hydraulics.md)."""

    pole_area: _Area = Field(gt=0, description=describe("pole (solenoid) area S", "area"))
    air_gap: Length = Field(gt=0, description=describe("air gap g at the centre", "length"))
    turns: quantity("any") = Field(gt=0, description="control coil turns N [1]")
    magnet_mmf: _Current = Field(
        gt=0, description=describe("polarising magnetomotive force M0 (ampere-turns)", "current")
    )
    gap_ratio: Dimensionless = Field(
        1.0, gt=0, description="armature motion at the gaps per jet-tip motion [1]"
    )


class JetPipeInput(Strict):
    """Torque motor, jet pipe, receiver and spool (seed 004 eqs. 6.1-6.3)."""

    jet_mass: Mass | None = Field(None, gt=0)
    hinge_stiffness: Stiffness | None = Field(None, ge=0)
    hinge_damping: Damping | None = Field(None, ge=0)
    motor_gain: quantity("any") | None = Field(None, description="k_t [N/A, SI]")
    wire_stiffness: Stiffness | None = Field(None, ge=0)
    receiver_gain: quantity("any") | None = Field(None, description="K_jr [Pa/m, SI]")
    receiver_pressure: Pressure | None = Field(None, gt=0)
    spool_area: _Area | None = Field(None, gt=0)
    spool_mass: Mass | None = Field(None, gt=0)
    spool_damping: Damping | None = Field(None, ge=0)
    rated_opening: Length | None = Field(None, gt=0)
    discharge: Dimensionless | None = Field(None, gt=0)
    density: quantity("any") | None = Field(None, gt=0, description="oil density [kg/m^3, SI]")
    torque_motor: TorqueMotorInput | None = Field(
        None, description="the reluctance law of the torque motor (absent: k_t i)"
    )

    @model_validator(mode="after")
    def _one_motor_law(self) -> JetPipeInput:
        if self.motor_gain is not None and self.torque_motor is not None:
            raise PydanticCustomError(
                "motor", "give 'motor_gain' (linear law) or 'torque_motor', not both"
            )
        return self


class LagInput(Strict):
    """Ideal position servo: first-order lag on the stroke, rod tied by k and c."""

    velocity_gain: _Rate | None = Field(
        None, gt=0, description=describe("K_v (absent: the valve loop's)", "frequency")
    )
    stiffness: Stiffness | None = Field(
        None, ge=0, description=describe("k (absent: k_h at design)", "stiffness")
    )
    damping: Damping | None = Field(None, ge=0, description=describe("c", "damping"))


class ServoActuator(Strict):
    """Hydraulic servo-actuator between two points: rod end, cylinder end."""

    type: Literal["servo_actuator"]
    points: NamePair = Field(description="[rod end, cylinder end]")
    fidelity: Literal["lag", "valve", "jet_pipe"] = "valve"
    command: expression("length") = Field(
        description="stroke demand x_cmd(t) from the design length, m (numbers SI)"
    )
    stroke: vector("length", 2) = Field(
        description=describe("[retracted, extended] stroke limits from the design", "length")
    )
    initial_pressures: vector("pressure", 2) | None = Field(
        None, description=describe("[p1, p2] at the start (absent: no force)", "pressure")
    )
    cylinder: CylinderInput | None = None
    supply: SupplyInput | None = None
    valve: ValveInput | None = None
    controller: ControllerInput | None = None
    jet_pipe: JetPipeInput | None = None
    lag: LagInput | None = None
    active: bool = Field(True, description="false: the element starts switched off")
