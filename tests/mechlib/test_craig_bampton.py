"""Craig-Bampton reduction, orthonormalisation and invariants (seed 003 eqs 1.3-1.8, Table 1.1).

References: the full FE model itself (its statics and free-free frequencies, scipy), and the
lumped-mass nodal sums of Table 1.1 as an oracle for the field-form invariants.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from mechlib.flexible.beam import Material, Section, assemble_beams
from mechlib.flexible.craig_bampton import ReductionError, canonical, craig_bampton, free_modes
from mechlib.flexible.fe_model import FEModel
from mechlib.flexible.modal_component import default_damping

STEEL = Material(E=210e9, nu=0.3, rho=7850.0)
SECTION = Section.rectangle(0.02, 0.03)


def _beam(n: int = 10, interface=(0, -1), bend: bool = True) -> FEModel:
    """A 1 m beam along x of n elements (kinked in y when `bend`, for 3-D coupling)."""
    xyz = np.outer(np.linspace(0.0, 1.0, n + 1), [1.0, 0.0, 0.0])
    if bend:
        xyz[:, 1] = 0.2 * xyz[:, 0] ** 2
        xyz[:, 2] = 0.05 * np.sin(3 * xyz[:, 0])
    elements = [(i, i + 1, SECTION, STEEL, (0.0, 0.3, 1.0)) for i in range(n)]
    return assemble_beams(xyz, elements, interface=tuple(i % (n + 1) for i in interface))


def _rigid(model: FEModel) -> np.ndarray:
    return np.hstack(
        [model.translation_field(), model.skew_field(model.coordinates, rotations=True)]
    )


def test_all_modes_reproduce_full_statics():
    """With every fixed-interface mode kept (T square), the modal static response to an
    inertia-relieved load equals the full FE solution M-orthogonal to rigid motion (1e-10;
    measured ~1e-13)."""
    model = _beam(10)
    n_internal = len(model.dof_map) - 12
    omega, psi = free_modes(model, n_internal)
    assert psi.shape[1] == len(model.dof_map) - 6
    k, m = model.stiffness.toarray(), model.mass.toarray()
    rigid = _rigid(model)
    f = np.random.default_rng(3).standard_normal(len(model.dof_map))
    f -= m @ rigid @ np.linalg.solve(rigid.T @ m @ rigid, rigid.T @ f)  # inertia relief
    saddle = np.block([[k, m @ rigid], [(m @ rigid).T, np.zeros((6, 6))]])
    exact = np.linalg.solve(saddle, np.r_[f, np.zeros(6)])[: len(f)]
    modal = psi @ ((psi.T @ f) / omega**2)
    assert np.abs(modal - exact).max() < 1e-10 * np.abs(exact).max()


def test_reduced_free_free_frequencies_match_the_full_model():
    """A curved beam of 20 elements, interface at both ends: with 20 fixed-interface modes
    the first six elastic frequencies are within 0.1 % of the full free-free model
    (measured 2e-5 to 6e-4), with 6 within 1.1 % (measured 6e-4 to 1.08e-2): the error
    falls as fixed-interface modes are added, always from above."""
    model = _beam(20)
    coarse, _ = free_modes(model, 6)
    omega, _ = free_modes(model, 20)
    w2 = sla.eigh(model.stiffness.toarray(), model.mass.toarray(), eigvals_only=True)
    full = np.sqrt(w2[6:12])
    assert np.abs(w2[:6]).max() < 1e-6 * w2[6]
    err = np.abs(omega[:6] / full - 1.0)
    assert err.max() < 1e-3
    assert np.all(np.abs(coarse[:6] / full - 1.0) < 0.011)
    assert np.all(coarse[:6] >= omega[:6])
    assert np.all(omega[:6] >= full * (1.0 - 1e-12))  # a Rayleigh-Ritz bound from above


def _lumped(model: FEModel) -> FEModel:
    """The same nodes with a diagonal mass: per node the mass of its ux row (the axial
    element's row sum) on all three translations, and a random rotary inertia."""
    rng = np.random.default_rng(5)
    diag = np.repeat(model.mass.toarray().sum(axis=1)[0::6], 6)
    rot = model.dof_map[:, 1] >= 3
    diag[rot] = rng.uniform(1e-4, 3e-4, rot.sum())
    return FEModel(
        model.node_ids,
        model.coordinates,
        model.dof_map,
        model.stiffness,
        sp.csr_matrix(sp.diags(diag)),
        model.interface,
    )


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def test_field_invariants_equal_nodal_sums():
    """Lumped mass (m_p, J_p = diag): the field form equals Table 1.1's nodal sums (1e-12)."""
    model = _lumped(_beam(8))
    comp = craig_bampton(model, modes=5, keep_nodes=range(9))
    inv, n = comp.invariants, comp.count
    diag = model.mass.diagonal()
    order = comp.node_ids - 1  # kept rows -> node indices
    m_p = diag[0::6][order]
    j_p = np.array([np.diag(diag[6 * p + 3 : 6 * p + 6]) for p in order])
    s, phi, phis = comp.positions, comp.phi, comp.phi_star
    ref = {
        "I1": m_p.sum(),
        "I2": np.einsum("p,pi->i", m_p, s),
        "I3": np.einsum("p,pin->in", m_p, phi),
        "I4": sum(m_p[p] * _skew(s[p]) @ phi[p] + j_p[p] @ phis[p] for p in range(9)),
        "I5": np.array(
            [sum(m_p[p] * _skew(phi[p][:, j]) @ phi[p] for p in range(9)) for j in range(n)]
        ),
        "I6": sum(m_p[p] * phi[p].T @ phi[p] + phis[p].T @ j_p[p] @ phis[p] for p in range(9)),
        "I7": sum(m_p[p] * _skew(s[p]).T @ _skew(s[p]) + j_p[p] for p in range(9)),
        "I8": np.array(
            [sum(m_p[p] * _skew(s[p]) @ _skew(phi[p][:, j]) for p in range(9)) for j in range(n)]
        ),
        "I9": np.array(
            [
                [
                    sum(m_p[p] * _skew(phi[p][:, j]) @ _skew(phi[p][:, k]) for p in range(9))
                    for k in range(n)
                ]
                for j in range(n)
            ]
        ),
    }
    for name, value in ref.items():
        got = getattr(inv, name)
        scale = max(np.abs(value).max(), 1e-300)
        assert np.abs(got - value).max() < 1e-12 * max(scale, 1.0), name
    assert np.abs(inv.I3).max() < 1e-12 and np.abs(inv.I4).max() < 1e-12  # mean axes
    assert np.abs(inv.I6 - np.eye(n)).max() < 1e-12


def test_not_free_free_mechanism_and_no_interface_are_errors():
    model = _beam(6)
    clamped = np.flatnonzero(model.dof_map[:, 0] != 0)  # node 0 removed: grounded
    held = FEModel(
        model.node_ids,
        model.coordinates,
        model.dof_map[clamped],
        model.stiffness[clamped][:, clamped],
        model.mass[clamped][:, clamped],
        (6,),
    )
    with pytest.raises(ReductionError, match="not free-free"):
        free_modes(held, 4)
    with pytest.raises(ReductionError, match="interface node"):
        free_modes(FEModel(*[getattr(model, f) for f in _FIELDS[:-1]], ()), 4)
    # two separate beams, one interface node each: 12 zero-energy modes
    xyz = np.vstack([model.coordinates, model.coordinates + [0.0, 0.0, 0.5]])
    elements = [(i, i + 1, SECTION, STEEL, (0.0, 1.0, 0.0)) for i in range(6)]
    elements += [(i + 7, i + 8, SECTION, STEEL, (0.0, 1.0, 0.0)) for i in range(6)]
    with pytest.raises(ReductionError, match=r"12 zero-energy modes.*mechanism"):
        free_modes(assemble_beams(xyz, elements, interface=(0, 7)), 4)


_FIELDS = ("node_ids", "coordinates", "dof_map", "stiffness", "mass", "interface")


def test_selection_and_damping():
    model = _beam(12)
    all_modes = craig_bampton(model, fixed_interface_modes=10)
    f = all_modes.frequencies / (2 * np.pi)
    band = craig_bampton(model, frequency_range=(f[2] - 1.0, f[5] + 1.0), fixed_interface_modes=10)
    assert band.frequencies == pytest.approx(all_modes.frequencies[2:6])
    assert all_modes.damping == pytest.approx(default_damping(f))
    assert set(default_damping(np.array([50.0, 500.0, 5000.0]))) == {0.01, 0.1, 1.0}
    two = craig_bampton(model, modes=3, damping={2: 0.05})
    assert two.damping[1] == 0.05 and two.damping[0] == default_damping(f[:1])[0]
    assert craig_bampton(model, modes=2, damping=0.02).damping == pytest.approx([0.02, 0.02])
    with pytest.raises(ReductionError, match="no mode between"):
        craig_bampton(model, frequency_range=(1e7, 2e7))


def test_reduction_is_the_same_whatever_arpack_did_before():
    """A beam of 120 elements (714 internal DOF: the fixed-interface modes come from ARPACK,
    whose own start vector is random and depends on the calls made before): reduced, then
    reduced again after an unrelated ARPACK call, the modes are the same to the last bit,
    each with its largest entry positive. (Before, the same model gave other mode shapes
    from run to run, and a flexible solar array's dynamic loads moved with them.)"""
    import scipy.sparse.linalg as spla

    model = _beam(120)
    first = craig_bampton(model, modes=8, fixed_interface_modes=12)
    spla.eigsh(sp.diags(np.arange(1.0, 201.0)), k=3, sigma=0.0)  # moves ARPACK's generator
    again = craig_bampton(model, modes=8, fixed_interface_modes=12)
    np.testing.assert_array_equal(first.frequencies, again.frequencies)
    np.testing.assert_array_equal(first.phi, again.phi)
    np.testing.assert_array_equal(first.phi_star, again.phi_star)
    _, psi = free_modes(model, 12)
    peak = psi[np.argmax(np.abs(psi), axis=0), np.arange(psi.shape[1])]
    assert np.all(peak > 0.0)


def test_equal_frequencies_have_one_basis():
    """A straight beam of square section bends alike about y and z: eigh returns any
    rotation of each such pair. `canonical` makes the basis unique: a rotated pair gives the
    same modes (1e-9), and here each is a pure bending mode (no z translation in the
    in-plane one: 1e-9 of its largest entry), so modal coordinates given in a case mean the
    same shape wherever they run."""
    xyz = np.outer(np.linspace(0.0, 0.3, 9), [1.0, 0.0, 0.0])
    square = Section.rectangle(0.008, 0.008)
    elements = [(i, i + 1, square, STEEL, (0.0, 1.0, 0.0)) for i in range(8)]
    model = assemble_beams(xyz, elements, interface=(0, 8))
    omega, psi = free_modes(model, 4)
    assert omega[1] - omega[0] < 1e-8 * omega[1]  # the pair, equal to round-off
    m = model.mass
    angle = 0.7
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    turned = psi.copy()
    turned[:, :2] = psi[:, :2] @ turn
    again = canonical(omega**2, turned, m)
    assert np.abs(np.abs(again[:, :2]) - np.abs(psi[:, :2])).max() < 1e-9 * np.abs(psi).max()
    y, z = model.dof_map[:, 1] == 1, model.dof_map[:, 1] == 2
    for mode in psi[:, :2].T:
        small = min(np.abs(mode[y]).max(), np.abs(mode[z]).max())
        assert small < 1e-9 * np.abs(mode).max()


def test_a_mode_s_sign_is_the_same_whatever_round_off_ties_its_largest_entries() -> None:
    """A symmetric structure's mode has entries equal but for round-off (CI 2026-11-30: an
    AVX-512 machine's LAPACK flipped two of the Test Set crank rod's modes): the first of
    the entries within 1e-6 of the largest sets the sign, whichever of them round-off made
    larger, and of either sign the mode comes out the same."""
    from mechlib.flexible.craig_bampton import signed

    for wobble in (1e-15, -1e-15, 0.0):
        mode = np.array([[0.1], [-0.7071067811865476 * (1.0 + wobble)], [0.7071067811865476]])
        for given in (mode, -mode):
            assert np.array_equal(signed(given), -mode)  # the first tied entry made positive
    clear = np.array([[0.2], [-0.9], [0.8]])  # a largest entry of its own: it sets the sign
    assert np.array_equal(signed(clear), -clear)


def test_equal_frequencies_basis_chosen_the_same_whatever_round_off_ties() -> None:
    """The entries `_pivots` chooses for a group of equal frequencies (QR with column
    pivoting, ties within 1e-6 to the first entry): a pair whose candidate entries tie but
    for round-off gives the same entries whichever round-off made larger."""
    from mechlib.flexible.craig_bampton import _pivots

    rng = np.random.default_rng(3)
    base = rng.standard_normal((8, 2))
    base[2] = base[5] = [3.0, 1.0]  # the largest entries, of equal norm: a symmetric pair
    chosen = set()
    for wobble in (1e-15, -1e-15):
        group = base.copy()
        group[5] *= 1.0 + wobble
        rotation = np.array([[0.6, -0.8], [0.8, 0.6]])  # any basis of the group
        chosen.add(tuple(_pivots(group @ rotation)))
    assert len(chosen) == 1
