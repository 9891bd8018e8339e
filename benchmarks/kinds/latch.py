"""Event-heavy: three flaps falling from the horizontal onto their latches.

Three slender flaps (1 kg; 0.3, 0.4 and 0.5 m long) hang from ground hinges about z at
x = 0, 1, 2 m, released at rest in the horizontal plane y = 0 under gravity (-y). Each falls
until its hinge angle reaches its latch angle (-50, -60, -70 deg); an event then switches on
its latch, a torsion spring-damper (500 N*m/rad, 0.5 N*m*s/rad, angle0 = the latch angle)
that holds the flap there: a free fall and a lock-up per flap, 1 s in all.

`loads`: a `torsion_spring` per hinge with `active: false` and an event
`when: angle(hinge) <= latch angle, then: activate` (located to 1e-9 s on re-solved steps).
Exudyn: an `ObjectConnectorTorsionalSpringDamper` per hinge (markers as the revolute joint,
offset = the latch angle), created inactive and switched on by the `PreStepUserFunction`
(the way Exudyn switches during a run) at the first step that starts past the latch angle:
the switch lags the crossing by up to one step, an error of first order in the step. All SI.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from benchmarks.models import GRAVITY, BodySpec, JointSpec, ModelSpec, OutputSpec

__all__ = ["FLAPS", "extend_case", "extend_exudyn", "spec"]

#: (length m, latch angle rad) of each flap
FLAPS: tuple[tuple[float, float], ...] = (
    (0.3, math.radians(-50.0)),
    (0.4, math.radians(-60.0)),
    (0.5, math.radians(-70.0)),
)
MASS = 1.0  # kg, each flap
PITCH = 1.0  # m, between hinges
STIFFNESS = 500.0  # N*m/rad, latch
DAMPING = 0.5  # N*m*s/rad, latch
END = 1.0  # s


def spec() -> ModelSpec:
    """The three flaps and their hinges as a ModelSpec (the latches are the extension's)."""
    bodies, joints = [], []
    for k, (length, _) in enumerate(FLAPS):
        hinge = (PITCH * k, 0.0, 0.0)
        across = MASS * length**2 / 12.0
        inertia = ((1e-4, 0.0, 0.0), (0.0, across, 0.0), (0.0, 0.0, across))
        cm = (PITCH * k + 0.5 * length, 0.0, 0.0)
        bodies.append(BodySpec(f"flap{k}", MASS, cm, inertia))
        joints.append(
            JointSpec(f"hinge{k}", "revolute", (f"flap{k}", "ground"), hinge, axis=(0, 0, 1.0))
        )
    return ModelSpec(
        name="flap_latches",
        title=f"three flaps falling onto their latches (an event each), {END:g} s",
        bodies=tuple(bodies),
        joints=tuple(joints),
        points=(),
        gravity=(0.0, -GRAVITY, 0.0),
        end=END,
        quick_end=0.5,
        output_step=1e-3,
        outputs=tuple(
            OutputSpec(f"flap{k}", "value", "joint_angle", f"hinge{k}") for k in range(len(FLAPS))
        ),
        main=tuple(f"flap{k}.value" for k in range(len(FLAPS))),
        extension=__name__,
        notes=(
            "3 bodies, 15 constraint equations, 3 DOF; 3 events switching on latch springs "
            f"({STIFFNESS:g} N*m/rad, {DAMPING:g} N*m*s/rad)",
        ),
    )


def extend_case(data: dict[str, Any]) -> None:
    """Add the latches (inactive torsion springs) and the events switching them on."""
    forces, events = {}, {}
    for k, (_, angle) in enumerate(FLAPS):
        forces[f"latch{k}"] = {
            "type": "torsion_spring",
            "joint": f"hinge{k}",
            "stiffness": STIFFNESS,
            "damping": DAMPING,
            "angle0": angle,
            "active": False,
        }
        events[f"lock{k}"] = {
            "when": f"angle(hinge{k}) <= {angle!r}",
            "then": [{"activate": f"latch{k}"}],
        }
    data["mechanism"]["forces"] = forces
    data["mechanism"]["events"] = events


def extend_exudyn(
    exu: Any, mbs: Any, bodies: dict[str, Any], joints: dict[str, Any], step: float
) -> Any:
    """Add an inactive torsional spring-damper per hinge; return the pre-step function that
    switches each on once its hinge angle has passed the latch angle."""
    from exudyn.utilities import (
        MarkerBodyRigid,
        ObjectConnectorTorsionalSpringDamper,
    )

    watched = []
    for k, (_, angle) in enumerate(FLAPS):
        hinge = np.array([PITCH * k, 0.0, 0.0])
        cm = np.array([PITCH * k + 0.5 * FLAPS[k][0], 0.0, 0.0])
        m0 = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies["ground"], localPosition=hinge))
        m1 = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[f"flap{k}"], localPosition=hinge - cm))
        spring = mbs.AddObject(
            ObjectConnectorTorsionalSpringDamper(
                markerNumbers=[m0, m1],
                stiffness=STIFFNESS,
                damping=DAMPING,
                offset=angle,
                activeConnector=False,
            )
        )
        watched.append((joints[f"hinge{k}"], spring, angle))
    rotation = exu.OutputVariableType.Rotation
    waiting = list(watched)

    def pre_step(mbs_: Any, t: float) -> bool:
        for item in list(waiting):
            joint, spring, angle = item
            if mbs_.GetObjectOutput(joint, rotation)[2] <= angle:
                mbs_.SetObjectParameter(spring, "activeConnector", True)
                waiting.remove(item)
        return True

    return pre_step
