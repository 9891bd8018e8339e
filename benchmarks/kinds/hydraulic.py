"""Hydraulics: a servo-actuator whose valve opens fully, driving a 50 kg ram against a spring.

A ram (50 kg) slides on a prismatic guide along x, pushed by a double-acting cylinder from a
ground eye 0.5 m behind it (the library cylinder of `loads`: 10 cm^2 both sides, stroke
-50 / +100 mm, dead volumes 20 cm^3, oil 0.8 GPa, viscous friction 4000 N*s/m, no leakage)
and held back by a spring of 1e5 N/m from a ground point 0.5 m ahead. At t = 0 the servovalve
(5 L/min at 70 bar, 100 Hz, damping 0.7) gets its rated current and stays there; both
chambers start at 105.9 bar ((p_s + p_r) / 2; supply 206.8 bar, return 5 bar). The spool
opens along the step response of its transfer function, the piston-side pressure rises, the
ram extends, its oil columns ringing at about 95 Hz (lightly damped), for 0.2 s.

`loads`: a `servo_actuator` (fidelity `valve`) whose controller saturates from the start
(kp 1000 A/m, ki 0, current limit = rated current, command 0.3 m: the error never drops
below 1e-5 m), so the spool obeys x_v'' + 2 zeta w x_v' + w^2 x_v = w^2 from rest; the
orifice transition pressure is 100 Pa (the regularised root differs from sqrt by under
3e-7 at the drops here), the vapour floor 0, end stops 0 (the ram stays in its stroke).
Exudyn: `ObjectConnectorHydraulicActuatorSimple` with `useChamberVolumeChange` (its
chambers' volumes follow the stroke as `loads`'s do; cylinder and hose moduli 0: the oil's
alone), `nominalFlow` the land gain K of `loads` (`ServoValve.flow_gain`), valve openings
x_v and -x_v set by the `PreStepUserFunction` (Exudyn's way to drive a valve) from the
spool's closed-form step response at the step's midpoint (`spool_opening`), held over the
step: a difference of second order in the step. All SI.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from benchmarks.models import BodySpec, JointSpec, ModelSpec, OutputSpec, PointSpec

__all__ = ["extend_case", "extend_exudyn", "spec", "spool_opening"]

MASS = 50.0  # kg
ROD_EYE = (0.0, 0.0, 0.0)  # m, on the ram
FRAME_EYE = (-0.5, 0.0, 0.0)  # m, cylinder end on the ground
SPRING_ANCHOR = (0.5, 0.0, 0.0)  # m, on the ground
SPRING_STIFFNESS = 1.0e5  # N/m
AREA = 1.0e-3  # m^2, both sides
STROKE = (-0.05, 0.1)  # m from the design length
DEAD_VOLUME = 2.0e-5  # m^3, each chamber
BULK_MODULUS = 0.8e9  # Pa
VISCOUS_FRICTION = 4000.0  # N*s/m
SUPPLY, RETURN = 206.8e5, 5.0e5  # Pa
RATED_FLOW, RATED_DROP = 5.0e-3 / 60.0, 70.0e5  # m^3/s, Pa
VALVE_FREQUENCY, VALVE_DAMPING = 100.0, 0.7  # Hz, 1
RATED_CURRENT = 0.01  # A
TRANSITION = 100.0  # Pa
END = 0.2  # s


def spool_opening(t: float) -> float:
    """Normalised spool opening (1) at t (s) after a unit step of current from rest: the
    underdamped second-order step response (zeta < 1)."""
    w, z = 2.0 * math.pi * VALVE_FREQUENCY, VALVE_DAMPING
    wd = w * math.sqrt(1.0 - z * z)
    return 1.0 - math.exp(-z * w * t) * (math.cos(wd * t) + z * w / wd * math.sin(wd * t))


def _flow_gain() -> float:
    """K (m^3/(s*Pa^0.5)) of one land, `loads`'s definition."""
    from mechlib.elements.hydraulics.parameters import ServoValve

    return ServoValve(rated_flow=RATED_FLOW, rated_pressure_drop=RATED_DROP).flow_gain


def spec() -> ModelSpec:
    """The ram on its guide as a ModelSpec (actuator and spring are the extension's)."""
    return ModelSpec(
        name="hydraulic_ram",
        title=f"servo-actuator, valve opened fully, driving a 50 kg ram on a spring, {END:g} s",
        bodies=(BodySpec("ram", MASS, ROD_EYE, ((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1.0))),),
        joints=(JointSpec("guide", "prismatic", ("ram", "ground"), ROD_EYE, axis=(1.0, 0, 0)),),
        points=(
            PointSpec("rod_eye", "ram", ROD_EYE),
            PointSpec("frame_eye", "ground", FRAME_EYE),
            PointSpec("anchor", "ground", SPRING_ANCHOR),
        ),
        gravity=(0.0, 0.0, 0.0),
        end=END,
        quick_end=0.05,
        output_step=1e-4,
        outputs=(OutputSpec("ram", "x", "point_position", "rod_eye"),),
        main=("ram.x",),
        extension=__name__,
        notes=("1 body, 5 constraint equations, 1 DOF; servo_actuator (valve: 5 states), spring",),
    )


def extend_case(data: dict[str, Any]) -> None:
    """Add the servo-actuator and the spring."""
    data["mechanism"]["forces"] = {
        "actuator": {
            "type": "servo_actuator",
            "points": ["rod_eye", "frame_eye"],
            "fidelity": "valve",
            "command": "0.3",
            "stroke": list(STROKE),
            "cylinder": {
                "area_1": AREA,
                "area_2": AREA,
                "dead_volumes": [DEAD_VOLUME, DEAD_VOLUME],
                "bulk_modulus": BULK_MODULUS,
                "leakage": 0.0,
                "viscous_friction": VISCOUS_FRICTION,
                "stop_stiffness": 0.0,
                "stop_damping": 0.0,
            },
            "supply": {"pressure": SUPPLY, "return_pressure": RETURN, "vapour_pressure": 0.0},
            "valve": {
                "rated_flow": RATED_FLOW,
                "rated_pressure_drop": RATED_DROP,
                "rated_current": RATED_CURRENT,
                "frequency": VALVE_FREQUENCY,
                "damping": VALVE_DAMPING,
                "transition_pressure": TRANSITION,
            },
            "controller": {"kp": 1000.0, "ki": 0.0, "current_limit": RATED_CURRENT},
        },
        "spring": {
            "type": "spring",
            "points": ["rod_eye", "anchor"],
            "stiffness": SPRING_STIFFNESS,
            "free_length": float(np.linalg.norm(np.subtract(SPRING_ANCHOR, ROD_EYE))),
        },
    }


def extend_exudyn(
    exu: Any, mbs: Any, bodies: dict[str, Any], joints: dict[str, Any], step: float
) -> Any:
    """Add the hydraulic actuator and the spring; return the pre-step function that sets
    the valve openings."""
    from exudyn.utilities import (
        MarkerBodyPosition,
        NodeGenericODE1,
        ObjectConnectorHydraulicActuatorSimple,
        ObjectConnectorSpringDamper,
    )

    def marker(body: str, at: tuple[float, float, float]) -> Any:
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodies[body], localPosition=list(at)))

    rod, frame = marker("ram", (0.0, 0.0, 0.0)), marker("ground", FRAME_EYE)
    design = float(np.linalg.norm(np.subtract(ROD_EYE, FRAME_EYE)))
    start = 0.5 * (SUPPLY + RETURN)
    pressures = mbs.AddNode(
        NodeGenericODE1(
            referenceCoordinates=[0.0, 0.0],
            initialCoordinates=[start, start],
            numberOfODE1Coordinates=2,
        )
    )
    actuator = mbs.AddObject(
        ObjectConnectorHydraulicActuatorSimple(
            markerNumbers=[frame, rod],
            nodeNumbers=[pressures],
            offsetLength=design + STROKE[0],
            strokeLength=STROKE[1] - STROKE[0],
            chamberCrossSection0=AREA,
            chamberCrossSection1=AREA,
            hoseVolume0=DEAD_VOLUME,
            hoseVolume1=DEAD_VOLUME,
            actuatorDamping=VISCOUS_FRICTION,
            oilBulkModulus=BULK_MODULUS,
            cylinderBulkModulus=0.0,
            hoseBulkModulus=0.0,
            nominalFlow=_flow_gain(),
            systemPressure=SUPPLY,
            tankPressure=RETURN,
            useChamberVolumeChange=True,
        )
    )
    mbs.AddObject(
        ObjectConnectorSpringDamper(
            markerNumbers=[marker("ground", SPRING_ANCHOR), rod],
            stiffness=SPRING_STIFFNESS,
            referenceLength=float(np.linalg.norm(np.subtract(SPRING_ANCHOR, ROD_EYE))),
        )
    )

    def pre_step(mbs_: Any, t: float) -> bool:
        opening = spool_opening(t + 0.5 * step)
        mbs_.SetObjectParameter(actuator, "valveOpening0", opening)
        mbs_.SetObjectParameter(actuator, "valveOpening1", -opening)
        return True

    return pre_step
