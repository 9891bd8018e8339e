"""The energy balance of a run as one request (`EnergyBalance`): stored energies at each
recorded row and the work and dissipation integrated over the rows.

Columns (J):
- `kinetic`: 1/2 qd^T M qd (0 in quasi-static and static rows: inertia is ignored there),
  modal coordinates of flexible bodies included;
- `gravitational`: -sum m g . r_cm (zero at the ground origin; a flexible body's deformed
  centre of mass);
- `elastic`: the potentials of the elements that give one (`potential(view)`, exact:
  their loads are -grad V): linear springs and torsion springs (k s^2/2 + preload s),
  springs, torsion springs and seals with a tabulated law (the table's exact integral,
  mechlib.model.tables.Table.integral), contacts and clearance joints (the integral
  k x^(n+1)/(n+1) of every normal law's elastic part k x^n over the penetration), seals
  (the same per station), cable loops (each strand's tension integrated over its
  elongation), bushings (1/2 d.K d + 1/2 theta.Kr theta: exact for the translational part
  and an isotropic or one-axis torsional stiffness, to second order in rotation otherwise,
  see mechlib.elements.bushing), and the modal strain energy 1/2 zeta^T K zeta of flexible
  bodies;
- `drive_work`: work done by the motions, the integral of -lam . nu (the constraint power:
  only the rows a motion drives have nu != 0);
- `dissipated`: energy taken out by friction and damping, the integral of -P of the
  elements of the `friction` and `damping` effects (joint friction, rotational dampers)
  and of the `dissipation(view)` (W) of the others: the dampers of springs and bushings;
  a contact's damping part (F_N - k x^n) times the penetration rate and its friction
  mu F_N |v_t|; a seal's friction. At equilibrium rows (forces without velocities) an
  element's `rest_dissipation(view, k)` where it has one: the static friction of contacts
  and seals against the rates of the row. Also flexible bodies' modal damping
  zeta_d^T D zeta_d;
- `load_work`: work of every other applied load: point forces and torques, hydraulic
  actuators (their oil volumes are states: the energy they store is not a potential of the
  mechanism's coordinates), springs whose law has no exact integral (a hinge law in series
  with a structure, `SeriesLaw`), the integral of P_e + D_e (an element with a potential
  loads with -dV/dt - D_e exactly: counted in `elastic` and `dissipated`), and the geometric
  stiffening forces of flexible bodies -zeta_d^T K_G zeta (not a potential in general);
- `balance`: kinetic + gravitational + elastic - drive_work - load_work + dissipated minus
  its value at the first row: zero up to the integration error.

The integrals are trapezoid sums over the recorded rows (second order in the output
interval, whatever the integrator's own steps): the output step sets their accuracy, and
`balance` shows it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mechlib.core.rotation import omega_body
from mechlib.kinematics.kernels import rotation_matrix
from mechlib.system.system import System

__all__ = ["COMPONENTS", "DISSIPATIVE_EFFECTS", "EnergyBalance", "energy_columns"]

COMPONENTS = (
    "kinetic",
    "gravitational",
    "elastic",
    "drive_work",
    "load_work",
    "dissipated",
    "balance",
)
DISSIPATIVE_EFFECTS = ("friction", "damping")


@dataclass(frozen=True)
class EnergyBalance:
    """The energy request: the columns of `COMPONENTS` (J)."""

    name: str
    units: ClassVar[dict[str, str]] = dict.fromkeys(COMPONENTS, "J")


def _element_power(system: System, k, view, element) -> float:
    """Power (W) of one element's loads at state k (velocities from k)."""
    F, N = np.zeros((system.nb + 1, 3)), np.zeros((system.nb + 1, 3))
    element.apply(view, F, N)
    qd = k.xd[:-1].ravel()
    return float(system.generalized(k, F, N)[: qd.size] @ qd)


def _modal(system: System, k, lam: np.ndarray) -> tuple[float, float, float, float]:
    """(gravitational, strain energy, power of the geometric stiffening, modal damping
    dissipation) of the flexible bodies at state k (their masses are not among the rigid
    bodies': the weight at the deformed centre of mass x + A (I2 + I3 zeta))."""
    gravitational = elastic = load = dissipation = 0.0
    for a in system.flexible:
        comp = a.body.component
        zeta, zeta_d = k.z[a.modes], k.zd[a.modes]
        A = rotation_matrix(k.p[a.frame])
        centre = k.r[a.frame] * comp.mass + A @ a.body.first_moment(zeta)
        gravitational -= float(system.gravity @ centre)
        elastic += 0.5 * float(comp.stiffness @ zeta**2)
        dissipation += float(comp.viscous @ zeta_d**2)
        if comp.geometric is not None:
            omega = omega_body(k.p[a.frame], k.pd[a.frame])
            stiffness = comp.geometric.stiffness(omega, system.node_loads(k, lam, a))
            load -= float(zeta_d @ stiffness @ zeta)
    return gravitational, elastic, load, dissipation


def _own_dissipation(element, k, view, rest: bool) -> float:
    """Power (W) an element takes out by itself: `dissipation(view)`, or at an equilibrium
    row (forces without velocities, the mechanism moving at k's rates) `rest_dissipation`
    where the element has one (the static friction of a contact or a seal)."""
    if rest and hasattr(element, "rest_dissipation"):
        return float(element.rest_dissipation(view, k))
    return float(element.dissipation(view)) if hasattr(element, "dissipation") else 0.0


def _row(system: System, k, view, lam: np.ndarray, rest: bool) -> tuple[float, ...]:
    """(kinetic, gravitational, elastic, drive power, load power, dissipation) at one row."""
    qd = np.r_[k.xd[:-1].ravel(), k.zd]
    kinetic = 0.0 if rest else 0.5 * float(qd @ system.mass_times(k, qd))
    modal_weight, elastic, load, dissipation = _modal(system, k, lam)
    gravitational = modal_weight - float(system.masses @ (k.r[:-1] @ system.gravity))
    for element in system.elements:
        if not element.active:
            continue
        if element.effect in DISSIPATIVE_EFFECTS:
            dissipation -= _element_power(system, k, view, element)
            continue
        own = _own_dissipation(element, k, view, rest)
        dissipation += own
        potential = getattr(element, "potential", None)
        if potential is not None:  # its power is -dV/dt - own, exactly: not needed
            elastic += float(potential(view))
        else:
            load += _element_power(system, k, view, element) + own
    drive = -float(lam @ system.nu(k))
    return kinetic, gravitational, elastic, drive, load, dissipation


def _integral(time: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """Running trapezoid integral of `rate` over `time`, 0 at the first row."""
    steps = 0.5 * (rate[1:] + rate[:-1]) * np.diff(time)
    return np.concatenate([[0.0], np.cumsum(steps)])


def energy_columns(system: System, trajectory, views) -> dict[str, np.ndarray]:
    """The `COMPONENTS` columns (J) at the recorded rows; `views(i)` gives (k, view) of row
    i as the requests see it (snapshot restored; the forces' view of equilibria)."""
    rows = []
    for i in range(len(trajectory)):
        k, view = views(i)
        rows.append(_row(system, k, view, trajectory.lam[i], trajectory.at_rest))
    kinetic, gravitational, elastic, drive, load, dissipation = np.array(rows).T
    time = np.asarray(trajectory.time, dtype=float)
    out = {
        "kinetic": kinetic,
        "gravitational": gravitational,
        "elastic": elastic,
        "drive_work": _integral(time, drive),
        "load_work": _integral(time, load),
        "dissipated": _integral(time, dissipation),
    }
    total = kinetic + gravitational + elastic
    out["balance"] = total - total[0] - out["drive_work"] - out["load_work"] + out["dissipated"]
    return out
