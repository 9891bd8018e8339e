"""A rigid system's constraint equations evaluated in one compiled call.

The grouped path (`System.grouped_phi_and_jacobian`) calls one kernel per primitive group
and assembles the coordinate rows in NumPy: about 30 us of Python per call on a
slider-crank, more than the arithmetic. Here the same equations (normalisations, spherical,
dot-1 and dot-2 rows, and the coordinate equations: motions, locks, couplers, gears,
screws) are one kernel call: `System.phi`, `phi_q`, `phi_and_jacobian`, `gamma` and
`commit` use them once the kernels are compiled, and the compiled generalized-alpha step
(mechlib.solvers.genalpha.compiled), the saddle matrix (mechlib.system.saddle) and the toggle check
call them from compiled code. Same primitives, same formulas (mechlib.kinematics.kernels,
mechlib.kinematics.coordinates): results equal to round-off. Systems with flexible bodies or
point-on-curve joints keep the grouped path.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics import kernels as kr
from mechlib.kinematics.constraints import Dot1, Dot2, Normalization, Spherical
from mechlib.kinematics.coordinate_block import CoordinateBlock
from mechlib.kinematics.kin import GROUND_Q

__all__ = ["DENSE_ROW", "ConstraintArrays", "pack_rows", "selected_pack"]

_TWO_PI = 2.0 * math.pi
_NO_INT = np.zeros(0, dtype=np.int64)
_NO_VEC = np.zeros((0, 3))
_ROW_BODIES = 4  # bodies a row's columns are recorded for (more: the row is dense)
_DENSE = -2
DENSE_ROW = _DENSE  # row_bodies' mark of a row over more bodies than _ROW_BODIES: filled whole


def _group(groups: list, kind, width: int) -> tuple:
    """The arguments of the system's group of `kind` (empty arrays without one)."""
    found = [g for g in groups if type(g) is kind]
    if found:
        return found[0].args
    return (_NO_INT, _NO_INT) + (_NO_VEC,) * width


class ConstraintArrays:
    """The constraint equations of a rigid `System` packed for the compiled kernels in two
    flat arrays, `ints` and `floats` (`packed()`: the geometric groups, the coordinate
    block's measures and coefficients, the active rows; rebuilt when an event changes the
    block or the active rows), and per time `functions(t)` (value, rate and acceleration of
    each coordinate equation's function) and `references()` (the angles' unwrapping
    references). Few arguments, because numba's dispatch costs about 0.2 us per array."""

    def __init__(self, system):
        assert self.eligible(system), "checked by the caller"
        self.system = system
        self._key: tuple = ()  # what `packed` was made from
        self._angle_args: tuple | None = None
        self._bodies: np.ndarray | None = None
        self._packed: tuple[np.ndarray, np.ndarray] = (_NO_INT, np.zeros(0))

    @staticmethod
    def eligible(system) -> bool:
        """Rigid bodies of 7 coordinates, primitive groups only (no flexible welds), no
        point-on-curve equations."""
        if getattr(system, "per_body", 0) != 7 or system.nz or system.flexible:
            return False
        kinds = (Normalization, Spherical, Dot1, Dot2)
        if not all(type(g) in kinds for g in system.groups):
            return False
        return not system.coordinate_rows().own

    def packed(self) -> tuple[np.ndarray, np.ndarray]:
        """(ints, floats) of the current block and active rows (`_unpack` reads them)."""
        system = self.system
        block: CoordinateBlock = system.coordinate_rows()
        key = self._key  # the objects themselves: an id may be reused
        if not key or key[0] is not block or key[1] != block.size or key[2] is not system.active:
            self._packed, self._key = _pack(system, block), (block, block.size, system.active)
        return self._packed

    def phi_and_jacobian(self, k) -> tuple[np.ndarray, np.ndarray]:
        """(phi, phi_q) of the active rows at state k (mechlib.system.system.System's)."""
        ints, floats = self.packed()
        m = self.system.active.size
        phi, jac = np.empty(m), np.empty((m, self.system.nq))
        phi_and_jacobian(
            k.x, ints, floats, self.functions(k.t, "value"), self.references(), phi, jac
        )
        return phi, jac

    def functions(self, t: float, parts: str = "value rate accel") -> np.ndarray:
        """(equations, 3): value, rate and acceleration of each coordinate equation's
        function of time at t, those named in `parts` (the others and equations without a
        function: zeros). The kernels read only what they need: phi the values, nu and
        gamma the rates and accelerations."""
        block = self.system.coordinate_rows()
        out = np.zeros((len(block.linear), 3))
        wanted = [(c, name) for c, name in enumerate(("value", "rate", "accel")) if name in parts]
        for row, i in enumerate(block.linear):
            f = block.equations[i].function
            if f is not None:
                for c, name in wanted:
                    out[row, c] = getattr(f, name)(t)
        return out

    def bodies(self) -> np.ndarray:
        """The rigid bodies' mass terms in one array for the kernels: gravity (3), masses
        (nb), the Euler parameters' normalising scale (nb), inertia tensors (nb x 9)."""
        if self._bodies is None:
            system = self.system
            self._bodies = np.concatenate(
                [system.gravity, system.masses, system.pscale, system.inertia.ravel()]
            ).astype(float)
        return self._bodies

    def nu_and_gamma(self, k) -> tuple[np.ndarray, np.ndarray]:
        """(nu, gamma) of the active rows at state k (right sides of phi_q qd = nu and
        phi_q qdd = gamma)."""
        ints, floats = self.packed()
        m = self.system.active.size
        nu, gamma = np.empty(m), np.empty(m)
        nu_and_gamma(
            k.x, k.xd, ints, floats, self.functions(k.t, "rate accel"), self.references(), nu, gamma
        )
        return nu, gamma

    def phi(self, k) -> np.ndarray:
        """phi of the active rows at state k, without the Jacobian."""
        ints, floats = self.packed()
        out = np.empty(self.system.active.size)
        phi_values(k.x, ints, floats, self.functions(k.t, "value"), self.references(), out)
        return out

    def commit_angles(self, k) -> None:
        """Every angle measure of the system takes its value at state k as its unwrapping
        reference (mechlib.kinematics.coordinates.AngleMeasure.commit, in one call)."""
        angles = self.system.angle_measures
        if not angles:
            return
        if self._angle_args is None:
            self._angle_args = measure_args([m.sine_cosine for m in angles], 4)
        refs = np.array([m.reference for m in angles])
        ai, aj, au, av = self._angle_args
        angle_values(k.x, ai, aj, au, av, refs)
        for m, value in zip(angles, refs):
            m.reference = float(value)

    def references(self) -> np.ndarray:
        """The angle measures' unwrapping references (rad), in the block's order."""
        return np.array([m.reference for m in self.system.coordinate_rows().angles])


def measure_args(groups: list, width: int) -> tuple:
    """The arguments of primitive groups (the Dot1 pairs of angle measures, width 4, or the
    Dot2 rows of travel measures, width 5) joined, empty arrays without any."""
    if not groups:
        return (_NO_INT,) * 2 + (_NO_VEC,) * (width - 2)
    return tuple(np.concatenate([g.args[j] for g in groups]) for j in range(width))


def _row_bodies(nb: int, sph, dot1, dot2, block: CoordinateBlock) -> np.ndarray:
    """(rows, _ROW_BODIES): the moving bodies whose columns each equation's row may fill
    (ground's are cut), -1 for none; a row of more bodies (a coordinate equation over many
    joints) is marked _DENSE."""
    rows = [[k] for k in range(nb)]
    rows += [[int(i), int(j)] for i, j in zip(*sph[:2]) for _ in range(3)]
    rows += [[int(i), int(j)] for i, j in zip(*dot1[:2])]
    rows += [[int(i), int(j)] for i, j in zip(*dot2[:2])]
    measures: list = [*block.angles, *block.travels]
    for row in block._coefficients:
        rows.append([b for c, m in zip(row, measures) if c != 0.0 for b in (m.bi, m.bj)])
    out = np.full((len(rows), _ROW_BODIES), -1, dtype=np.int64)
    for r, bodies in enumerate(rows):
        moving = sorted({b for b in bodies if b != nb})
        if len(moving) > _ROW_BODIES:
            out[r, 0] = _DENSE
        else:
            out[r, : len(moving)] = moving
    return out


def pack_rows(system, block: CoordinateBlock) -> tuple[np.ndarray, np.ndarray]:
    """`ConstraintArrays.packed`'s (ints, floats) of any object with a system's `groups`,
    `nb` and `active` rows, and coordinate block `block` (mechlib.flexible.packed: the rigid
    rows of a system with modal bodies)."""
    return _pack(system, block)


def _pack(system, block: CoordinateBlock) -> tuple[np.ndarray, np.ndarray]:
    """ints: a header of sizes (nb, spherical items, dot-1 rows, dot-2 rows, angles,
    travels, coordinate equations, active rows), then the body indices of each group, the
    equations' rows, the active rows; floats: each group's vectors, the coefficients."""
    sph = _group(system.groups, Spherical, 2)
    dot1 = _group(system.groups, Dot1, 2)
    dot2 = _group(system.groups, Dot2, 3)
    sines = block._sines.args if block._sines is not None else (_NO_INT,) * 2 + (_NO_VEC,) * 2
    travels = (
        block._distances.args if block._distances is not None else (_NO_INT,) * 2 + (_NO_VEC,) * 3
    )
    linear = np.asarray(block.linear, dtype=np.int64)
    header = [
        system.nb,
        len(sph[0]),
        len(dot1[0]),
        len(dot2[0]),
        len(block.angles),
        len(travels[0]),
        len(linear),
        len(system.active),
    ]
    groups = (sph, dot1, dot2, sines, travels)
    ints = np.concatenate(
        [np.array(header, dtype=np.int64)]
        + [np.asarray(a, dtype=np.int64) for g in groups for a in g[:2]]
        + [linear, np.asarray(system.active, dtype=np.int64)]
        + [_row_bodies(system.nb, sph, dot1, dot2, block).ravel()]
    )
    floats = np.concatenate(
        [np.asarray(a, dtype=float).ravel() for g in groups for a in g[2:]]
        + [np.asarray(block._coefficients, dtype=float).ravel()]
    )
    return ints, floats


class _Selection:
    """The groups, size and active rows `_pack` reads, of a system's rows cut to some."""

    def __init__(self, groups: list, nb: int, active: np.ndarray):
        self.groups, self.nb, self.active = groups, nb, active


def selected_pack(system, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ints, floats) of a pack (`ConstraintArrays.packed`) of only the items of the
    geometric groups that fill the system's `rows` (indices into all its rows), beside every
    normalisation and the whole coordinate block; its active rows are `rows`, renumbered:
    `unpacked_rows` of it fills those rows alone, each by the same kernel and arithmetic
    as the whole pack (a joint's reactions read its own rows: mechlib.kinematics.reactions)."""
    block: CoordinateBlock = system.coordinate_rows()
    nb = system.nb
    groups, renumbered = [], np.asarray(rows, dtype=np.int64).copy()
    start, new_start = nb, nb
    for kind in (Spherical, Dot1, Dot2):
        found = [g for g in system.groups if type(g) is kind]
        per = kind.rows_per_item
        count = len(found[0].args[0]) if found else 0
        inside = (rows >= start) & (rows < start + per * count)
        items = np.unique((rows[inside] - start) // per)
        if len(items):
            groups.append(kind(*(a[items] for a in found[0].args)))
            position = np.searchsorted(items, (rows[inside] - start) // per)
            renumbered[inside] = new_start + per * position + (rows[inside] - start) % per
        start, new_start = start + per * count, new_start + per * len(items)
    coordinate = rows >= start
    renumbered[coordinate] = rows[coordinate] - start + new_start
    return _pack(_Selection(groups, nb, renumbered), block)


@njit(**KERNEL, inline="always")
def _full_rows(x, nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj, phi, rows):
    """Residuals and Jacobian rows (nall, 7 (nb+1)) of the geometric groups, in the
    system's row order; `rows` zeroed by the caller. Returns the first coordinate row."""
    kr.norm_phi(x, nb, phi[:nb])
    kr.norm_jac(x, nb, rows[:nb])
    r = nb
    n = 3 * sbi.shape[0]
    kr.sph_phi(x, sbi, sbj, ssi, ssj, phi[r : r + n])
    kr.sph_jac(x, sbi, sbj, ssi, ssj, rows[r : r + n])
    r += n
    n = d1i.shape[0]
    kr.dot1_phi_jac(x, d1i, d1j, d1u, d1v, phi[r : r + n], rows[r : r + n])
    r += n
    n = d2i.shape[0]
    if n:  # its kernels make their work arrays before the loop
        kr.dot2_phi_jac(x, d2i, d2j, d2v, d2si, d2sj, phi[r : r + n], rows[r : r + n])
    return r + n


@njit(**KERNEL, inline="always")
def body_terms(body, nb):
    """(gravity (3,), masses (nb,), Euler-parameter scales (nb,), inertia tensors (nb, 3,
    3)): views of `ConstraintArrays.bodies`' array."""
    inertia = body[3 + 2 * nb : 3 + 11 * nb].reshape((nb, 3, 3))
    return body[:3], body[3 : 3 + nb], body[3 + nb : 3 + 2 * nb], inertia


@njit(**KERNEL)
def state_arrays(q, qd, nb):
    """x, xd (nb+1, 7) of (q, qd) with ground appended (mechlib.kinematics.kin.Kin.from_state)."""
    x, xd = np.empty((nb + 1, 7)), np.empty((nb + 1, 7))
    state_into(q, qd, x, xd)
    return x, xd


@njit(**KERNEL)
def state_into(q, qd, x, xd):
    """`state_arrays` written into x, xd (nb+1, 7): no allocation in a loop of iterations."""
    nb = x.shape[0] - 1
    for b in range(nb):
        for c in range(7):
            x[b, c] = q[7 * b + c]
            xd[b, c] = qd[7 * b + c]
    for c in range(7):
        x[nb, c] = GROUND_Q[c]
        xd[nb, c] = 0.0


@njit(**KERNEL)
def angle_values(x, ai, aj, au, av, refs):
    """Angles atan2(S, C) (rad) of the measures whose sine and cosine dot-1 pairs are
    given, unwrapped against `refs`, written over `refs`."""
    sc = np.empty(ai.shape[0])
    kr.dot1_phi(x, ai, aj, au, av, sc)
    for i in range(refs.shape[0]):
        raw = math.atan2(sc[2 * i], sc[2 * i + 1])
        refs[i] = raw + _TWO_PI * np.round((refs[i] - raw) / _TWO_PI)


@njit(**KERNEL)
def measure_rows(x, ai, aj, au, av, ti, tj, tv, tsi, tsj, refs, values, grads):
    """Values (rad, m) and gradients (rows of 7 (nb+1)) of angle measures (their sine and
    cosine dot-1 pairs; atan2(S, C) unwrapped against `refs`) then travel measures
    (dot-2 rows), into `values` and the zeroed `grads` (mechlib.kinematics.coordinates)."""
    na = refs.shape[0]
    ncol = grads.shape[1]
    sc = np.empty(2 * na)
    sc_rows = np.zeros((2 * na, ncol))
    kr.dot1_phi(x, ai, aj, au, av, sc)
    kr.dot1_jac(x, ai, aj, au, av, sc_rows)
    for i in range(na):
        s, c = sc[2 * i], sc[2 * i + 1]
        raw = math.atan2(s, c)
        values[i] = raw + _TWO_PI * np.round((refs[i] - raw) / _TWO_PI)
        r2 = s * s + c * c
        for j in range(ncol):
            grads[i, j] = (c * sc_rows[2 * i, j] - s * sc_rows[2 * i + 1, j]) / r2
    kr.dot2_phi(x, ti, tj, tv, tsi, tsj, values[na:])
    kr.dot2_jac(x, ti, tj, tv, tsi, tsj, grads[na:])


@njit(**KERNEL)
def _coordinate_rows(
    x, ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, functions, refs, first, phi, rows
):
    """The coordinate equations' residuals and rows (coef @ measures - f(t)) from row
    `first` on."""
    if linear.shape[0] == 0:
        return
    nm = refs.shape[0] + ti.shape[0]
    values = np.empty(nm)
    grads = np.zeros((nm, rows.shape[1]))
    measure_rows(x, ai, aj, au, av, ti, tj, tv, tsi, tsj, refs, values, grads)
    for e in range(linear.shape[0]):
        row = first + linear[e]
        acc = 0.0
        for m in range(nm):
            acc += coef[e, m] * values[m]
        phi[row] = acc - functions[e, 0]
        for m in range(nm):
            if coef[e, m] != 0.0:
                for j in range(rows.shape[1]):
                    rows[row, j] += coef[e, m] * grads[m, j]


@njit(**KERNEL)
def row_count(ints):
    """The pack's rows, active or not (`ConstraintArrays.packed`'s ints): Euler-parameter
    norms, 3 a spherical group, the dot-1 and dot-2 rows, the coordinate equations."""
    return ints[0] + 3 * ints[1] + ints[2] + ints[3] + ints[6]


@njit(**KERNEL)
def unpack(ints, floats):
    """The arrays `_pack` laid out: (nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j,
    d2v, d2si, d2sj, ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, active,
    row_bodies), views."""
    nb, ns, n1, n2, na, nt, ne, nact = ints[:8]
    o = 8
    sbi, sbj = ints[o : o + ns], ints[o + ns : o + 2 * ns]
    o += 2 * ns
    d1i, d1j = ints[o : o + n1], ints[o + n1 : o + 2 * n1]
    o += 2 * n1
    d2i, d2j = ints[o : o + n2], ints[o + n2 : o + 2 * n2]
    o += 2 * n2
    ai, aj = ints[o : o + 2 * na], ints[o + 2 * na : o + 4 * na]
    o += 4 * na
    ti, tj = ints[o : o + nt], ints[o + nt : o + 2 * nt]
    o += 2 * nt
    linear = ints[o : o + ne]
    active = ints[o + ne : o + ne + nact]
    o += ne + nact
    nall = nb + 3 * ns + n1 + n2 + ne
    row_bodies = ints[o : o + _ROW_BODIES * nall].reshape((nall, _ROW_BODIES))
    f = 0
    ssi = floats[f : f + 3 * ns].reshape((ns, 3))
    ssj = floats[f + 3 * ns : f + 6 * ns].reshape((ns, 3))
    f += 6 * ns
    d1u = floats[f : f + 3 * n1].reshape((n1, 3))
    d1v = floats[f + 3 * n1 : f + 6 * n1].reshape((n1, 3))
    f += 6 * n1
    d2v = floats[f : f + 3 * n2].reshape((n2, 3))
    d2si = floats[f + 3 * n2 : f + 6 * n2].reshape((n2, 3))
    d2sj = floats[f + 6 * n2 : f + 9 * n2].reshape((n2, 3))
    f += 9 * n2
    au = floats[f : f + 6 * na].reshape((2 * na, 3))
    av = floats[f + 6 * na : f + 12 * na].reshape((2 * na, 3))
    f += 12 * na
    tv = floats[f : f + 3 * nt].reshape((nt, 3))
    tsi = floats[f + 3 * nt : f + 6 * nt].reshape((nt, 3))
    tsj = floats[f + 6 * nt : f + 9 * nt].reshape((nt, 3))
    f += 9 * nt
    coef = floats[f : f + ne * (na + nt)].reshape((ne, na + nt))
    return (
        nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj,
        ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, active, row_bodies,
    )  # fmt: skip


@njit(**KERNEL)
def phi_and_jacobian(x, ints, floats, functions, refs, phi, jac):
    """phi (m,) and phi_q (m, 7 nb) of the active rows at x (nb+1, 7), into phi and jac;
    (ints, floats) from `ConstraintArrays.packed`, `functions` and `refs` at the time."""
    unpacked_phi_and_jacobian(x, unpack(ints, floats), functions, refs, phi, jac)


@njit(**KERNEL)
def unpacked_phi_and_jacobian(x, packed, functions, refs, phi, jac):
    """`phi_and_jacobian` of the pack unpacked once (`unpack`: about 1 us a call, as much
    as a third of the Jacobian of a few bodies)."""
    nall = row_count_unpacked(packed)
    full = np.empty(nall)
    rows = np.empty((nall, x.shape[0] * 7))
    phi_and_jacobian_in(x, packed, functions, refs, phi, jac, full, rows)


@njit(**KERNEL, inline="always")
def phi_and_jacobian_in(x, packed, functions, refs, phi, jac, full, rows):
    """`unpacked_phi_and_jacobian` in the work arrays full (`row_count`,) and rows
    (`row_count`, 7 (nb+1)), zeroed here: a loop of rows makes them once. The coordinate
    equations are evaluated only when one of them is active (a call with 17 arguments
    costs 0.17 us even when it returns at once: at every dense row's Newton iterate)."""
    (
        nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj,
        ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, active, _,
    ) = packed  # fmt: skip
    full[:] = 0.0
    rows[:] = 0.0
    first = _full_rows(
        x, nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj, full, rows
    )
    if _any_from(active, first):  # only active rows are read (`unpacked_rows`)
        _coordinate_rows(
            x, ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, functions, refs, first, full,
            rows,
        )  # fmt: skip
    nq = 7 * nb
    for i in range(active.shape[0]):
        phi[i] = full[active[i]]
        for j in range(nq):
            jac[i, j] = rows[active[i], j]


@njit(**KERNEL)
def phi_values(x, ints, floats, functions, refs, phi):
    """phi (m,) of the active rows at x (nb+1, 7), without the Jacobian rows."""
    unpacked_phi_values(x, unpack(ints, floats), functions, refs, phi)


@njit(**KERNEL)
def unpacked_phi_values(x, packed, functions, refs, phi):
    """`phi_values` of the pack unpacked once (`unpack`)."""
    (
        nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj,
        ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, active, _,
    ) = packed  # fmt: skip
    ns, n1, n2 = 3 * sbi.shape[0], d1i.shape[0], d2i.shape[0]
    first = nb + ns + n1 + n2
    full = np.empty(first + linear.shape[0])
    kr.norm_phi(x, nb, full[:nb])
    kr.sph_phi(x, sbi, sbj, ssi, ssj, full[nb : nb + ns])
    kr.dot1_phi(x, d1i, d1j, d1u, d1v, full[nb + ns : nb + ns + n1])
    kr.dot2_phi(x, d2i, d2j, d2v, d2si, d2sj, full[nb + ns + n1 : first])
    if linear.shape[0]:
        na = refs.shape[0]
        values = np.empty(na + ti.shape[0])
        values[:na] = refs
        angle_values(x, ai, aj, au, av, values[:na])
        kr.dot2_phi(x, ti, tj, tv, tsi, tsj, values[na:])
        for e in range(linear.shape[0]):
            acc = 0.0
            for m in range(values.shape[0]):
                acc += coef[e, m] * values[m]
            full[first + linear[e]] = acc - functions[e, 0]
    for i in range(active.shape[0]):
        phi[i] = full[active[i]]


@njit(**KERNEL)
def constraint_rows(x, ints, floats, functions, refs, full, rows):
    """Residuals `full` and Jacobian rows `rows` (all rows, 7 (nb+1)) at x, filled only in
    the column blocks of each row's bodies and ground's (the rest of `rows` is left as it
    was: read it with `times` and `transpose_times`), the coordinate equations only when
    one of them is active (read the active rows alone). Returns (active rows,
    row bodies) of the pack."""
    return unpacked_rows(x, unpack(ints, floats), functions, refs, full, rows)


@njit(**KERNEL, inline="always")
def unpacked_rows(x, packed, functions, refs, full, rows):
    """`constraint_rows` of the pack unpacked once (`unpack`: a loop of Newton
    iterations unpacks it once, not at every iteration)."""
    (
        nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj,
        ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, active, row_bodies,
    ) = packed  # fmt: skip
    g = 7 * nb
    for r in range(full.shape[0]):
        if row_bodies[r, 0] == _DENSE:
            rows[r, :] = 0.0
            continue
        for c in range(_ROW_BODIES):
            b = row_bodies[r, c]
            if b >= 0:
                rows[r, 7 * b : 7 * b + 7] = 0.0
        rows[r, g : g + 7] = 0.0
    first = _full_rows(
        x, nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj, full, rows
    )
    if _any_from(active, first):
        _coordinate_rows(
            x, ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, functions, refs, first, full,
            rows,
        )  # fmt: skip
    return active, row_bodies


@njit(**KERNEL)
def _any_from(active, first):
    """Whether an active row is a coordinate equation (row `first` on): rows no caller
    reads are not evaluated (a redundant coordinate equation left inactive cost 2 us of
    the 5 of the four-bar's rows at every Newton iteration)."""
    for i in range(active.shape[0]):  # noqa: SIM110 -- numba compiles no generator in any()
        if active[i] >= first:
            return True
    return False


@njit(**KERNEL)
def transpose_times(rows, active, row_bodies, lam, out):
    """out (7 nb,) = phi_q^T lam over the active rows of `constraint_rows`' `rows`."""
    out[:] = 0.0
    nq = out.shape[0]
    for i in range(active.shape[0]):
        r, weight = active[i], lam[i]
        if weight == 0.0:
            continue
        if row_bodies[r, 0] == _DENSE:
            for j in range(nq):
                out[j] += weight * rows[r, j]
            continue
        for c in range(_ROW_BODIES):
            b = row_bodies[r, c]
            if b >= 0:
                for j in range(7 * b, 7 * b + 7):
                    out[j] += weight * rows[r, j]


@njit(**KERNEL)
def times(rows, active, row_bodies, v, out):
    """out (m,) = phi_q v over the active rows of `constraint_rows`' `rows`."""
    nq = v.shape[0]
    for i in range(active.shape[0]):
        r = active[i]
        acc = 0.0
        if row_bodies[r, 0] == _DENSE:
            for j in range(nq):
                acc += rows[r, j] * v[j]
        else:
            for c in range(_ROW_BODIES):
                b = row_bodies[r, c]
                if b >= 0:
                    for j in range(7 * b, 7 * b + 7):
                        acc += rows[r, j] * v[j]
        out[i] = acc


@njit(**KERNEL)
def nu_and_gamma(x, xd, ints, floats, functions, refs, nu, gamma):
    """The right sides of phi_q qd = nu and phi_q qdd = gamma of the active rows at (x, xd)
    (mechlib.kinematics.constraints, mechlib.kinematics.coordinates: the same formulas)."""
    unpacked_nu_and_gamma(x, xd, unpack(ints, floats), functions, refs, nu, gamma)


@njit(**KERNEL)
def unpacked_nu_and_gamma(x, xd, packed, functions, refs, nu, gamma):
    """`nu_and_gamma` of the pack unpacked once (`unpack`)."""
    unpacked_gamma(x, xd, packed, functions, refs, gamma, np.empty(row_count_unpacked(packed)))
    unpacked_nu_values(packed, functions, nu)


@njit(**KERNEL, inline="always")
def row_count_unpacked(packed):
    """The number of rows (active or not) of the pack unpacked (`unpack`)."""
    return _coordinates_first(packed) + packed[24].shape[0]


@njit(**KERNEL, inline="always")
def _coordinates_first(packed):
    """The first coordinate equation's row of the pack unpacked (`unpack`): after the
    Euler-parameter norms, 3 rows a spherical group, the dot-1 and dot-2 rows."""
    nb, sbi, d1i, d2i = packed[0], packed[1], packed[5], packed[9]
    return nb + 3 * sbi.shape[0] + d1i.shape[0] + d2i.shape[0]


@njit(**KERNEL, inline="always")
def unpacked_gamma(x, xd, packed, functions, refs, gamma, full):
    """gamma (m,) of the active rows at (x, xd): `nu_and_gamma`'s gamma without its nu, in
    the work array `full` (`row_count_unpacked` rows; each row it reads is written first)."""
    (
        nb, sbi, sbj, ssi, ssj, d1i, d1j, d1u, d1v, d2i, d2j, d2v, d2si, d2sj,
        _, _, _, _, _, _, _, _, _, _, _, active, _,
    ) = packed  # fmt: skip
    ns, n1, n2 = 3 * sbi.shape[0], d1i.shape[0], d2i.shape[0]
    first = nb + ns + n1 + n2
    kr.norm_gamma(xd, nb, full[:nb])
    kr.sph_gamma(x, xd, sbi, sbj, ssi, ssj, full[nb : nb + ns])
    kr.dot1_gamma(x, xd, d1i, d1j, d1u, d1v, full[nb + ns : nb + ns + n1])
    kr.dot2_gamma(x, xd, d2i, d2j, d2v, d2si, d2sj, full[nb + ns + n1 : first])
    if _any_from(active, first):  # an active coordinate equation (`unpacked_rows`)
        _coordinate_gamma(x, xd, packed, functions, refs, first, full)
    for i in range(active.shape[0]):
        gamma[i] = full[active[i]]


@njit(**KERNEL)
def _coordinate_gamma(x, xd, packed, functions, refs, first, full):
    """gamma of the coordinate equations into full[first:] (`unpacked_gamma`)."""
    (
        _, _, _, _, _, _, _, _, _, _, _, _, _, _,
        ai, aj, au, av, ti, tj, tv, tsi, tsj, coef, linear, _, _,
    ) = packed  # fmt: skip
    na, nt = refs.shape[0], ti.shape[0]
    sc, scd, scq = np.empty(2 * na), np.empty(2 * na), np.empty(2 * na)
    kr.dot1_phi(x, ai, aj, au, av, sc)
    kr.dot1_rate(x, xd, ai, aj, au, av, scd)
    kr.dot1_gamma(x, xd, ai, aj, au, av, scq)
    quads = np.empty(na + nt)
    for i in range(na):
        s, c, sd, cd = sc[2 * i], sc[2 * i + 1], scd[2 * i], scd[2 * i + 1]
        sq, cq = -scq[2 * i], -scq[2 * i + 1]
        r2 = s * s + c * c
        rate = (c * sd - s * cd) / r2
        quads[i] = (c * sq - s * cq) / r2 - 2.0 * rate * (s * sd + c * cd) / r2
    kr.dot2_gamma(x, xd, ti, tj, tv, tsi, tsj, quads[na:])
    for m in range(nt):
        quads[na + m] = -quads[na + m]
    for e in range(linear.shape[0]):
        acc = 0.0
        for m in range(na + nt):
            acc += coef[e, m] * quads[m]
        full[first + linear[e]] = functions[e, 2] - acc


@njit(**KERNEL)
def nu_values(ints, floats, functions, nu):
    """nu (m,) of the active rows: `nu_and_gamma`'s nu without its gamma (it reads no
    state: the time functions' rates of the coordinate rows, zero elsewhere)."""
    unpacked_nu_values(unpack(ints, floats), functions, nu)


@njit(**KERNEL, inline="always")
def unpacked_nu_values(packed, functions, nu):
    """`nu_values` of the pack unpacked once (`unpack`)."""
    _active_nu(_coordinates_first(packed), packed[24], packed[25], functions, nu)


@njit(**KERNEL)
def _active_nu(first, linear, active, functions, nu):
    """nu (m,) of the active rows: the rate functions[e, 1] of coordinate
    equation e (row first + linear[e]; the last such e where two share a row), zero for
    every other row (no array made)."""
    for i in range(active.shape[0]):
        nu[i] = 0.0
        for e in range(linear.shape[0]):
            if first + linear[e] == active[i]:
                nu[i] = functions[e, 1]


@njit(**KERNEL)
def scaled_row(q, packed, scale, work, jac):
    """At state q (7 nb,): the active constraint rows scaled per column by `scale` and each
    to unit length (jac (m, 7 nb): zero rows stay zero): what mechlib.checks.singularity
    measures at a recorded row. `packed`: the constraints unpacked (`unpack`); `work`:
    `row_work`'s arrays, reused from row to row (no array made: two a row before)."""
    full, rows, refs, functions, x, xd = work
    nq = q.shape[0]
    state_into(q, q, x, xd)
    active, _ = unpacked_rows(x, packed, functions, refs, full, rows)
    for i in range(active.shape[0]):
        r = active[i]
        norm = 0.0
        for j in range(nq):
            v = rows[r, j] * scale[j]
            jac[i, j] = v
            norm += v * v
        if norm > 0.0:
            reciprocal = 1.0 / math.sqrt(norm)
            for j in range(nq):
                jac[i, j] *= reciprocal


def row_work(ints: np.ndarray, nq: int) -> tuple:
    """Work arrays of `scaled_row` for a pack (`ConstraintArrays.packed`'s ints): the rows
    start at zero (`constraint_rows` fills only their bodies' blocks); then the state
    arrays x, xd (nb+1, 7: `state_into`)."""
    nall, ne = row_count(ints), ints[6]
    x, xd = np.empty((nq // 7 + 1, 7)), np.empty((nq // 7 + 1, 7))
    return np.zeros(nall), np.zeros((nall, nq + 7)), np.zeros(ints[4]), np.zeros((ne, 3)), x, xd
