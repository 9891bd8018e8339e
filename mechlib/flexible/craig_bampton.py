"""Craig-Bampton reduction of a free-free FEModel to orthonormal modes (seed 003 eqs 1.3-1.8).

Basis T = [[I, 0], [Phi_IC, Phi_IN]] (interface DOF first): constraint modes
Phi_IC = -K_II^-1 K_IB and fixed-interface normal modes Phi_IN of (K_II, M_II). The reduced
K^ = T^T K T, M^ = T^T M T is orthonormalised, K^ N = M^ N Lambda (eqs 1.6-1.8), after the
six rigid-body motions (exact in the reduced coordinates: constraint modes reproduce rigid
motion) are removed: the eigenproblem is solved in their M^-orthogonal complement. So the
kept modes are free-free approximations plus boundary eigenvectors, each with a frequency,
all orthogonal to rigid motion (a linearised mean-axis frame: I3 = I4 = 0).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from mechlib.flexible.fe_model import COMPONENTS, FEModel
from mechlib.flexible.invariants import field_invariants
from mechlib.flexible.modal_component import ModalComponent, damping_ratios
from mechlib.flexible.stiffening import modal_geometric

__all__ = [
    "ReductionError",
    "basis",
    "canonical",
    "craig_bampton",
    "elastic_mass_problem",
    "free_modes",
    "signed",
]

_RIGID_ENERGY = 1e-8  # |K R| / (|K| |R|) above this: the rigid motions strain the model
_MECHANISM = 1e-12  # omega^2 / max(omega^2) below this: a zero-energy deformation
_DEGENERATE = 1e-8  # relative: eigenvalues this close are one group of modes (canonical)
_DENSE_LIMIT = 600  # internal DOF up to which the fixed-interface modes come from eigh
_TIE = 1e-6  # relative: entries this close to a mode's largest in magnitude tie with it (`signed`)


class ReductionError(ValueError):
    """The FE model cannot be reduced as asked (says why)."""


def _split(model: FEModel) -> tuple[np.ndarray, np.ndarray]:
    if not model.interface:
        raise ReductionError("a Craig-Bampton reduction needs at least one interface node")
    boundary = np.flatnonzero(np.isin(model.dof_map[:, 0], model.interface))
    return boundary, np.setdiff1d(np.arange(len(model.dof_map)), boundary)


def _fixed_interface(k_ii, m_ii, count: int) -> np.ndarray:
    """The `count` lowest fixed-interface modes (n_i, count)."""
    n = k_ii.shape[0]
    if count == 0:
        return np.zeros((n, 0))
    if n <= _DENSE_LIMIT or count >= n - 1:
        _, vec = sla.eigh(k_ii.toarray(), m_ii.toarray(), subset_by_index=[0, count - 1])
        return signed(vec)
    # ARPACK's own start vector is random (its generator's state depends on the calls made
    # before in the process): the same model gave other mode shapes from run to run
    start = np.full(n, 1.0 / np.sqrt(n))
    _, vec = spla.eigsh(k_ii.tocsc(), k=count, M=m_ii.tocsc(), sigma=0.0, v0=start)
    return signed(vec)


def signed(vectors: np.ndarray) -> np.ndarray:
    """The columns of `vectors` with the sign that makes each one's largest entry in
    magnitude positive, the first of those within _TIE of the largest where several are: an
    eigenvector's sign is otherwise arbitrary, and a symmetric structure's mode has entries
    equal but for round-off (the Test Set crank's rod at its quarter points), which the
    LAPACK kernels of one machine and another order differently (two of its 24 modes came
    out flipped on an AVX-512 machine, and a case's modal initial values meant other
    shapes there)."""
    if vectors.size == 0:
        return vectors
    size = np.abs(vectors)
    rows = np.argmax(size >= (1.0 - _TIE) * size.max(axis=0), axis=0)
    flip = np.sign(vectors[rows, np.arange(vectors.shape[1])])
    return vectors * np.where(flip == 0.0, 1.0, flip)


def canonical(w2: np.ndarray, vectors: np.ndarray, mass) -> np.ndarray:
    """`vectors` (ndof, n), mass-normalised eigenvectors of the eigenvalues `w2` (n,)
    ascending, with a unique basis in each group of equal eigenvalues (within _DEGENERATE):
    eigh returns any rotation of such a group (a square section's two bending modes), so
    modal coordinates given by a user would mean another shape on another machine. The
    group's basis is the one that is 1 at one and 0 at the others of the entries chosen by
    QR with column pivoting (`_pivots`: largest first, rotation-invariant choices, ties to
    the first entry), made mass-orthonormal in the order of those entries."""
    out = vectors.copy()
    start = 0
    while start < len(w2):
        end = start + 1
        while end < len(w2) and w2[end] - w2[start] <= _DEGENERATE * abs(w2[end]):
            end += 1
        if end - start > 1:
            group = vectors[:, start:end]
            pivots = _pivots(group)
            unit = group @ np.linalg.inv(group[pivots])
            for c in range(end - start):
                v = unit[:, c] - out[:, start : start + c] @ (
                    out[:, start : start + c].T @ (mass @ unit[:, c])
                )
                out[:, start + c] = v / np.sqrt(v @ (mass @ v))
        start = end
    return out


def _pivots(group: np.ndarray) -> np.ndarray:
    """The k entries (rows of `group` (ndof, k)) that QR with column pivoting of group.T
    chooses (the largest remaining norm first), in ascending order; a tie within _TIE goes
    to the first entry. A symmetric structure's group ties exactly but for round-off (a
    square section's bending pair: an interface node's y and z displacements), and LAPACK's
    pivoting then chose by the machine's kernels (the Test Set crank's rod: another basis,
    and its case's modal initial values other shapes, on an AVX-512 machine)."""
    rest = np.array(group.T, dtype=float)  # (k, ndof): each entry's column
    chosen: list[int] = []
    for _ in range(group.shape[1]):
        norms = np.einsum("ij,ij->j", rest, rest)
        norms[chosen] = -1.0
        j = int(np.argmax(norms >= (1.0 - _TIE) ** 2 * norms.max()))
        chosen.append(j)
        unit = rest[:, j] / np.sqrt(norms[j])
        rest -= np.outer(unit, unit @ rest)
    return np.sort(np.array(chosen))


def basis(model: FEModel, fixed_interface_modes: int) -> np.ndarray:
    """The Craig-Bampton basis T (ndof, n_b + n_q): the interface DOF's n_b constraint
    modes, then the n_q = min(`fixed_interface_modes`, internal DOF) lowest
    fixed-interface modes (mass-normalised)."""
    b, i = _split(model)
    k, m = model.stiffness.tocsr(), model.mass.tocsr()
    k_ii = k[i][:, i]
    try:
        lu = spla.splu(k_ii.tocsc())
    except RuntimeError as exc:
        raise ReductionError(
            "the stiffness with the interface nodes held is singular: a part of the model "
            "is not connected to an interface node (a mechanism)"
        ) from exc
    constraint = -lu.solve(k[i][:, b].toarray())
    n_q = min(fixed_interface_modes, len(i))
    normal = _fixed_interface(k_ii, m[i][:, i], n_q)
    t = np.zeros((len(model.dof_map), len(b) + n_q))
    t[b, : len(b)] = np.eye(len(b))
    t[i, : len(b)] = constraint
    t[i, len(b) :] = normal
    return t


def free_modes(model: FEModel, fixed_interface_modes: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """(omega (n,) rad/s ascending, Psi (ndof, n) mass-normalised): every elastic mode of
    the Craig-Bampton basis, the six rigid-body motions removed."""
    omega, psi, _ = _reduce(model, fixed_interface_modes)
    return omega, psi


def _reduce(model: FEModel, fixed_interface_modes: int) -> tuple[np.ndarray, np.ndarray, float]:
    """`free_modes` and the held frequency (rad/s): the lowest frequency of the reduced
    model with one interface node's six boundary DOF held, the lowest over the nodes (a
    Rayleigh-Ritz value on the Craig-Bampton basis, exact when it is the only node)."""
    t = basis(model, fixed_interface_modes)
    k_hat, m_hat = t.T @ (model.stiffness @ t), t.T @ (model.mass @ t)
    b, _ = _split(model)
    rigid = _rigid(model, t)
    strain = np.linalg.norm(k_hat @ rigid) / (np.linalg.norm(k_hat) * np.linalg.norm(rigid))
    if strain > _RIGID_ENERGY:
        raise ReductionError(
            "the FE model is not free-free: rigid-body motions strain it (constrained DOF "
            "in the model?); fewer than six rigid-body modes"
        )
    complement = sla.null_space(rigid.T @ m_hat)
    m_elastic = complement.T @ m_hat @ complement
    problem = _mass_problem(model, t @ complement, m_elastic)
    if problem is not None:
        raise ReductionError(problem)
    w2, vec = sla.eigh(complement.T @ k_hat @ complement, m_elastic)
    zero = int(np.count_nonzero(w2 < _MECHANISM * w2.max(initial=0.0)))
    if zero:
        raise ReductionError(
            f"{6 + zero} zero-energy modes where exactly six rigid-body modes are expected: "
            "the model is a mechanism (parts joined only through interface nodes, or too few "
            "interface DOF to hold them)"
        )
    psi = signed(canonical(w2, t @ (complement @ vec), model.mass))
    return np.sqrt(w2), psi, _held(model.dof_map[b, 0], k_hat, m_hat)


def elastic_mass_problem(model: FEModel, fixed_interface_modes: int = 0) -> str | None:
    """Why the reduced mass off the six rigid motions is not positive definite (the
    eigenproblem of the reduction needs it), naming the DOF that moves most in a
    deformation without kinetic energy; or None. With no fixed-interface modes the basis
    is the constraint modes alone (Guyan): a check before any eigensolver."""
    t = basis(model, fixed_interface_modes)
    m_hat = t.T @ (model.mass @ t)
    complement = sla.null_space(_rigid(model, t).T @ m_hat)
    return _mass_problem(model, t @ complement, complement.T @ m_hat @ complement)


def _rigid(model: FEModel, t: np.ndarray) -> np.ndarray:
    """(k, 6): the rigid motions in reduced coordinates, [R_B; 0]."""
    b, _ = _split(model)
    rigid = np.zeros((t.shape[1], 6))
    rigid[: len(b)] = np.hstack([model.translation_field(), _rotation_field(model)])[b]
    return rigid


def _mass_problem(model: FEModel, motions: np.ndarray, m_elastic: np.ndarray) -> str | None:
    """`elastic_mass_problem` of `m_elastic` (k, k), whose coordinates move the DOF by
    `motions` (ndof, k)."""
    try:
        sla.cholesky(m_elastic, lower=True)  # what eigh does first with its B
        return None
    except np.linalg.LinAlgError:
        pass
    _, vectors = np.linalg.eigh(0.5 * (m_elastic + m_elastic.T))
    node, component = model.dof_map[int(np.argmax(np.abs(motions @ vectors[:, 0])))]
    return (
        "the mass matrix is not positive definite off the rigid-body motions: a deformation "
        f"has no kinetic energy, mostly on node {model.node_ids[node]} "
        f"{COMPONENTS[component]} (a DOF without mass, or a mass term missing from the file?)"
    )


def _held(boundary_nodes: np.ndarray, k_hat: np.ndarray, m_hat: np.ndarray) -> float:
    """The lowest frequency (rad/s) of the reduced model held at one of its interface nodes
    (boundary coordinates first, `boundary_nodes` their nodes), the lowest over the nodes."""
    lowest = np.inf
    for node in np.unique(boundary_nodes):
        free = np.r_[np.flatnonzero(boundary_nodes != node), len(boundary_nodes) : len(k_hat)]
        w2 = sla.eigh(k_hat[np.ix_(free, free)], m_hat[np.ix_(free, free)], eigvals_only=True)
        lowest = min(lowest, float(np.sqrt(max(w2[0], 0.0))))
    return lowest


def _rotation_field(model: FEModel) -> np.ndarray:
    return model.skew_field(model.coordinates, rotations=True)


def _select(omega: np.ndarray, modes: int | None, band: Sequence[float] | None) -> np.ndarray:
    """Indices of the kept modes: the lowest `modes`, or those in `band` (Hz)."""
    f = omega / (2.0 * np.pi)
    if band is not None:
        kept = np.flatnonzero((f >= band[0]) & (f <= band[1]))
        if kept.size == 0:
            raise ReductionError(
                f"no mode between {band[0]:g} and {band[1]:g} Hz "
                f"(the reduced model's modes: {f.min():.4g} to {f.max():.4g} Hz)"
            )
        return kept
    count = len(omega) if modes is None else modes
    if count > len(omega):
        raise ReductionError(
            f"{count} modes asked, the reduced model has {len(omega)}: raise fixed_interface_modes"
        )
    return np.arange(count)


def craig_bampton(
    model: FEModel,
    *,
    modes: int | None = None,
    frequency_range: Sequence[float] | None = None,
    fixed_interface_modes: int | None = None,
    damping: float | Mapping[int, float] | None = None,
    keep_nodes: Sequence[int] = (),
    stiffening: bool = False,
) -> ModalComponent:
    """The modal component of `model`: `modes` lowest elastic modes or those within
    `frequency_range` (Hz); `fixed_interface_modes` (default: enough for the modes asked,
    at least 10); `damping` as `damping_ratios`; slices kept at the interface nodes and
    the node indices `keep_nodes`; with `stiffening`, the modal geometric stiffness
    (mechlib.flexible.stiffening; beam models only, else ReductionError)."""
    n_q = fixed_interface_modes
    if n_q is None:
        n_q = max(10, modes or 0, 20 if frequency_range is not None else 0)
    omega, psi, held = _reduce(model, n_q)
    kept = _select(omega, modes, frequency_range)
    omega, psi = omega[kept], psi[:, kept]
    mass, origin, _ = model.rigid_properties()
    nodes = list(dict.fromkeys([*model.interface, *keep_nodes]))
    phi = np.zeros((len(nodes), 6, len(kept)))
    for row, node in enumerate(nodes):
        for dof in np.flatnonzero(model.dof_map[:, 0] == node):
            phi[row, model.dof_map[dof, 1]] = psi[dof]
    geometric = None
    if stiffening:
        try:
            geometric = modal_geometric(model, psi, origin, nodes)
        except ValueError as exc:
            raise ReductionError(str(exc)) from exc
    return ModalComponent(
        mass=mass,
        origin=origin,
        invariants=field_invariants(model, psi, origin),
        node_ids=model.node_ids[nodes],
        positions=model.coordinates[nodes] - origin,
        phi=phi[:, :3],
        phi_star=phi[:, 3:],
        frequencies=omega,
        damping=damping_ratios(omega / (2.0 * np.pi), damping),
        geometric=geometric,
        held_frequency=held,
    )
