/// \file
/// \brief Stability and modes of the linearised object dynamics (52) M dxdd + D dxd + K dx = h
/// (Theorems 3-4, Corollary 1; docs/analysis.md, errata E4).
///
/// M, D, K symmetric positive definite make (52) asymptotically stable. The paper's Theorem 4
/// also claims classical damping, D M^-1 K = K M^-1 D; that holds for symmetric set-ups only
/// (E4), so modes and damping ratios come from the generalized eigenproblem, and the commutator is
/// reported rather than assumed zero.
#pragma once

#include "coopdyn/analysis/apparent_impedance.hpp"
#include "coopdyn/config.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace coopdyn {

/// \brief First-order state matrix of (52) for x = [dx; dxd]: [[0, I6], [-M^-1 K, -M^-1 D]].
template <typename Scalar>
Eigen::Matrix<Scalar, 12, 12> state_matrix(const ApparentImpedance<Scalar>& impedance)
{
    const Eigen::LLT<Matrix6<Scalar>> inertia(impedance.inertia);
    Eigen::Matrix<Scalar, 12, 12> result = Eigen::Matrix<Scalar, 12, 12>::Zero();
    result.template topRightCorner<6, 6>().setIdentity();
    result.template bottomLeftCorner<6, 6>() = -inertia.solve(impedance.stiffness);
    result.template bottomRightCorner<6, 6>() = -inertia.solve(impedance.damping);
    return result;
}

/// \brief The 12 eigenvalues of the linearised system (52); all have negative real part when
/// M, D, K are positive definite (Theorem 3).
template <typename Scalar>
Eigen::Matrix<std::complex<Scalar>, 12, 1> linearised_eigenvalues(const ApparentImpedance<Scalar>& impedance)
{
    const Eigen::EigenSolver<Eigen::Matrix<Scalar, 12, 12>> solver(state_matrix(impedance), false);
    return solver.eigenvalues();
}

/// \brief Undamped modes of (52) from K v = omega^2 M v, with the modal damping ratios
/// zeta_k = v_k^T D v_k / (2 omega_k) (v_k M-normalised). These are the exact damping ratios
/// when D is classical (classical_damping_commutator = 0); otherwise use linearised_eigenvalues.
/// Requires M and K symmetric positive definite (a zero or negative omega^2 gives NaN).
template <typename Scalar> struct Modes {
    Vector6<Scalar> natural_frequencies;  ///< omega_k, rad/s, ascending
    Vector6<Scalar> damping_ratios;       ///< zeta_k
    Matrix6<Scalar> shapes;               ///< column k: v_k, with v_k^T M v_k = 1
};

template <typename Scalar> Modes<Scalar> modes(const ApparentImpedance<Scalar>& impedance)
{
    using std::sqrt;
    const Eigen::GeneralizedSelfAdjointEigenSolver<Matrix6<Scalar>> solver(impedance.stiffness, impedance.inertia);
    Modes<Scalar> result;
    result.shapes = solver.eigenvectors();
    for (int k = 0; k < 6; ++k) {
        const Scalar frequency = sqrt(solver.eigenvalues()(k));
        const Vector6<Scalar> shape = result.shapes.col(k);
        result.natural_frequencies(k) = frequency;
        result.damping_ratios(k) = shape.dot(impedance.damping * shape) / (Scalar(2) * frequency);
    }
    return result;
}

/// \brief Frobenius norm of D M^-1 K - K M^-1 D: zero exactly when the damping is classical
/// (the paper's Theorem 4 claim; errata E4: nonzero for asymmetric set-ups).
template <typename Scalar> Scalar classical_damping_commutator(const ApparentImpedance<Scalar>& impedance)
{
    const Eigen::LLT<Matrix6<Scalar>> inertia(impedance.inertia);
    const Matrix6<Scalar> commutator = impedance.damping * inertia.solve(impedance.stiffness) -
                                       impedance.stiffness * inertia.solve(impedance.damping);
    return commutator.norm();
}

/// \brief Corollary 1: translation and rotation are decoupled when the off-diagonal 3x3 blocks
/// of M, D and K vanish (each relative to its matrix's largest entry, within `tolerance`).
template <typename Scalar>
bool is_decoupled(const ApparentImpedance<Scalar>& impedance, const Scalar& tolerance = Scalar(1e-12))
{
    const auto coupling_vanishes = [&tolerance](const Matrix6<Scalar>& matrix) {
        const Scalar scale = matrix.cwiseAbs().maxCoeff();
        return matrix.template topRightCorner<3, 3>().cwiseAbs().maxCoeff() <= tolerance * scale &&
               matrix.template bottomLeftCorner<3, 3>().cwiseAbs().maxCoeff() <= tolerance * scale;
    };
    return coupling_vanishes(impedance.inertia) && coupling_vanishes(impedance.damping) &&
           coupling_vanishes(impedance.stiffness);
}

/// \brief Centre of stiffness of K, relative to the object's centre of mass (in {w}): the point
/// about which a force produces no rotation when the translational stiffness is isotropic. With
/// K = [[K_tt, K_tr], [K_rt, K_rr]] it is vee of the skew-symmetric part of K_rt K_tt^-1; for the
/// cooperative K (E3) that is sum k_i r_i / sum k_i, exactly: a force through that point is
/// resisted by a pure translation, K^-1 [f; c x f] = [f / sum k_i; 0]. Requires an invertible
/// translational block K_tt (sum k_i > 0).
template <typename Scalar> Vector3<Scalar> centre_of_stiffness(const Matrix6<Scalar>& stiffness)
{
    const Matrix3<Scalar> coupling =
        stiffness.template bottomLeftCorner<3, 3>() * stiffness.template topLeftCorner<3, 3>().inverse();
    const Matrix3<Scalar> skew_part = Scalar(0.5) * (coupling - coupling.transpose());
    return Vector3<Scalar>(skew_part(2, 1), skew_part(0, 2), skew_part(1, 0));
}

}  // namespace coopdyn
