"""Contact between primitive geometries and clearance joints (force elements, SI units).

geometry / profile: penetration, normal, contact point and relative velocity of a pair;
laws: normal force (impact, Hertz with Lankarani-Nikravesh damping, restitution);
friction: Stribeck and regularised Coulomb coefficients; element: the `Contact` force
element; clearance: ball-in-socket and pin-in-hole clearance joints with eccentricity.
"""

from mechlib.elements.contact.clearance import (
    ArchardWear,
    ClearanceJoint,
    revolute_clearance,
    spherical_clearance,
)
from mechlib.elements.contact.element import Contact
from mechlib.elements.contact.friction import CoulombFriction, StribeckFriction
from mechlib.elements.contact.geometry import CylinderInCylinder, SphereInSphere, SpherePlane
from mechlib.elements.contact.laws import HertzLaw, ImpactLaw, RestitutionLaw, hertz_stiffness, step
from mechlib.elements.contact.profile import CircleProfile

__all__ = [
    "ArchardWear",
    "CircleProfile",
    "ClearanceJoint",
    "Contact",
    "CoulombFriction",
    "CylinderInCylinder",
    "HertzLaw",
    "ImpactLaw",
    "RestitutionLaw",
    "SphereInSphere",
    "SpherePlane",
    "StribeckFriction",
    "hertz_stiffness",
    "revolute_clearance",
    "spherical_clearance",
    "step",
]
