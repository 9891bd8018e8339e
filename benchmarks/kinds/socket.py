"""Contact-heavy: a steel ball rattling in its spherical socket (a rod-end's clearance).

A steel ball (radius 10 mm, 32.9 g) sits in a ground socket of radial clearance 0.5 mm, the
two centres coinciding at the design position. It starts there at (0.08, 0.05, 0.03) m/s
under gravity (-y) and rattles for 0.2 s: about 30 impacts against the socket wall, then it
slides around the socket's bottom in continuous contact. Contact force: the `hertz` law of
`loads` (Hertz with Lankarani-Nikravesh damping, restitution 0.8), K = 4/3 E* sqrt(R) for
steel on steel (1.54e10 N/m^1.5); no friction, so the ball's spin never changes.

Exudyn: its native `ObjectContactSphereSphere` with the socket as a hollow sphere
(`isHollowSphere1`) of radius R + c: gap c - |e| as `loads`'s `sphere_in_sphere`, the
Hunt-Crossley model with e_HC = (1 + e^2) / 2 (benchmarks.exudyn_models). Two differences
vanish with the step, as for the bouncing ball: Exudyn remembers the approach speed at the
end of its first step in contact and switches the contact per step. All SI.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from benchmarks.ball import BALL_RADIUS, STEEL, ball_mass, effective_modulus
from benchmarks.models import GRAVITY, BodySpec, ModelSpec, OutputSpec, PointSpec

__all__ = ["CLEARANCE", "extend_case", "extend_exudyn", "spec"]

CLEARANCE = 0.5e-3  # m, radial
RESTITUTION = 0.8
START_VELOCITY = (0.08, 0.05, 0.03)  # m/s
END = 0.2  # s


def _stiffness() -> float:
    """Hertz K (N/m^1.5) of the ball against the socket (taken as a plane: R_socket >> c)."""
    return 4.0 / 3.0 * effective_modulus(*STEEL, *STEEL) * math.sqrt(BALL_RADIUS)


def spec() -> ModelSpec:
    """The ball in its socket as a ModelSpec (the contact is added by the extension)."""
    mass = ball_mass()
    inertia = 0.4 * mass * BALL_RADIUS**2
    diag = ((inertia, 0.0, 0.0), (0.0, inertia, 0.0), (0.0, 0.0, inertia))
    return ModelSpec(
        name="socket_rattle",
        title=f"steel ball rattling in its socket (0.5 mm clearance), Hertz, {END:g} s",
        bodies=(BodySpec("ball", mass, (0.0, 0.0, 0.0), diag),),
        joints=(),
        points=(PointSpec("centre", "ball", (0.0, 0.0, 0.0)),),
        gravity=(0.0, -GRAVITY, 0.0),
        end=END,
        quick_end=0.05,
        output_step=1e-4,
        outputs=tuple(OutputSpec("ball", c, "point_position", "centre") for c in "xyz"),
        main=("ball.x", "ball.y", "ball.z"),
        initial_velocity=(("ball", START_VELOCITY),),
        extension=__name__,
        notes=(
            f"1 body, 6 DOF, sphere_in_sphere clearance {CLEARANCE * 1e3:g} mm, Hertz K = "
            f"{_stiffness():.4g} N/m^1.5, Lankarani-Nikravesh restitution {RESTITUTION:g}",
        ),
    )


def extend_case(data: dict[str, Any]) -> None:
    """Add the socket contact to the `loads` case `data`."""
    data["mechanism"]["contacts"] = {
        "socket": {
            "type": "hertz",
            "bodies": ["ball", "ground"],
            "geometry": {
                "shape": "sphere_in_sphere",
                "center": [0.0, 0.0, 0.0],
                "radius": BALL_RADIUS,
                "clearance": CLEARANCE,
            },
            "stiffness": _stiffness(),
            "exponent": 1.5,
            "restitution": RESTITUTION,
        }
    }


def extend_exudyn(
    exu: Any, mbs: Any, bodies: dict[str, Any], joints: dict[str, Any], step: float
) -> None:
    """Add the socket contact to the Exudyn system: a ball against a hollow ground sphere."""
    from exudyn.utilities import (
        MarkerBodyRigid,
        NodeGenericData,
        ObjectContactSphereSphere,
    )

    from benchmarks.exudyn_models import MIN_IMPACT_SPEED, hunt_crossley_restitution

    m_ball = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies["ball"], localPosition=np.zeros(3)))
    m_socket = mbs.AddMarker(
        MarkerBodyRigid(bodyNumber=bodies["ground"], localPosition=np.zeros(3))
    )
    data = mbs.AddNode(
        NodeGenericData(numberOfDataCoordinates=4, initialCoordinates=[CLEARANCE, 0, 0, 0])
    )
    mbs.AddObject(
        ObjectContactSphereSphere(
            name="socket",
            markerNumbers=[m_ball, m_socket],
            nodeNumber=data,
            spheresRadii=[BALL_RADIUS, BALL_RADIUS + CLEARANCE],
            isHollowSphere1=True,
            contactStiffness=_stiffness(),
            contactStiffnessExponent=1.5,
            restitutionCoefficient=hunt_crossley_restitution(RESTITUTION),
            minimumImpactVelocity=MIN_IMPACT_SPEED,
            impactModel=1,
        )
    )
