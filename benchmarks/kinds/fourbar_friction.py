"""Springs, dampers and joint friction: one four-bar loop of fourbar10 with a spring-damper
on its crank, a torsion spring-damper on its rocker and a friction torque in its crank pivot.

The loop (R-S-U-R, benchmarks.models.fourbar10's first loop: crank `link0` on `r0` at the
origin, coupler, rocker `link1` on `r1` at (0.2, 0, 0); 1 DOF) starts at its design position
with the crank turning at 4 rad/s and swings under gravity (-y) for 2 s, slowed by
- `lift`: a spring-damper from the crank's lower end (0, -0.15, 0) to the ground point
  (-0.2, -0.15, 0): 200 N/m, 0.1 N*s/m, free length 0.15 m (0.05 m stretched at design);
- `coil`: a torsion spring-damper on `r1`: 2 N*m/rad, 0.002 N*m*s/rad, angle0 0;
- `rub`: friction in `r0`, a constant torque of 0.003 N*m (`preload`; `mu` 0) against the
  crank's rotation through the regularised Coulomb law of `loads`
  (`mechlib.elements.regularize.coulomb_factor`, full from 1e-3 rad/s).

Exudyn: `ObjectConnectorSpringDamper` (the same law: k (L - L0) + d L' along the line),
`ObjectConnectorTorsionalSpringDamper` on the rocker, and on the crank a torsional
spring-damper of zero stiffness whose `springTorqueUserFunction` (Python, called at every
evaluation) returns preload * coulomb_factor(omega / 1e-3 rad/s), the same function. One
difference: `loads` holds a friction joint exactly while it sticks (mechlib.solvers.stick),
where Exudyn's regularised torque lets it creep; the crank does not stick within the 2 s (the
springs drive it through every reversal), so both integrate the same equations. All SI.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from benchmarks.models import ModelSpec, OutputSpec, PointSpec, fourbar10

__all__ = ["extend_case", "extend_exudyn", "spec"]

SPRING = {"stiffness": 200.0, "damping": 0.1, "free_length": 0.15}  # N/m, N*s/m, m
SPRING_ENDS = ((0.0, -0.15, 0.0), (-0.2, -0.15, 0.0))  # m: on the crank, on the ground
COIL = {"stiffness": 2.0, "damping": 0.002, "angle0": 0.0}  # N*m/rad, N*m*s/rad, rad
FRICTION_TORQUE = 0.003  # N*m
PIN_RADIUS = 0.01  # m (unused with mu = 0; the case language asks for it)
RATE = 4.0  # rad/s, crank at t = 0
END = 2.0  # s


def _friction_threshold() -> float:
    """Relative rate (rad/s) of full friction: `loads`'s JointFriction default."""
    from mechlib.elements.friction import JointFriction

    return float(JointFriction.v_threshold)


def spec() -> ModelSpec:
    """fourbar10's first loop with its crank at RATE, as a ModelSpec (the force elements are
    the extension's)."""
    ten = fourbar10()
    keep = {"link0", "link1", "coupler0"}
    joints = tuple(j for j in ten.joints if j.name in {"r0", "r1", "s0", "u0"})
    return ModelSpec(
        name="fourbar_friction",
        title=f"four-bar with spring-dampers and pivot friction, {END:g} s",
        bodies=tuple(b for b in ten.bodies if b.name in keep),
        joints=joints,
        points=(
            PointSpec("crank_end", "link0", SPRING_ENDS[0]),
            PointSpec("anchor", "ground", SPRING_ENDS[1]),
        ),
        gravity=ten.gravity,
        end=END,
        quick_end=0.5,
        output_step=1e-3,
        outputs=(
            OutputSpec("crank", "value", "joint_angle", "r0"),
            OutputSpec("rocker", "value", "joint_angle", "r1"),
        ),
        main=("crank.value", "rocker.value"),
        initial_rate=("r0", RATE),
        extension=__name__,
        notes=(
            "3 bodies, 17 constraint equations, 1 DOF; spring-damper, torsion spring-damper, "
            f"pivot friction {FRICTION_TORQUE:g} N*m",
        ),
    )


def extend_case(data: dict[str, Any]) -> None:
    """Add the spring-damper, the torsion spring-damper and the pivot friction."""
    data["mechanism"]["forces"] = {
        "lift": {"type": "spring", "points": ["crank_end", "anchor"], **SPRING},
        "coil": {"type": "torsion_spring", "joint": "r1", **COIL},
        "rub": {
            "type": "joint_friction",
            "joint": "r0",
            "mu": 0.0,
            "pin_radius": PIN_RADIUS,
            "preload": FRICTION_TORQUE,
        },
    }


def extend_exudyn(
    exu: Any, mbs: Any, bodies: dict[str, Any], joints: dict[str, Any], step: float
) -> None:
    """Add the same three elements to the Exudyn system (friction as a user torque)."""
    from exudyn.utilities import (
        MarkerBodyRigid,
        ObjectConnectorSpringDamper,
        ObjectConnectorTorsionalSpringDamper,
    )

    from mechlib.elements.regularize import coulomb_factor

    model = spec()

    def marker(body: str, at: tuple[float, float, float]) -> Any:
        cm = np.zeros(3) if body == "ground" else np.array(model.body(body).cm)
        local = np.array(at, dtype=float) - cm
        return mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[body], localPosition=local))

    mbs.AddObject(
        ObjectConnectorSpringDamper(
            markerNumbers=[marker("ground", SPRING_ENDS[1]), marker("link0", SPRING_ENDS[0])],
            stiffness=SPRING["stiffness"],
            damping=SPRING["damping"],
            referenceLength=SPRING["free_length"],
        )
    )
    r1, r0 = model.joint("r1"), model.joint("r0")
    mbs.AddObject(
        ObjectConnectorTorsionalSpringDamper(
            markerNumbers=[marker("ground", r1.at), marker("link1", r1.at)],
            stiffness=COIL["stiffness"],
            damping=COIL["damping"],
            offset=COIL["angle0"],
        )
    )
    threshold = _friction_threshold()

    def friction(
        mbs: Any,
        t: float,
        itemNumber: int,  # Exudyn calls it with these names
        rotation: float,
        angularVelocity: float,
        stiffness: float,
        damping: float,
        offset: float,
    ) -> float:
        return FRICTION_TORQUE * coulomb_factor(angularVelocity, threshold)

    mbs.AddObject(
        ObjectConnectorTorsionalSpringDamper(
            markerNumbers=[marker("ground", r0.at), marker("link0", r0.at)],
            springTorqueUserFunction=friction,
        )
    )
