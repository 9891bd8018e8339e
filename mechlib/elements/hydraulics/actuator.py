"""Hydraulic servo-actuator between two points, with its states integrated in the same
implicit step as the mechanism (mechlib.elements.states); equations in docs/hydraulics.md.

Stroke x = L - L_design (m, extension positive) of the distance L between the two points;
the actuator force F (N, extending positive) acts on both points along their line (tension
-F, as a spring's). Fidelities:
- `lag`: ideal position servo, stroke demand followed with a first-order lag,
  s' = K_v (x_cmd - s), the rod tied to s by the oil columns: F = k (s - x) + c (s' - x').
- `valve`: PI controller on e = x_cmd - x, spool as a second-order transfer function of
  the current, critically centred 4-land spool, two compressible chambers with leakage,
  piston friction.
- `jet_pipe`: the same with torque motor, jet pipe, receiver and spool (seed 004 ch. 6).
All three have end stops: one-sided spring-dampers beyond the stroke limits.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from mechlib.core.rotation import cross
from mechlib.elements.hydraulics.laws import chamber_rates, pack, piston_force, stop_force
from mechlib.elements.hydraulics.orifice import floored, spool_flows
from mechlib.elements.hydraulics.parameters import Controller, Cylinder, JetPipe, ServoValve, Supply
from mechlib.elements.hydraulics.stages import controller_current, jet_pipe_rates, valve_rates
from mechlib.elements.hydraulics.valve_states import (
    N_VALVE,
    advance_valve,
    chamber_wrench,
    stroke_line,
)
from mechlib.elements.hydraulics.valve_states import valve_rates as compiled_valve_rates
from mechlib.kinematics.view import StateView

__all__ = ["FIDELITIES", "LAG_DAMPING", "ServoActuator"]

FIDELITIES = ("lag", "valve", "jet_pipe")
LAG_DAMPING = 2.0e4  # N*s/m: zeta ~ 0.2 for 100 kg on the library oil columns
_N_STATES = {"lag": 1, "valve": 5, "jet_pipe": 7}
_STAGE_STATES = {"valve": 2, "jet_pipe": 4}  # after the integral, before p1, p2
_HYDRAULIC_UNITS = {
    "current": "A",
    "p1": "Pa",
    "p2": "Pa",
    "q1": "m^3/s",
    "q2": "m^3/s",
    "q_supply": "m^3/s",
    "q_return": "m^3/s",
    "power": "W",
    "throttling": "W",
}
_COMMON_UNITS = {"value": "N", "force": "N", "stroke": "m", "speed": "m/s", "command": "m"}


@dataclass
class ServoActuator:
    """Servo-actuator between `points` ((body, at), (body, at)): the rod end on the first,
    the cylinder on the second (only the line between them matters). `command(t)`: stroke
    demand (m) from the design length. `velocity_gain` (1/s, lag; None: the valve loop's
    K_v), `lag_stiffness` (N/m, lag; None: k_h at the design stroke), `lag_damping`
    (N*s/m). `initial_pressures` (Pa): (p1, p2); None: p1 A1 = p2 A2 with p1 + p2 = p_s +
    p_r (no force, a centred spool's null)."""

    name: str
    points: tuple[tuple[str, Sequence[float]], tuple[str, Sequence[float]]]
    command: Callable[[float], float]
    fidelity: str = "valve"
    cylinder: Cylinder = field(default_factory=Cylinder)
    supply: Supply = field(default_factory=Supply)
    valve: ServoValve = field(default_factory=ServoValve)
    controller: Controller = field(default_factory=Controller)
    jet_pipe: JetPipe = field(default_factory=JetPipe)
    velocity_gain: float | None = None
    lag_stiffness: float | None = None
    lag_damping: float = LAG_DAMPING
    initial_pressures: tuple[float, float] | None = None
    effect: str = "hydraulics"
    active: bool = True
    _geometry: tuple = field(default=(), repr=False)
    _design_length: float = field(default=math.nan, init=False, repr=False)
    _seen: tuple | None = field(default=None, init=False, repr=False)  # (view, x, x')
    _params: np.ndarray = field(default_factory=lambda: np.zeros(0), init=False, repr=False)

    def __post_init__(self) -> None:
        if self.fidelity not in FIDELITIES:
            raise ValueError(f"servo actuator {self.name}: fidelity must be one of {FIDELITIES}")
        self._pack()

    def _pack(self) -> None:
        """The parameters as the laws' kernels take them (mechlib.elements.hydraulics.laws)."""
        self._params = pack(self.cylinder, self.supply, self.valve, self.controller)

    @property
    def compiled_states(self) -> bool:
        """The states advance in one compiled call (`advance_trial`): the `valve` fidelity."""
        return self.fidelity == "valve"

    @property
    def n_states(self) -> int:
        return _N_STATES[self.fidelity]

    def state_scales(self) -> list[float]:
        """The size of each state for the integrator's error test (mechlib.solvers.
        error_weights), from the actuator's data: the servo stroke (lag) and the
        controller's integral (m s, over one second) by the stroke's span; the valve's
        normalised opening by 1 and its rate by the valve's frequency (rad/s); the jet pipe
        and spool positions by the rated opening (m), their rates by it times the valve's
        frequency; the chamber pressures by the supply pressure (Pa)."""
        lo, hi = self.cylinder.stroke
        span = hi - lo
        if self.fidelity == "lag":
            return [span]
        w = 2.0 * math.pi * self.valve.frequency
        if self.fidelity == "valve":
            stages = [1.0, w]
        else:
            x = self.jet_pipe.rated_opening
            stages = [x, x * w, x, x * w]
        p = self.supply.pressure
        return [span * 1.0, *stages, p, p]

    @property
    def output_units(self) -> dict[str, str]:
        if self.fidelity == "lag":
            return {**_COMMON_UNITS, "servo_stroke": "m"}
        extra = {"spool": "-"} if self.fidelity == "valve" else {"spool": "m", "jet": "m"}
        return {**_COMMON_UNITS, **_HYDRAULIC_UNITS, **extra}

    def loop_gain(self) -> float:
        """K_v (1/s) of the position loop: kp / i_R * Q_NL / A1, Q_NL the no-load flow
        Q_R sqrt((p_s - p_r)/dp_R) (Merritt: K_v = K_a K_sv K_q / A)."""
        v, s = self.valve, self.supply
        no_load = v.rated_flow * math.sqrt((s.pressure - s.return_pressure) / v.rated_pressure_drop)
        return self.controller.kp / v.rated_current * no_load / self.cylinder.area_1

    def bind(self, system) -> None:
        (b1, at1), (b2, at2) = self.points
        self._geometry = (*system.body_point(b1, at1), *system.body_point(b2, at2))
        self._design_length = float(np.linalg.norm(np.subtract(at1, at2)))
        self._pack()
        self._lag_gain = self.velocity_gain or self.loop_gain()
        self._lag_stiffness = self.lag_stiffness or self.cylinder.hydraulic_stiffness(0.0)

    def initial_states(self) -> list[float]:
        if self.fidelity == "lag":
            return [0.0]
        if self.initial_pressures is not None:
            p1, p2 = self.initial_pressures
        else:
            total, a1, a2 = (
                self.supply.pressure + self.supply.return_pressure,
                self.cylinder.area_1,
                self.cylinder.area_2,
            )
            p1, p2 = total * a2 / (a1 + a2), total * a1 / (a1 + a2)
        return [0.0] * (1 + _STAGE_STATES[self.fidelity]) + [p1, p2]

    # ---- kinematics -------------------------------------------------------------------
    def _line(self, view: StateView) -> tuple[float, float, np.ndarray]:
        """(stroke x (m), stroke rate x' (m/s), unit vector from point 2 to point 1)."""
        b1, s1, b2, s2 = self._geometry
        line = np.empty(5)
        stroke_line(view.kin.x, view.kin.xd, b1, s1, b2, s2, self._design_length, line)
        return float(line[0]), float(line[1]), line[2:5]

    def _stop_force(self, x: float, xd: float) -> float:
        """End stops (N, extending positive): laws.stop_force."""
        return stop_force(self._params, x, xd)

    # ---- states -----------------------------------------------------------------------
    def _stroke(self, view: StateView) -> tuple[float, float]:
        """(x (m), x' (m/s)) at `view`, found once per view (one line per Newton iterate)."""
        if self._seen is None or self._seen[0] is not view:
            self._seen = (view, *self._line(view)[:2])
        return self._seen[1], self._seen[2]

    def state_rates(self, view: StateView, z) -> list[float] | np.ndarray:
        x, xd = self._stroke(view)
        if self.fidelity == "valve":  # the compiled rates: the same laws as `_evaluate`'s
            out = np.empty(N_VALVE)
            demand = float(self.command(view.t))
            compiled_valve_rates(self._params, demand, x, xd, np.asarray(z, dtype=float), out)
            return out
        return self._evaluate(view.t, x, xd, z, view.at_rest)[0]

    def advance_trial(self, view: StateView, z0, f0, z: np.ndarray, h: float) -> None:
        """The `valve` states over a step h (s) from z0 (rates f0) to the iterate `view`:
        the trapezoidal rule solved in place in z (valve_states.advance_valve)."""
        x, xd = self._stroke(view)
        advance_valve(self._params, float(self.command(view.t)), x, xd, z0, f0, h, z)

    def _evaluate(
        self, t: float, x: float, xd: float, z, at_rest: bool = False
    ) -> tuple[list[float], dict[str, float]]:
        """(dz/dt, outputs) at time t, stroke x, rate xd and states z; `at_rest`: in an
        equilibrium, where the rod follows the servo piston without inertia, the oil
        columns' damping (lag) carries no force."""
        demand = float(self.command(t))
        out = {"stroke": x, "speed": xd, "command": demand}
        if self.fidelity == "lag":
            s = z[0]
            sd = self._lag_gain * (demand - s)
            force = self._lag_stiffness * (s - x)
            if not at_rest:
                force += self.lag_damping * (sd - xd)
            out.update(servo_stroke=s, force=force + self._stop_force(x, xd))
            return [sd], out
        current, integral_rate = controller_current(self.controller, demand - x, z[0])
        n = _STAGE_STATES[self.fidelity]
        stage, p1, p2 = z[1 : 1 + n], z[1 + n], z[2 + n]
        s = self.supply
        pf1, pf2 = (floored(p, s.vapour_pressure, s.floor_width) for p in (p1, p2))
        if self.fidelity == "valve":
            stage_rates, opening = valve_rates(self.valve, current, stage)
            out["spool"] = opening
        else:
            drop = s.pressure - s.return_pressure - math.copysign(1.0, stage[2]) * (pf1 - pf2)
            stage_rates, opening, more = jet_pipe_rates(
                self.jet_pipe, self.valve, current, stage, drop
            )
            out.update(more, spool=stage[2])
        flows = spool_flows(
            opening, pf1, pf2, s, self.valve.flow_gain, self.valve.transition_pressure
        )
        pressure_rates = self._chamber_rates(x, xd, pf1, pf2, flows.q1, flows.q2)
        out.update(
            current=current,
            p1=pf1,
            p2=pf2,
            q1=flows.q1,
            q2=flows.q2,
            q_supply=flows.q_supply,
            q_return=flows.q_return,
            power=s.pressure * flows.q_supply - s.return_pressure * flows.q_return,
            throttling=flows.throttling,
            force=self._piston_force(x, xd, pf1, pf2),
        )
        return [integral_rate, *stage_rates, *pressure_rates], out

    def _chamber_rates(self, x, xd, p1, p2, q1, q2) -> list[float]:
        """p1' = beta/V1 (q1 - A1 x' - q_L), p2' = beta/V2 (-q2 + A2 x' + q_L), q_L the
        leakage C_ip (p1 - p2) across the piston (seed 004 eqs. 6.8-6.12; laws.chamber_rates)."""
        return list(chamber_rates(self._params, x, xd, p1, p2, q1, q2))

    def _piston_force(self, x: float, xd: float, p1: float, p2: float) -> float:
        """p1 A1 - p2 A2 - gamma x' - F_c tanh(x'/v_c) + end stops (N, eq. 6.13;
        laws.piston_force)."""
        return piston_force(self._params, x, xd, p1, p2)

    # ---- element interface ------------------------------------------------------------
    def _state(self, view: StateView) -> tuple[dict[str, float], np.ndarray]:
        x, xd, u = self._line(view)
        out = self._evaluate(view.t, x, xd, view.states(self), view.at_rest)[1]
        out["value"] = -out["force"]
        return out, u

    def _force(self, view: StateView) -> tuple[float, np.ndarray]:
        """(F (N, extending positive), the unit vector of the line) at `view`: with
        chambers, the piston force of the floored pressures alone (what `_evaluate` gives,
        without the controller, valve and flows the states' rates need)."""
        x, xd, u = self._line(view)
        z = view.states(self)
        if self.fidelity == "lag":
            return self._evaluate(view.t, x, xd, z, view.at_rest)[1]["force"], u
        s = self.supply
        pf1, pf2 = (floored(p, s.vapour_pressure, s.floor_width) for p in (z[-2], z[-1]))
        return self._piston_force(x, xd, pf1, pf2), u

    def apply(self, view: StateView, F: np.ndarray, N: np.ndarray) -> None:
        b1, s1, b2, s2 = self._geometry
        if self.fidelity != "lag":  # the chambers' piston force, in one compiled call
            z = view.states(self)
            kin, length = view.kin, self._design_length
            chamber_wrench(kin.x, kin.xd, b1, s1, b2, s2, length, self._params, z[-2], z[-1], F, N)
            return
        actuator, u = self._force(view)
        for body, s, sign in ((b1, s1, 1.0), (b2, s2, -1.0)):
            force = sign * actuator * u
            F[body] += force
            N[body] += cross(view.point_position(body, s) - view.kin.r[body], force)

    def output(self, view: StateView) -> dict[str, float]:
        return self._state(view)[0]
