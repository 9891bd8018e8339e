"""Guard rails of modal bodies: warnings with the results where the linear modal model is
stretched (issue 13 item 5). Each returns one message per flexible body at fault.

- linear limit: interface nodes deform by more than the body's `linear_limit` share of its
  size (Adams' CHAR_LEN idea, default 10 %) or turn by more than ROTATION_LIMIT;
- unresolved modes: kept modes with fewer than STEPS_PER_PERIOD mean steps per period;
- spin: without geometric stiffening, a spin rate whose square exceeds SPIN_LIMIT of the
  squared lowest frequency of the body held at one interface node.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.rotation import omega_body

__all__ = ["deformation_warnings", "spin_warnings", "unresolved_mode_warnings"]

LINEAR_LIMIT = 0.1  # default share of the characteristic length: Adams' CHAR_LEN (10 %)
ROTATION_LIMIT = 0.1  # rad: the linearised node rotation I + theta~ errs by theta^2/2
STEPS_PER_PERIOD = 20  # fewer steps per period of a mode: it is not resolved
SPIN_LIMIT = 0.05  # (spin / held frequency)^2: the centrifugal stiffness changes the
# held body's lowest frequency squared by about this share (1.19 + 1 for a cantilever's
# first in-plane mode: Southwell's coefficient and the frame's softening)


def _modal(system, trajectory, a) -> np.ndarray:
    """The modal coordinates (t, n) of modal body `a` along `trajectory`."""
    start = 7 * system.nb + a.offset
    return np.array([q[start : start + a.body.n] for q in trajectory.q])


def _size(comp) -> float:
    """Characteristic length (m): the extent of the kept nodes, or twice the radius of
    gyration sqrt(tr(I7) / m) if larger (a body kept at one node)."""
    extent = float(np.ptp(comp.positions, axis=0).max(initial=0.0))
    gyration = 2.0 * float(np.sqrt(np.trace(comp.invariants.I7) / comp.mass))
    return max(extent, gyration, 1e-3)


def deformation_warnings(system, trajectory) -> list[str]:
    """A warning per flexible body whose interface nodes deform by more than its linear
    limit (a share of its characteristic length, `_size`) or turn by
    more than ROTATION_LIMIT relative to its floating frame along `trajectory`: beyond them
    the linear modal model (and the linearised node rotation) is no longer a good one."""
    out = []
    for a in system.flexible:
        comp = a.body.component
        zeta = _modal(system, trajectory, a)
        if zeta.size == 0:
            continue
        limit = system.mechanism.flexible[a.name].linear_limit
        moved = np.linalg.norm(np.einsum("pcn,tn->tpc", comp.phi, zeta), axis=2).max(axis=1)
        turned = np.linalg.norm(np.einsum("pcn,tn->tpc", comp.phi_star, zeta), axis=2).max(axis=1)
        length = _size(comp)
        if moved.max() > limit * length or turned.max() > ROTATION_LIMIT:
            i = int(np.argmax(np.maximum(moved / (limit * length), turned / ROTATION_LIMIT)))
            out.append(
                f"flexible body {a.name}: at t = {trajectory.time[i]:.6g} s its interface nodes "
                f"deform by {moved[i]:.3g} m and turn by {turned[i]:.3g} rad relative to its "
                f"floating frame (limits {100 * limit:.3g} % of its size {length:.3g} m and "
                f"{ROTATION_LIMIT:g} rad): beyond the small deformation its modal model assumes"
            )
    return out


def unresolved_mode_warnings(system, duration: float, steps: int) -> list[str]:
    """A warning per flexible body keeping modes whose period spans fewer than
    STEPS_PER_PERIOD of the mean step taken (`duration` s over `steps` accepted steps):
    generalized-alpha damps them numerically (rho_inf < 1) instead of following them."""
    if steps <= 0 or duration <= 0.0:
        return []
    h = duration / steps
    out = []
    for a in system.flexible:
        f = a.body.component.frequencies / (2.0 * np.pi)
        fast = f[f * h * STEPS_PER_PERIOD > 1.0]
        if fast.size:
            out.append(
                f"flexible body {a.name}: {fast.size} of its {f.size} modes ({fast.min():.4g} "
                f"to {fast.max():.4g} Hz) are not resolved by the mean step {h:.3g} s (fewer "
                f"than {STEPS_PER_PERIOD} steps per period): the integrator damps them; drop "
                "them (modes, frequency_range) or lower the step (tolerance, max_step)"
            )
    return out


def spin_warnings(system, trajectory) -> list[str]:
    """A warning per flexible body without geometric stiffening that spins (its frame's
    angular velocity along `trajectory`) fast enough that the centrifugal stiffness
    matters: spin^2 above SPIN_LIMIT of its held frequency^2 (the lowest frequency of the
    body held at one interface node). A linear modal body's bending softens as it spins
    (Kane's spin-up beam lags 17 % too much at 1.05 times its held frequency)."""
    out = []
    for a in system.flexible:
        comp = a.body.component
        if comp.geometric is not None or not comp.held_frequency or not len(trajectory):
            continue
        cols = slice(7 * a.frame + 3, 7 * a.frame + 7)
        spin = np.linalg.norm(
            omega_body(np.asarray(trajectory.q)[:, cols], np.asarray(trajectory.qd)[:, cols]),
            axis=1,
        )
        i = int(np.argmax(spin))
        if spin[i] ** 2 > SPIN_LIMIT * comp.held_frequency**2:
            out.append(
                f"flexible body {a.name}: at t = {trajectory.time[i]:.6g} s it spins at "
                f"{spin[i]:.4g} rad/s, {spin[i] / comp.held_frequency:.2g} times its lowest "
                f"frequency held at one interface node ({comp.held_frequency:.4g} rad/s): "
                "without geometric stiffening its bending softens as it spins instead of "
                "stiffening; set stiffening: true"
            )
    return out
