"""Analysis settings (what to compute) and the trajectory an analysis records."""

from __future__ import annotations

import functools
import math
from bisect import bisect_right
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from mechlib.model.step_feed import GrowingGrid, StepFeed
from mechlib.model.step_grid import StepGrid

__all__ = [
    "DEFAULT_MAX_STEPS",
    "DEFAULT_TOLERANCE",
    "BranchCheck",
    "Dynamic",
    "InitialBodyVelocity",
    "InitialModes",
    "InitialValue",
    "Kinematic",
    "Modes",
    "Phase",
    "Phases",
    "QuasiStatic",
    "Static",
    "Trajectory",
    "output_times",
    "row_times",
    "same_times",
]

DEFAULT_TOLERANCE = 1e-6
DEFAULT_MAX_STEPS = 500_000  # accepted + rejected steps: a few minutes of CPU, small model


@dataclass(frozen=True)
class _Timed:
    """Output every `step` s from `start` to `end` (s); at most `max_steps` steps (accepted
    and rejected: integrator steps, or output times and their sub-steps)."""

    end: float
    step: float
    start: float = 0.0
    max_steps: int = DEFAULT_MAX_STEPS


@dataclass(frozen=True)
class Kinematic(_Timed):
    """Motions fix every degree of freedom; output every `step` s from `start` to `end`."""

    name = "kinematic"


@dataclass(frozen=True)
class Static:
    """One equilibrium at `time` (s), motions held at their value, inertia ignored."""

    time: float = 0.0
    name = "static"


@dataclass(frozen=True)
class QuasiStatic(_Timed):
    """A sequence of static equilibria along the motions, every `step` s to `end`."""

    name = "quasi-static"


@dataclass(frozen=True)
class Dynamic(_Timed):
    """Equations of motion integrated in time.

    `tolerance`: relative local error per step (absolute parts scaled by the mechanism's
    size); `integrator`: `generalized-alpha` (index-3, Arnold & Bruls 2007) or `radau`
    (scipy Radau IIA on the index-1 form with projection, for cross-checks); `max_step` (s);
    `rho_inf`: spectral radius at infinity of generalized-alpha (numerical damping);
    `fixed_step`: take exactly `step` per step, no error control (for convergence studies);
    `grid`: with dense output and generalized-alpha, the steps follow these step ends
    instead of the error control (mechlib.model.step_grid.StepGrid: no error test; or a
    GrowingGrid, mechlib.model.step_feed: another run's, made as that run is solved);
    `feed`: a StepFeed the run records its step ends and events in as it goes (what a
    GrowingGrid follows);
    `dense`: the steps do not land on the output times (their size is the error control's,
    up to `max_step` or the mechanism's natural time), the rows between them come from
    dense output (mechlib.solvers.dense). A case's dynamic analysis is dense unless it says
    `output: steps` (loadcases.build); this dataclass's own default stays False.
    `rows`: output times (s) recorded besides every `step` (`row_times`): the accuracy
    companion's rows at another run's one-row spikes and about its extreme crests
    (loadcases.run.companion.sparser).
    `compiled`: the compiled paths generalized-alpha may take where the model allows them,
    all with the same steps and results to round-off (tests/mechlib/test_genalpha_run.py;
    with force elements a whole run's iteration matrix differs, its results agree to the
    Newton tolerance):
    `runs` (whole runs of steps in one compiled call, mechlib.solvers.genalpha.run), `steps`
    (every step from Python, its Newton loop and dense rows compiled) or `python` (none:
    the reference the compiled paths are tested against).
    """

    tolerance: float = DEFAULT_TOLERANCE
    integrator: str = "generalized-alpha"
    max_step: float | None = None
    rho_inf: float = 0.9
    fixed_step: bool = False
    dense: bool = False
    compiled: str = "runs"
    grid: StepGrid | GrowingGrid | None = None
    feed: StepFeed | None = None
    rows: tuple[float, ...] = ()
    name = "dynamic"

    def __post_init__(self) -> None:
        if self.compiled not in COMPILED_PATHS:
            raise ValueError(f"Dynamic.compiled is one of {COMPILED_PATHS}, not {self.compiled!r}")
        if self.grid is not None and not (
            self.dense and not self.fixed_step and self.integrator == "generalized-alpha"
        ):
            raise ValueError("Dynamic.grid needs dense output and generalized-alpha steps")


COMPILED_PATHS = ("runs", "steps", "python")


@dataclass(frozen=True)
class Phase:
    """One analysis of a sequence (`Phases`): a `Static` at its `time`, or a `QuasiStatic`
    or `Dynamic` from its `start` to its `end` (s). `locks`: joints held at their
    coordinate of the phase's first state while it lasts (hinges fixed for a preload);
    `motions`: the motions driving in this phase (None: all; the others switched off)."""

    analysis: Static | QuasiStatic | Dynamic
    name: str = ""
    locks: tuple[str, ...] = ()
    motions: tuple[str, ...] | None = None

    @property
    def start(self) -> float:
        """Time of the phase's first state (s)."""
        return float(getattr(self.analysis, "start", getattr(self.analysis, "time", 0.0)))


@dataclass(frozen=True)
class Phases:
    """Analyses in sequence, each starting from the state where the last ended: its
    positions, its rates after a dynamic phase (after a static or quasi-static one, the
    rates the motions prescribe: the bodies at rest), element states and events carried.
    An event's `stop` ends the phase it fires in (the next starts there)."""

    phases: tuple[Phase, ...]
    name = "phases"

    def __post_init__(self) -> None:
        if not self.phases:
            raise ValueError("Phases needs at least one phase")

    @property
    def start(self) -> float:
        """Time of the first phase's first state (s)."""
        return self.phases[0].start


@dataclass(frozen=True)
class Modes:
    """An analysis of the normal modes about the equilibrium at `time` (s)."""

    time: float = 0.0
    count: int | None = None  # how many modes to report (None: all)
    name = "modes"


@dataclass(frozen=True)
class InitialValue:
    """A joint coordinate (rad or m) and/or its rate given for the start of an analysis;
    `guess`: a coordinate to assemble near (the branch of a loop), not imposed."""

    joint: str
    value: float | None = None
    rate: float | None = None
    coordinate: str | None = None
    guess: float | None = None


@dataclass(frozen=True)
class BranchCheck:
    """When a run is said to leave the assembly branch of its drawn geometry (or of the
    guesses): a joint `angle` (rad) from its guess, a loop that cannot reach the given
    values on that branch, a snap-through between rows; `error`: such a change fails the
    run instead of a warning."""

    angle: float = math.radians(30.0)
    error: bool = False


@dataclass(frozen=True)
class InitialBodyVelocity:
    """A body's angular velocity (rad/s) and/or cm velocity (m/s), global axes."""

    body: str
    omega: Sequence[float] | None = None
    velocity: Sequence[float] | None = None


@dataclass(frozen=True)
class InitialModes:
    """A flexible body's modal coordinates `modes` (kg^0.5 m, one per mode) and/or their
    rates `rates` (kg^0.5 m/s) given for the start of an analysis; `static`: its modal
    coordinates instead those of its quasi-static deflection at the start (the elastic
    forces balance the loads, reactions and inertia of the motion there: no modal
    acceleration), in a dynamic analysis."""

    body: str
    modes: Sequence[float] | None = None
    rates: Sequence[float] | None = None
    static: bool = False


def output_times(start: float, end: float, step: float) -> np.ndarray:
    """Output grid start, start+step, ..., end (end always included), read-only: the
    grids of a campaign's runs are the same and made once per process."""
    return _output_times(float(start), float(end), float(step))


def row_times(spec: _Timed) -> np.ndarray:
    """The output times of `spec` after its start: every `step` and, for a `Dynamic`, its
    extra `rows` (s) within the run, sorted, those within 1e-9 s of another left out;
    read-only."""
    times = output_times(spec.start, spec.end, spec.step)[1:]
    extra = np.asarray(getattr(spec, "rows", ()), dtype=float)
    extra = extra[(extra > spec.start) & (extra < spec.end)]
    if not len(extra):
        return times
    near = np.searchsorted(times, extra)
    before = np.abs(extra - times[np.maximum(near - 1, 0)])
    after = np.abs(times[np.minimum(near, len(times) - 1)] - extra)
    extra = np.unique(extra[np.minimum(before, after) > 1e-9])
    merged = np.sort(np.concatenate((times, extra)))
    # read-only as the plain grid: the compiled run's kernels take one array type (a
    # writable one compiled, and each process loaded, a second run_steps: 0.14 s)
    merged.flags.writeable = False
    return merged


@functools.lru_cache(maxsize=8)  # a set's runs share a few grids; long grids weigh MB each
def _output_times(start: float, end: float, step: float) -> np.ndarray:
    n = int(np.floor((end - start) / step + 1e-9))
    # rounded to 12 significant digits: 0.6, not 0.6000000000000001, in the results
    times = np.array([float(f"{start + step * i:.12g}") for i in range(n + 1)])
    if end - times[-1] > 1e-9 * max(step, 1.0):
        times = np.append(times, end)
    times.flags.writeable = False
    return times


def same_times(t: np.ndarray, among: np.ndarray) -> np.ndarray:
    """Which times `t` (s) are one of `among` (s, sorted) to 1e-12 of the time (bool per
    time of t): an output time is the same number wherever it is made (`output_times`)."""
    if not len(among) or not len(t):
        return np.zeros(len(t), dtype=bool)
    k = np.searchsorted(among, t)
    before = np.abs(among[np.maximum(k - 1, 0)] - t)
    near = np.minimum(before, np.abs(among[np.minimum(k, len(among) - 1)] - t))
    return near <= 1e-12 * np.maximum(1.0, np.abs(t))


def _stack(rows: list) -> np.ndarray:
    """Rows (arrays of one length) as a (rows, width) float array (a copy)."""
    if not rows:
        return np.empty((0, 0))
    return np.array(rows, dtype=float).reshape(len(rows), -1)


class Snapshots:
    """The system snapshot of each recorded row (`System.snapshot`: active equations, angle
    references...): dicts appended one by one, or the rows of a compiled run, which share
    one base snapshot and differ only in their angle references (and element states), kept
    as arrays and made into a dict when a row's is read (most are never read: the outputs
    restore one per batch of rows)."""

    def __init__(self) -> None:
        self._rows: list[dict | None] = []  # None: in a block, not made yet
        # (first, base, keys, refs, element states per row or None)
        self._blocks: list[tuple[int, dict, tuple, np.ndarray, np.ndarray | None]] = []
        self._firsts: list[int] = []  # of the blocks

    def __len__(self) -> int:
        return len(self._rows)

    def append(self, snapshot: dict) -> None:
        self._rows.append(snapshot)

    def extend(self, snapshots) -> None:
        self._rows.extend(snapshots)

    def extend_block(
        self, base: dict, keys: Sequence, refs: np.ndarray, states: np.ndarray | None = None
    ) -> None:
        """Rows whose snapshots are `base` with the angle references `keys` set to each
        row of `refs` (rows, keys), and its element states to each row of `states` (rows,
        nz) when given."""
        kept = None if states is None else np.array(states, dtype=float)
        self._blocks.append((len(self._rows), base, tuple(keys), np.array(refs, dtype=float), kept))
        self._firsts.append(len(self._rows))
        self._rows.extend([None] * len(refs))

    def __getitem__(self, i: int) -> dict:
        found = self._rows[i]
        if found is None:
            first, base, keys, refs, states = self._block(i)
            row = i % len(self._rows) - first
            angles = dict(base["angles"])
            angles.update(zip(keys, refs[row].tolist()))
            found = dict(base, angles=angles)
            if states is not None:
                found["states"] = states[row].copy()
            self._rows[i] = found
        return found

    def angle_references(self, key) -> np.ndarray:
        """The unwrapping reference (rad) of joint angle `key` ((joint, "angle")) in every
        row's snapshot (n,), read from the blocks' arrays without making their dicts."""
        out = np.empty(len(self._rows))
        for i, found in enumerate(self._rows):
            if found is not None:
                out[i] = found["angles"][key]
        for first, base, keys, refs, _ in self._blocks:
            rows = slice(first, first + len(refs))
            out[rows] = refs[:, keys.index(key)] if key in keys else base["angles"][key]
        return out

    def active(self, i: int):
        """Row i's active equations (the snapshot's `active`), without making its dict."""
        found = self._rows[i]
        return found["active"] if found is not None else self._block(i)[1]["active"]

    def same_active(self, first: int, most: int) -> int:
        """The end of the rows from `first` on (at most `most`) whose snapshots hold the
        same active equations (the same array: a run keeps it between events); a block's
        rows share their base's."""
        active = self.active(first)
        end, limit = first + 1, min(len(self._rows), first + most)
        while end < limit:
            found = self._rows[end]
            if found is None:
                start, base, _, refs, _ = self._block(end)
                if base["active"] is not active:
                    break
                end = min(start + len(refs), limit)
            elif found["active"] is not active:
                break
            else:
                end += 1
        return end

    def block_of(self, i: int) -> tuple[int, dict, tuple, np.ndarray, np.ndarray | None]:
        """The block row i is in: (its first row, base snapshot, angle keys, their
        references by row, element states by row or None)."""
        return self._block(i)

    def _block(self, i: int) -> tuple[int, dict, tuple, np.ndarray, np.ndarray | None]:
        return self._blocks[bisect_right(self._firsts, i % len(self._rows)) - 1]

    def __delitem__(self, rows: slice) -> None:
        """Drop the rows from `rows.start` on (Trajectory.trim)."""
        if rows.stop is not None or rows.step is not None:
            raise ValueError("only the rows from an index on can be dropped")
        n = len(range(*rows.indices(len(self._rows))))
        end = len(self._rows) - n
        del self._rows[end:]
        self._blocks = [
            (k, b, keys, r[: end - k], None if z is None else z[: end - k])
            for k, b, keys, r, z in self._blocks
            if k < end
        ]
        self._firsts = [b[0] for b in self._blocks]

    def __iter__(self) -> Iterator[dict]:
        return (self[i] for i in range(len(self)))


@dataclass
class Trajectory:
    """States recorded at output times: q, qd, qdd (n, nq) and multipliers lam (n, m).

    `snapshot()` (e.g. `System.references`) is stored with each row, so that outputs read
    joint angles unwrapped as the solver tracked them, however far they turn between rows.
    `at_rest`: the states are equilibria (static, quasi-static): force elements were
    evaluated without velocities, and their outputs must be too; qd holds the rates the
    motions prescribe, for the kinematic outputs.
    """

    snapshot: Callable[[], dict] | None = None
    check: Callable[..., None] | None = None
    at_rest: bool = False
    time: list = field(default_factory=list)
    q: list = field(default_factory=list)
    qd: list = field(default_factory=list)
    qdd: list = field(default_factory=list)
    lam: list = field(default_factory=list)
    references: Snapshots = field(default_factory=Snapshots)
    # the rows recorded at an event's instant, before its actions (mechlib.solvers.march),
    # which no output time asked for
    event_rows: list[int] = field(default_factory=list)
    # (first row, block (n, 3 nq + m), nq) of each `extend`: its rows are views of it
    _blocks: list = field(default_factory=list, repr=False)

    def record(self, t: float, q, qd, qdd, lam, snapshot: dict | None = None) -> None:
        """Append a row; `snapshot`: the system's snapshot to keep with it (default: taken
        now). A non-finite state stops the run here (`check`)."""
        if self.check is not None:
            self.check(t, q, qd, qdd, lam)
        if snapshot is None:
            snapshot = self.snapshot() if self.snapshot else {}
        self.references.append(snapshot)
        self.time.append(float(t))
        self.q.append(np.array(q, dtype=float))
        self.qd.append(np.array(qd, dtype=float))
        self.qdd.append(np.array(qdd, dtype=float))
        self.lam.append(np.array(lam, dtype=float))

    def extend(
        self,
        times,
        states: np.ndarray,
        nq: int,
        snapshot: dict,
        keys: Sequence,
        refs,
        element_states: np.ndarray | None = None,
    ) -> None:
        """Append rows found finite already (a compiled run's): times (n,), states (n,
        3 nq + m) with q, qd, qdd, lam stacked; their snapshots are `snapshot` with the
        angle references `keys` set to each row of `refs` (n, keys) and the element states
        to each row of `element_states` (n, nz) when given."""
        block = np.array(states, dtype=float)  # one copy; the rows are views of it
        self._blocks.append((len(self.time), block, nq))
        self.references.extend_block(snapshot, keys, refs, element_states)
        self.time.extend(np.asarray(times, dtype=float).tolist())
        self.q.extend(block[:, :nq])
        self.qd.extend(block[:, nq : 2 * nq])
        self.qdd.extend(block[:, 2 * nq : 3 * nq])
        self.lam.extend(block[:, 3 * nq :])

    def stacked(self, name: str, first: int = 0, end: int | None = None) -> np.ndarray:
        """Rows first..end-1 of `name` (q, qd, qdd or lam) as one (rows, width) array, not
        to be written to: slices of the blocks compiled runs recorded them in (a view when
        one block holds them all), the rows recorded one by one copied."""
        end = len(self) if end is None else end
        rows, parts, row = getattr(self, name), [], first
        for start, block, nq in self._blocks:  # in row order
            stop = start + len(block)
            if stop <= row or start >= end:
                continue
            if start > row:
                parts.append(_stack(rows[row:start]))
            low, high = {"q": (0, nq), "qd": (nq, 2 * nq), "qdd": (2 * nq, 3 * nq)}.get(
                name, (3 * nq, block.shape[1])
            )
            row, top = max(row, start), min(end, stop)
            parts.append(block[row - start : top - start, low:high])
            row = top
        if row < end or not parts:
            parts.append(_stack(rows[row:end]))
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    def same_active(self, first: int, most: int) -> int:
        """The end of the rows from `first` on (at most `most`) recorded with the same
        active equations (the same array, as a run keeps it between events)."""
        return self.references.same_active(first, most)

    def without(self, times: np.ndarray) -> Trajectory:
        """These rows but the output rows at `times` (s, sorted: `same_times`), in a new
        trajectory (an event's row stays): the rows of a compiled run's blocks kept in
        blocks."""
        t = np.asarray(self.time, dtype=float)
        dropped = same_times(t, np.asarray(times, dtype=float))
        dropped[self.event_rows] = False
        keep = np.flatnonzero(~dropped)
        owner = np.full(len(t), -1)
        for b, (first, block, _) in enumerate(self._blocks):
            owner[first : first + len(block)] = b
        out = Trajectory(self.snapshot, self.check, self.at_rest)
        out.event_rows = np.searchsorted(keep, self.event_rows).tolist()
        if not len(keep):
            return out
        for rows in np.split(keep, np.flatnonzero(np.diff(owner[keep])) + 1):
            if owner[rows[0]] < 0:
                for i in rows.tolist():
                    out.references.append(self.references[i])
                    out.time.append(self.time[i])
                    for name in ("q", "qd", "qdd", "lam"):
                        getattr(out, name).append(getattr(self, name)[i])
                continue
            first, block, nq = self._blocks[owner[rows[0]]]
            _, base, keys, refs, states = self.references.block_of(int(rows[0]))
            local = rows - first
            chosen = None if states is None else states[local]
            out.extend(t[rows], block[local], nq, base, keys, refs[local], chosen)
        return out

    def trim(self) -> None:
        """Drop a row that an interrupt left half-appended (all lists to the shortest)."""
        rows = self._fields()
        n = min(len(rows_) for rows_ in rows)
        for rows_ in rows:
            del rows_[n:]
        self._blocks = [(k, b[: n - k], nq) for k, b, nq in self._blocks if k < n]
        self.event_rows = [i for i in self.event_rows if i < n]

    def _fields(self) -> tuple[list | Snapshots, ...]:
        return (self.references, self.time, self.q, self.qd, self.qdd, self.lam)

    def __len__(self) -> int:
        return len(self.time)
