"""Internal states of force elements: first-order ODEs dz/dt = f(t, state, z) integrated
with the mechanism (a damper's elongation in a Maxwell element, a controller integrator,
hydraulic pressures).

An element with states declares `n_states`, `initial_states()` and
`state_rates(view, z) -> dz/dt`, and reads its current z with `view.states(self)`. Every
analysis in time advances them by the trapezoidal rule over each step, solved for the
mechanism's new state by a small Newton of their own, which makes them A-stable and second
order like the mechanism. Its Jacobian is block diagonal by element: an element's
`state_jacobian(view, z)` when it has one, else forward differences of its own rates. They
are advanced: in a dynamic analysis at every Newton
iterate of a step; a quasi-static one at every iterate of each equilibrium (the view at
rest, as its forces see it); a kinematic one at each solved position (its velocities
included). A static analysis solves one instant, with no time to integrate over: the
states keep their initial values there.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.differences import fd_step
from mechlib.core.jit import KERNEL, njit

__all__ = ["NEWTON_ITERATIONS", "ElementStates", "residual_size"]

NEWTON_ITERATIONS = 20  # the most iterations of the states' Newton in one advance
_RTOL, _ATOL = 1e-12, 1e-14  # converged: each residual within 1e-12 of its state (1e-14 abs)


@njit(**KERNEL)
def residual_size(res, z):
    """max_i |res_i| / (1e-12 |z_i| + 1e-14): the states' Newton has converged at or below
    1 (the one rule of the Python advance and of compiled ones,
    mechlib.elements.hydraulics.valve_states)."""
    worst = 0.0
    for i in range(res.shape[0]):
        size = abs(res[i]) / (_RTOL * abs(z[i]) + _ATOL)
        if size > worst or size != size:  # a NaN stays: never converged
            worst = size
    return worst


class ElementStates:
    """Accepted values `z`, the trial values of the step under way, and their rates."""

    def __init__(self, elements):
        self.slices: dict[int, slice] = {}
        start = 0
        for e in elements:
            n = int(getattr(e, "n_states", 0))
            if n:
                self.slices[id(e)] = slice(start, start + n)
                start += n
        self.owners = [e for e in elements if id(e) in self.slices]
        self.z = (
            np.concatenate([np.asarray(e.initial_states(), float) for e in self.owners])
            if self.owners
            else np.zeros(0)
        )
        self.trial = self.z.copy()
        self.rates_accepted: np.ndarray | None = None
        # states that no force reads (`states_drive_forces = False`: an integral kept as an
        # output, e.g. a clearance joint's wear work) have rates independent of z: one
        # explicit trapezoid per advance, and no part in the mechanism's tangent
        self.drive_forces = any(getattr(e, "states_drive_forces", True) for e in self.owners)
        # every owner advances its own states in one compiled call (`advance_trial`): the
        # Jacobian is block diagonal, so the blocks' Newtons are the one Newton's
        self.compiled = bool(self.owners) and all(
            getattr(e, "compiled_states", False) for e in self.owners
        )
        self._lu: tuple | None = None  # factored Newton matrix of `advance`, at step _lu_h
        self._lu_h = 0.0
        self._h = 0.0  # the step (s) of the trial values
        # (rates, step in s) of the accepted state before the current one: the local error
        # estimate's history (None at the start and after a resume)
        self._previous: tuple[np.ndarray, float] | None = None

    def __bool__(self) -> bool:
        return bool(self.owners)

    def of(self, element) -> np.ndarray:
        """The current (trial) states of one element."""
        return self.trial[self.slices[id(element)]]

    def rates(self, view, z: np.ndarray) -> np.ndarray:
        saved, self.trial = self.trial, z
        try:
            return np.concatenate(
                [np.asarray(e.state_rates(view, z[self.slices[id(e)]]), float) for e in self.owners]
            )
        finally:
            self.trial = saved

    def start(self, view) -> None:
        """Rates at the accepted state (the trapezoidal rule's first half)."""
        self.trial = self.z.copy()
        self.rates_accepted = self.rates(view, self.z)

    def advance(self, view, h: float) -> None:
        """Trial z at the iterate `view` after a step h: z = z_n + h/2 (f_n + f(z)).

        Modified Newton: the factored matrix I - h/2 df/dz is kept across iterations and
        calls while it contracts (residual at least 4x smaller per iteration), refreshed
        when it does not or h changed. Converged when each residual is within 1e-12 of its
        state (1e-14 absolute): a pressure of 1e7 Pa and a spool travel of 1e-5 m each at
        their own scale."""
        self._h = h
        if not self.drive_forces:  # rates independent of z: the trapezoid is explicit
            self.trial = self.z + 0.5 * h * (self.rates_accepted + self.rates(view, self.z))
            return
        if self.compiled:
            assert self.rates_accepted is not None, "start() gives the accepted rates"
            trial = self.trial.copy()
            for e in self.owners:
                block = self.slices[id(e)]
                e.advance_trial(view, self.z[block], self.rates_accepted[block], trial[block], h)
            self.trial = trial
            return
        # LAPACK's getrf / getrs directly: the routines scipy's lu_factor / lu_solve call
        # (the same numbers), without their checks, about 35 us a call on these few states
        from scipy.linalg.lapack import dgetrf, dgetrs  # here: a System without states needs none

        z = self.trial.copy()
        prev, fresh = np.inf, False
        for _ in range(NEWTON_ITERATIONS):
            rates = self.rates(view, z)
            res = z - self.z - 0.5 * h * (self.rates_accepted + rates)
            size = residual_size(res, z)
            if size <= 1.0:
                break
            if self._lu is None or self._lu_h != h or (size > 0.25 * prev and not fresh):
                matrix = np.eye(z.size) - 0.5 * h * self.jacobian(view, z, rates)
                lu, pivots, info = dgetrf(matrix)
                if info < 0:  # pragma: no cover - an argument error, never a singular matrix
                    raise ValueError(f"element states: LAPACK getrf argument {-info} is illegal")
                self._lu, self._lu_h, fresh = (lu, pivots), h, True
            else:
                fresh = False
            z = z - dgetrs(*self._lu, res)[0]
            prev = size
        self.trial = z

    def compiled_step(self, h: float) -> None:
        """A compiled caller advances the trial values in place over a step h (s)
        (mechlib.solvers.genalpha.compiled.loaded_newton, with this class's rule)."""
        self._h = h

    def jacobian(self, view, z: np.ndarray, rates: np.ndarray) -> np.ndarray:
        """d(dz/dt)/dz at `z` (rates: dz/dt there), block diagonal: an element's rates
        depend on its own states only. An element's `state_jacobian(view, z_e)` gives its
        block; otherwise forward differences of its own `state_rates`."""
        jac = np.zeros((z.size, z.size))
        for e in self.owners:
            block = self.slices[id(e)]
            ze = z[block]
            own = getattr(e, "state_jacobian", None)
            if own is not None:
                jac[block, block] = own(view, ze)
                continue
            base = rates[block]
            for i in range(ze.size):
                dz = fd_step(ze[i])
                zi = ze.copy()
                zi[i] += dz
                jac[block, block.start + i] = (
                    np.asarray(e.state_rates(view, zi), float) - base
                ) / dz
        return jac

    def local_error(self, h: float) -> np.ndarray | None:
        """Estimated local error (nz,) of the trial values after a step h (s): the
        trapezoidal rule's h^3/12 z(3) by Milne's device, its difference from the explicit
        second-order predictor z_n + h f_n + h^2/2 (f_n - f_(n-1))/k (k the previous step)
        times h / (3 (h + k)) (Taylor expansion of both about t_n). None without a previous
        accepted step."""
        if self._previous is None or self.rates_accepted is None:
            return None
        before, k = self._previous
        f = self.rates_accepted
        predicted = self.z + h * f + 0.5 * h * h * (f - before) / k
        return (self.trial - predicted) * (h / (3.0 * (h + k)))

    def accept(self, view) -> None:
        if self.rates_accepted is not None and self._h > 0.0:
            self._previous = (self.rates_accepted, self._h)
        self.z = self.trial.copy()
        self.rates_accepted = self.rates(view, self.z)

    def reject(self) -> None:
        self.trial = self.z.copy()

    def mark(self, view) -> tuple[np.ndarray, np.ndarray]:
        """(z, dz/dt) of the trial values at the state `view`: what `resume` goes on from."""
        return self.trial.copy(), self.rates(view, self.trial)

    def resume(self, mark: tuple[np.ndarray, np.ndarray]) -> None:
        """Make a `mark` the accepted values (a step starts from there)."""
        self.z, self.rates_accepted = mark[0].copy(), mark[1]
        self.trial = self.z.copy()
        self._previous = None
