"""The first paper's kernels against references built in numpy from their definitions in docs/:
G of (24) by hand, A and b of (13)-(14) by hand, the constraint wrench (18) by its pseudo-inverse
formula, the internal wrenches (53) by Gauss's principle on the rigid motions, the weighted grasp
inverse by its block formula (25) with errata E2, the apparent impedance by the sums (31)-(32)."""

import numpy as np
import pytest

import coopdyn
from conftest import block_diag, constraint_by_hand, grasp_block, grasp_by_hand, random_spd, skew


def layouts(a):
    """The same values in several memory layouts: C order, Fortran order, a transposed view, a
    strided slice of a larger array, integer-valued floats as a list."""
    big = np.zeros((a.shape[0] * 2, a.shape[1] * 3))
    big[::2, ::3] = a
    return [np.ascontiguousarray(a), np.asfortranarray(a), np.ascontiguousarray(a.T).T, big[::2, ::3], a.tolist()]


def test_grasp_matrix_by_hand_in_every_layout(rng):
    for n in (1, 2, 3, 5):
        r = rng.standard_normal((3, n))
        reference = grasp_by_hand(r)
        for variant in layouts(r):
            G = coopdyn.grasp_matrix(variant)
            assert G.shape == (6, 6 * n)
            np.testing.assert_array_equal(G, reference)
            assert G.flags.writeable and G.flags.owndata


def test_integer_arrays_are_converted():
    r = np.array([[1, 0], [0, 1], [0, 0]])
    np.testing.assert_array_equal(coopdyn.grasp_matrix(r), grasp_by_hand(r.astype(float)))


def test_wrong_shapes_name_the_argument_and_the_shape(rng):
    for bad in (np.zeros(3), np.zeros((2, 2)), np.zeros((3, 2, 1)), "abc"):
        with pytest.raises(coopdyn.InvalidArgument) as error:
            coopdyn.grasp_matrix(bad)
        assert isinstance(error.value, ValueError)
        assert error.value.parameter == "r"
        assert error.value.component == "grasp_matrix"
        assert error.value.arm is None
        assert "(3, N)" in str(error.value)
    r = rng.standard_normal((3, 2))
    with pytest.raises(ValueError) as error:
        coopdyn.interaction_wrenches(np.eye(6), np.eye(6), r, np.zeros(3), np.zeros(18))
    assert error.value.parameter == "ee_inertias" and "(6, 12)" in str(error.value)
    with pytest.raises(ValueError) as error:
        coopdyn.interaction_wrenches(np.eye(6), np.hstack([np.eye(6)] * 2), r, np.zeros(3), np.zeros(12))
    assert error.value.parameter == "h_sigma" and "(18,)" in str(error.value)


def test_constraint_matrix_and_bias_by_hand(rng):
    r = rng.standard_normal((3, 3))
    omega = rng.standard_normal(3)
    A, b = constraint_by_hand(r, omega)
    np.testing.assert_array_equal(coopdyn.constraint_matrix(r), A)
    np.testing.assert_allclose(coopdyn.constraint_bias(r, omega), b, rtol=1e-14, atol=1e-14)


def uk_reference(M, A, b, h_sigma):
    """(18): h = M^(1/2) (A M^(-1/2))^+ (b - A M^-1 h_sigma), with the Cholesky factor as M^(1/2)."""
    L = np.linalg.cholesky(M)
    return L @ np.linalg.pinv(A @ np.linalg.inv(L).T) @ (b - A @ np.linalg.solve(M, h_sigma))


def test_udwadia_kalaba_against_the_pseudo_inverse_formula(rng):
    for n, m in ((4, 2), (6, 3), (12, 6)):
        M = random_spd(rng, n)
        A = rng.standard_normal((m, n))
        A[-1] = A[0] + A[1]  # a redundant row
        x = rng.standard_normal(n)
        b = A @ x  # consistent
        h_sigma = rng.standard_normal(n)
        h = coopdyn.udwadia_kalaba(M, A, b, h_sigma)
        np.testing.assert_allclose(h, uk_reference(M, A, b, h_sigma), rtol=1e-9, atol=1e-9)
        # The constrained acceleration satisfies the constraint (Gauss's principle (19)).
        np.testing.assert_allclose(A @ np.linalg.solve(M, h_sigma + h), b, atol=1e-9)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.udwadia_kalaba(-np.eye(2), np.ones((1, 2)), [0.0], [0.0, 0.0])
    assert error.value.parameter == "M"


def test_interaction_wrenches_against_udwadia_kalaba_in_numpy(rng):
    for n in (1, 2, 4):
        r = rng.standard_normal((3, n))
        omega = rng.standard_normal(3)
        object_inertia = random_spd(rng, 6)
        ee = [random_spd(rng, 6, 2.0) for _ in range(n)]
        h_sigma = rng.standard_normal(6 * (n + 1))
        A, b = constraint_by_hand(r, omega)
        M = block_diag(object_inertia, *ee)
        reference = uk_reference(M, A, b, h_sigma)
        h = coopdyn.interaction_wrenches(object_inertia, np.hstack(ee), r, omega, h_sigma)
        np.testing.assert_allclose(h, reference, rtol=1e-9, atol=1e-9 * np.abs(reference).max())
        # Newton's third law: the object's wrench is G times the arms' reactions, h_o = -G [h_1; ...] ((22)-(23)).
        np.testing.assert_allclose(h[:6], -grasp_by_hand(r) @ h[6:], rtol=1e-9, atol=1e-9 * np.abs(h).max())


def test_internal_wrenches_by_gauss_principle_on_rigid_motions(rng):
    for n in (2, 3):
        r = rng.standard_normal((3, n))
        omega = rng.standard_normal(3)
        ee = [random_spd(rng, 6) for _ in range(n)]
        h_motion = rng.standard_normal(6 * n)
        Mp = block_diag(*ee)
        G = grasp_by_hand(r)
        centripetal = np.concatenate([np.r_[np.cross(omega, np.cross(omega, r[:, i])), 0, 0, 0] for i in range(n)])
        # Rigid accelerations xdd' = G^T y + centripetal; Gauss: y minimises |xdd' - M'^-1 h'^x|_M'.
        y = np.linalg.solve(G @ Mp @ G.T, G @ (h_motion - Mp @ centripetal))
        reference = Mp @ (G.T @ y + centripetal) - h_motion
        h_int = coopdyn.internal_wrenches(np.hstack(ee), r, omega, h_motion)
        np.testing.assert_allclose(h_int, reference, rtol=1e-9, atol=1e-9 * np.abs(reference).max())
        # Internal: they move no object, G h'_int = 0 (Definition 1).
        np.testing.assert_allclose(G @ h_int, 0, atol=1e-9 * np.abs(h_int).max())


def test_weighted_grasp_inverse_block_formula(rng):
    n = 3
    m = rng.uniform(0.5, 2.0, n)
    p = rng.standard_normal((3, n))
    r = p - (p @ m / m.sum())[:, None]  # sum m_i r_i = 0: (25) as printed applies
    J = [random_spd(rng, 3) for _ in range(n)]
    m_o = m.sum()
    J_o = sum(J) + sum(m[i] * skew(r[:, i]) @ skew(r[:, i]).T for i in range(n))
    J_o_inv = np.linalg.inv(J_o)
    reference = np.zeros((6 * n, 6))
    for i in range(n):
        reference[6 * i:6 * i + 3, :3] = m[i] / m_o * np.eye(3)
        reference[6 * i:6 * i + 3, 3:] = m[i] * skew(r[:, i]).T @ J_o_inv  # errata E2's order
        reference[6 * i + 3:6 * i + 6, 3:] = J[i] @ J_o_inv
    G_plus = coopdyn.weighted_grasp_inverse(r, m, np.hstack(J))
    np.testing.assert_allclose(G_plus, reference, rtol=1e-10, atol=1e-12)
    # Any grasp (centroid elsewhere): G G+_M = I.
    r2 = rng.standard_normal((3, n)) + 1.0
    np.testing.assert_allclose(grasp_by_hand(r2) @ coopdyn.weighted_grasp_inverse(r2, m, np.hstack(J)), np.eye(6),
                               atol=1e-12)
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.weighted_grasp_inverse(r, [1.0, -1.0, 1.0], np.hstack(J))
    assert error.value.arm == 1
    assert "mass" in error.value.parameter


def test_apparent_impedance_sums(rng):
    n = 2
    r = rng.standard_normal((3, n))
    Mo = random_spd(rng, 6)
    Mi = [random_spd(rng, 6) for _ in range(n)]
    Di = [np.diag(np.r_[[d] * 3, [e] * 3]) for d, e in rng.uniform(1, 5, (n, 2))]
    Ki = [np.diag(np.r_[[k] * 3, [c] * 3]) for k, c in rng.uniform(1, 5, (n, 2))]
    result = coopdyn.apparent_impedance(Mo, np.hstack(Mi), np.hstack(Di), np.hstack(Ki), r)
    Gi = [grasp_block(r[:, i]) for i in range(n)]
    np.testing.assert_allclose(result.inertia, Mo + sum(G @ M @ G.T for G, M in zip(Gi, Mi)), rtol=1e-12)
    np.testing.assert_allclose(result.damping, sum(G @ D @ G.T for G, D in zip(Gi, Di)), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result.stiffness, sum(G @ K @ G.T for G, K in zip(Gi, Ki)), rtol=1e-12, atol=1e-12)
    with pytest.raises(ValueError):
        result.inertia[0, 0] = 1.0  # a read-only copy


def block_formula_inverse(r, m, J):
    """G+_M of (25) with errata E2 by its blocks (docs/coordination.md), for sum m_i r_i = 0."""
    n = r.shape[1]
    J_o = sum(J) + sum(m[i] * skew(r[:, i]) @ skew(r[:, i]).T for i in range(n))
    J_o_inv = np.linalg.inv(J_o)
    out = np.zeros((6 * n, 6))
    for i in range(n):
        out[6 * i:6 * i + 3, :3] = m[i] / m.sum() * np.eye(3)
        out[6 * i:6 * i + 3, 3:] = m[i] * skew(r[:, i]).T @ J_o_inv
        out[6 * i + 3:6 * i + 6, 3:] = J[i] @ J_o_inv
    return out


def test_load_distribution_and_squeeze_by_the_block_formula(rng):
    n = 3
    m = rng.uniform(0.5, 2.0, n)
    p = rng.standard_normal((3, n))
    r = p - (p @ m / m.sum())[:, None]
    J = [random_spd(rng, 3) for _ in range(n)]
    G_plus = block_formula_inverse(r, m, J)
    h_o = rng.standard_normal(6)
    # (26): h_i^d = -(G+_M h_o^d)_i.
    np.testing.assert_allclose(coopdyn.load_distribution(r, m, np.hstack(J), h_o), -G_plus @ h_o, rtol=1e-10,
                               atol=1e-12)
    hbar = rng.standard_normal(6 * n)
    squeeze = coopdyn.squeeze_wrenches(r, m, np.hstack(J), hbar)
    np.testing.assert_allclose(squeeze, hbar - G_plus @ grasp_by_hand(r) @ hbar, rtol=1e-10, atol=1e-12)
    # The squeeze moves nothing: G hbar_sq = 0; a non-squeezing distribution has none.
    np.testing.assert_allclose(grasp_by_hand(r) @ squeeze, 0, atol=1e-12)
    np.testing.assert_allclose(coopdyn.squeeze_wrenches(r, m, np.hstack(J), G_plus @ h_o), 0, atol=1e-12)
    with pytest.raises(ValueError) as error:
        coopdyn.load_distribution(r, m, np.hstack(J), np.zeros(5))
    assert error.value.parameter == "object_wrench"


def test_stability_of_the_apparent_impedance(rng):
    """(52), Theorems 3-4, Corollary 1 (docs/analysis.md): the state matrix by hand, its eigenvalues
    by numpy, the modes by a Cholesky-reduced symmetric eigenproblem in numpy, the commutator by
    hand, and the centre of stiffness sum k_i r_i / sum k_i of the cooperative K."""
    n = 3
    r = rng.standard_normal((3, n))
    k = rng.uniform(100, 300, n)
    kappa = rng.uniform(10, 30, n)
    Mi = [random_spd(rng, 6) for _ in range(n)]
    Di = [np.diag(np.r_[[d] * 3, [e] * 3]) for d, e in rng.uniform(5, 20, (n, 2))]
    Ki = [np.diag(np.r_[[k[i]] * 3, [kappa[i]] * 3]) for i in range(n)]
    impedance = coopdyn.apparent_impedance(random_spd(rng, 6), np.hstack(Mi), np.hstack(Di), np.hstack(Ki), r)
    M, D, K = impedance.inertia, impedance.damping, impedance.stiffness
    A = np.block([[np.zeros((6, 6)), np.eye(6)], [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    np.testing.assert_allclose(coopdyn.state_matrix(impedance), A, rtol=1e-10, atol=1e-10)
    eigenvalues = coopdyn.linearised_eigenvalues(impedance)
    assert eigenvalues.dtype == np.complex128 and eigenvalues.shape == (12,)
    reference = np.linalg.eigvals(A)
    np.testing.assert_allclose(np.sort_complex(eigenvalues), np.sort_complex(reference), rtol=1e-8, atol=1e-8)
    assert np.all(eigenvalues.real < 0)  # Theorem 3
    L = np.linalg.cholesky(M)
    Linv = np.linalg.inv(L)
    omega2, W = np.linalg.eigh(Linv @ K @ Linv.T)
    modes = coopdyn.modes(impedance)
    np.testing.assert_allclose(modes.natural_frequencies, np.sqrt(omega2), rtol=1e-9)
    V = Linv.T @ W  # M-normalised
    zeta = np.array([V[:, j] @ D @ V[:, j] / (2 * np.sqrt(omega2[j])) for j in range(6)])
    np.testing.assert_allclose(modes.damping_ratios, zeta, rtol=1e-8)
    np.testing.assert_allclose(modes.shapes.T @ M @ modes.shapes, np.eye(6), atol=1e-9)
    commutator = D @ np.linalg.solve(M, K) - K @ np.linalg.solve(M, D)
    assert coopdyn.classical_damping_commutator(impedance) == pytest.approx(np.linalg.norm(commutator), rel=1e-9)
    np.testing.assert_allclose(coopdyn.centre_of_stiffness(K), r @ k / k.sum(), rtol=1e-10, atol=1e-12)
    assert not coopdyn.is_decoupled(impedance)
    # Corollary 1: a symmetric two-arm grasp about the centre with block-diagonal inertias decouples.
    sym = np.array([[0.0, 0.0], [-0.4, 0.4], [0.0, 0.0]])
    block = np.diag([10.0, 10, 10, 0.5, 0.5, 0.5])
    Kb = np.diag([300.0] * 3 + [50.0] * 3)
    decoupled = coopdyn.apparent_impedance(np.diag([1.75] * 3 + [0.055, 0.01, 0.055]), np.hstack([block] * 2),
                                           np.hstack([np.diag([180.0] * 3 + [10.0] * 3)] * 2), np.hstack([Kb] * 2), sym)
    assert coopdyn.is_decoupled(decoupled)
    made = coopdyn.ApparentImpedance(M, D, K)
    np.testing.assert_array_equal(made.inertia, M)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.ApparentImpedance(np.zeros((6, 6)), D, K)
    assert error.value.parameter == "inertia"


def test_impedance_synthesis(rng):
    """synthesize_gains recovers gains that produce a reachable target (the K of known gains, (E3)
    in numpy as sum G_i diag(k_i I, kappa_i I) G_i^T); classical_damping gives every mode the
    requested ratio (numpy's generalized eigenproblem) and commutes (Theorem 4)."""
    n = 3
    r = rng.standard_normal((3, n))
    k = rng.uniform(100, 300, n)
    kappa = rng.uniform(10, 30, n)
    target = sum(grasp_block(r[:, i]) @ np.diag(np.r_[[k[i]] * 3, [kappa[i]] * 3]) @ grasp_block(r[:, i]).T
                 for i in range(n))
    result = coopdyn.synthesize_gains(r, target)
    assert result.achievable and result.relative_residual < 1e-9
    np.testing.assert_allclose(result.achieved, target, rtol=1e-9, atol=1e-9 * np.abs(target).max())
    assert np.all(result.translational >= 0) and np.all(result.rotational >= 0)
    assert result.total_rotational == pytest.approx(kappa.sum(), rel=1e-9)
    unreachable = np.eye(6)
    unreachable[0, 3] = unreachable[3, 0] = 0.9
    assert not coopdyn.synthesize_gains(r, unreachable).achievable

    M = random_spd(rng, 6)
    impedance = coopdyn.ApparentImpedance(M, np.zeros((6, 6)), target)
    D = coopdyn.classical_damping(impedance, 0.7)
    L = np.linalg.cholesky(M)
    Linv = np.linalg.inv(L)
    omega2, W = np.linalg.eigh(Linv @ target @ Linv.T)
    V = Linv.T @ W
    zeta = np.array([V[:, j] @ D @ V[:, j] / (2 * np.sqrt(omega2[j])) for j in range(6)])
    np.testing.assert_allclose(zeta, 0.7, rtol=1e-8)
    commutator = D @ np.linalg.solve(M, target) - target @ np.linalg.solve(M, D)
    assert np.linalg.norm(commutator) < 1e-9 * np.linalg.norm(D) * np.linalg.norm(target) / np.linalg.norm(M)
