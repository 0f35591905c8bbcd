/// \file
/// \brief Impedance synthesis: per-arm stiffness and damping gains that give the object a desired
/// apparent stiffness K and damping D (Theorem 2 read backwards, docs/analysis.md with errata
/// E3). Not in the reference papers. A design-time tool: double precision, allocates freely,
/// throws on invalid input; nothing here is meant for the per-tick path.
///
/// K and D are linear in the gains. From K = sum_i G_i diag(k_i I3, kappa_i I3) G_i^T (E3):
///
///     K = sum_i k_i T(r_i) + (sum_i kappa_i) R,    T(r) = G_i diag(I3, 0) G_i^T = [[I3, S(r)^T], [S(r), S(r) S(r)^T]],
///                                                  R    = G_i diag(0, I3) G_i^T = diag(0, I3),
///
/// and D = sum_i G_i D_i G_i^T (32) is the same expression in d_i, delta_i. So the reachable object
/// matrices form a convex cone spanned by T(r_1), ..., T(r_N) and R, and only the sum of the
/// rotational gains is determined (every kappa_i adds kappa_i I3 at the object, wherever it grasps).
///
/// The gains are the non-negative least-squares fit (Lawson-Hanson) of the symmetric part of the
/// target in the Frobenius norm. The target is reported achievable when the relative residual
/// ||K(gains) - K_target||_F / ||K_target||_F (against the target as given, so an asymmetric
/// target counts its skew part) is at most the tolerance; otherwise the closest gains are still
/// returned, with achievable = false and the residual, never as a silent approximation. The sum
/// of the rotational gains is split equally among the arms (the least-norm split).
///
/// Entry points:
/// - `synthesize_gains(r, target)`: the kernel, from the grasp offsets r (3 x N, {w}).
/// - `synthesize_stiffness(model, data, K)`, `synthesize_damping(model, data, D)`: at the grasp
///   configuration in a Data (after grasp_kinematics or interaction_dynamics).
/// - `with_stiffness(model, result)`, `with_damping(model, result)`: a copy of the Model with the
///   synthesized gains (refuses an unachievable result); `arms_with_stiffness` /
///   `arms_with_damping` return the arms for deliberate use of closest-fit gains.
/// - `classical_damping(M, K, zeta)`: the D that gives damping ratio zeta to every mode of (M, K).
#pragma once

#include "coopdyn/analysis/apparent_impedance.hpp"
#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/numerics/non_negative_least_squares.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace coopdyn {

/// \brief Result of an impedance synthesis (stiffness or damping gains), double precision.
template <typename Scalar> struct SynthesisResult {
    /// relative_residual <= tolerance: the gains reproduce the target.
    bool achievable = false;
    /// Translational gains per arm, N (k_i or d_i), all >= 0.
    Eigen::Matrix<Scalar, Eigen::Dynamic, 1> translational;
    /// Rotational gains per arm, N (kappa_i or delta_i), all >= 0: total_rotational split equally.
    Eigen::Matrix<Scalar, Eigen::Dynamic, 1> rotational;
    /// sum_i kappa_i (or sum_i delta_i), the only rotational quantity the object matrix determines.
    Scalar total_rotational = Scalar(0);
    /// The object matrix the gains produce, sum_i k_i T(r_i) + total_rotational R.
    Matrix6<Scalar> achieved = Matrix6<Scalar>::Zero();
    /// ||achieved - target||_F / ||target||_F (absolute when the target is zero).
    Scalar relative_residual = Scalar(0);
    /// The tolerance achievable was decided with.
    Scalar tolerance = Scalar(0);
};

namespace detail {

/// The 21 independent entries of a symmetric 6x6 matrix (lower triangle, off-diagonal entries
/// weighted by sqrt(2) so that the Euclidean norm equals the Frobenius norm).
COOPDYN_LAZY Eigen::Matrix<double, 21, 1> symmetric_entries(const Matrix6<double>& matrix)
{
    Eigen::Matrix<double, 21, 1> result;
    int index = 0;
    for (int column = 0; column < 6; ++column) {
        for (int row = column; row < 6; ++row) {
            result(index++) = row == column ? matrix(row, column) : std::sqrt(2.0) * matrix(row, column);
        }
    }
    return result;
}

/// T(r) = G_i diag(I3, 0) G_i^T = [[I3, S(r)^T], [S(r), S(r) S(r)^T]]: the object matrix of a
/// unit translational gain at grasp offset r (errata E3, docs/analysis.md).
COOPDYN_LAZY Matrix6<double> unit_translational_contribution(const Vector3<double>& r_i)
{
    return CentralInertia<double>(1.0, Symmetric3<double>::Zero()).shifted(r_i).matrix();
}

/// R = G_i diag(0, I3) G_i^T = diag(0, I3): the object matrix of a unit rotational gain (a
/// massless inertia is unchanged by the shift, whatever r_i).
COOPDYN_LAZY Matrix6<double> unit_rotational_contribution()
{
    return CentralInertia<double>(0.0, Symmetric3<double>::Identity()).matrix();
}

template <typename ModelType> void require_impedance_model()
{
    static_assert(is_impedance_end_effector_v<typename ModelType::EndEffectorModel>,
                  "impedance synthesis needs impedance end-effectors (scalar damping and stiffness gains)");
}

/// Gains for every arm of the model, each non-negative and finite (InvalidArgument naming the arm).
template <typename ModelType>
void require_gains_for(const ModelType& model, const SynthesisResult<double>& gains)
{
    if (gains.translational.size() != model.arms() || gains.rotational.size() != model.arms()) {
        fail("impedance synthesis", "gains",
             "were synthesized for " + std::to_string(gains.translational.size()) + " arms, the model has " +
                 std::to_string(model.arms()));
    }
    for (Index i = 0; i < model.arms(); ++i) {
        require_non_negative(gains.translational(i), argument_context("impedance synthesis", i), "gains.translational");
        require_non_negative(gains.rotational(i), argument_context("impedance synthesis", i), "gains.rotational");
    }
}

template <typename ModelType, typename Gain>
std::vector<typename ModelType::ArmType> arms_with_gains(const ModelType& model, const SynthesisResult<double>& gains,
                                                         Gain ModelType::EndEffectorModel::*translational,
                                                         Gain ModelType::EndEffectorModel::*rotational)
{
    using Scalar = typename ModelType::Scalar;
    require_gains_for(model, gains);
    std::vector<typename ModelType::ArmType> arms;
    arms.reserve(static_cast<std::size_t>(model.arms()));
    for (Index i = 0; i < model.arms(); ++i) {
        typename ModelType::ArmType arm{model.end_effector(i), {model.grasp_offsets_body().col(i),
                                                                Quaternion<Scalar>(model.grasp_orientation_body(i))}};
        arm.end_effector.*translational = Scalar(gains.translational(i));
        arm.end_effector.*rotational = Scalar(gains.rotational(i));
        arms.push_back(arm);
    }
    return arms;
}

/// `matrix`: "stiffness" or "damping", the object matrix the gains were synthesized for.
COOPDYN_LAZY void require_achievable(const SynthesisResult<double>& gains, const std::string& matrix)
{
    if (!gains.achievable) {
        std::ostringstream problem;
        problem << "do not reproduce the requested object " << matrix << " (relative residual "
                << gains.relative_residual << " > tolerance " << gains.tolerance << "); use arms_with_" << matrix
                << " to apply the closest gains deliberately";
        fail("impedance synthesis", "gains", problem.str());
    }
}

}  // namespace detail

/// \brief Non-negative per-arm gains whose apparent object matrix (docs/analysis.md, E3) is
/// closest to `target`: the kernel of synthesize_stiffness / synthesize_damping.
/// \param r 3 x N grasp offsets r_i in {w} (from the object's centre of mass).
/// \param target 6x6 desired object stiffness K (or damping D), in {w} about the centre of mass.
/// \param tolerance relative Frobenius residual up to which the target counts as achievable.
/// \return gains, achieved matrix, residual and the verdict; see the file comment.
/// \throws InvalidArgument when r is not 3 x N (N >= 1) or not finite, the target is not 6x6 or
///         not finite, or the tolerance is not positive.
template <typename DerivedR, typename DerivedTarget>
SynthesisResult<double> synthesize_gains(const Eigen::MatrixBase<DerivedR>& r,
                                         const Eigen::MatrixBase<DerivedTarget>& target, double tolerance = 1e-9)
{
    const std::string context = "impedance synthesis";
    if (r.rows() != 3 || r.cols() < 1) {
        detail::fail(context, "r", "must be 3 x N with N >= 1");
    }
    if (target.rows() != 6 || target.cols() != 6) {
        detail::fail(context, "target", "must be 6x6");
    }
    detail::require_finite(r, context, "r");
    detail::require_finite(target, context, "target");
    detail::require_positive(tolerance, context, "tolerance");

    const Eigen::Matrix<double, 3, Eigen::Dynamic> offsets = detail::values_of(r);
    const Matrix6<double> requested = detail::values_of(target);
    const Index arms = offsets.cols();

    // Columns: T(r_1), ..., T(r_N), R (one column for the sum of the rotational gains).
    Eigen::MatrixXd basis(21, arms + 1);
    for (Index i = 0; i < arms; ++i) {
        basis.col(i) = detail::symmetric_entries(detail::unit_translational_contribution(offsets.col(i)));
    }
    basis.col(arms) = detail::symmetric_entries(detail::unit_rotational_contribution());
    // Fit the symmetric part: it is the Frobenius-closest symmetric matrix, and every reachable
    // matrix is symmetric.
    const Matrix6<double> symmetric_part = 0.5 * (requested + requested.transpose());
    const Eigen::VectorXd gains = numerics::non_negative_least_squares(basis, detail::symmetric_entries(symmetric_part));

    SynthesisResult<double> result;
    result.tolerance = tolerance;
    result.translational = gains.head(arms);
    result.total_rotational = gains(arms);
    result.rotational = Eigen::VectorXd::Constant(arms, result.total_rotational / static_cast<double>(arms));
    result.achieved = result.total_rotational * detail::unit_rotational_contribution();
    for (Index i = 0; i < arms; ++i) {
        result.achieved += result.translational(i) * detail::unit_translational_contribution(offsets.col(i));
    }
    const double scale = requested.norm();
    result.relative_residual = (result.achieved - requested).norm() / (scale > 0.0 ? scale : 1.0);
    result.achievable = result.relative_residual <= tolerance;
    return result;
}

namespace detail {
/// synthesize_gains at the grasp offsets of `data`: stiffness and damping are the same fit (the
/// file comment), so both entry points are this one.
template <typename ModelType, typename DerivedTarget>
SynthesisResult<double> synthesize_at(const ModelType& model, const Data<ModelType>& data,
                                      const Eigen::MatrixBase<DerivedTarget>& target, double tolerance)
{
    require_impedance_model<ModelType>();
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    (void)model;
    return synthesize_gains(data.grasp_offsets, target, tolerance);
}
}  // namespace detail

/// \brief Per-arm stiffness gains k_i, kappa_i (all >= 0) that give the object the apparent
/// stiffness `target` (K of Theorem 2 with E3; symmetric 6x6 in {w} about the centre of mass) at
/// the grasp configuration in `data`; see synthesize_gains and the file comment.
template <typename ModelType, typename DerivedTarget>
SynthesisResult<double> synthesize_stiffness(const ModelType& model, const Data<ModelType>& data,
                                             const Eigen::MatrixBase<DerivedTarget>& target, double tolerance = 1e-9)
{
    return detail::synthesize_at(model, data, target, tolerance);
}

/// \brief Per-arm damping gains d_i, delta_i (all >= 0) that give the object the apparent damping
/// `target` (D of (32)); see synthesize_gains and the file comment.
template <typename ModelType, typename DerivedTarget>
SynthesisResult<double> synthesize_damping(const ModelType& model, const Data<ModelType>& data,
                                           const Eigen::MatrixBase<DerivedTarget>& target, double tolerance = 1e-9)
{
    return detail::synthesize_at(model, data, target, tolerance);
}

/// \brief Damping matrix that gives every mode of (M, K) the damping ratio zeta (classical
/// damping; compare docs/analysis.md and errata E4):
/// D = 2 zeta M^(1/2) (M^(-1/2) K M^(-1/2))^(1/2) M^(1/2).
/// For the M-normalised modes K v = w^2 M v this gives v^T D v = 2 zeta w and v_j^T D v_k = 0
/// (j != k), and D M^-1 K = K M^-1 D. The result is generally not reachable by per-arm scalar
/// gains; feed it to synthesize_damping, which says whether it is.
/// \param inertia symmetric positive definite 6x6 M (e.g. (31)).
/// \param stiffness symmetric positive semi-definite 6x6 K.
/// \param damping_ratio zeta >= 0.
/// \throws InvalidArgument on a non-symmetric or indefinite M or K, or a negative zeta.
COOPDYN_LAZY Matrix6<double> classical_damping(const Matrix6<double>& inertia, const Matrix6<double>& stiffness,
                                         double damping_ratio)
{
    const std::string context = "classical damping";
    detail::require_symmetric_positive(inertia, context, "inertia");
    detail::require_symmetric_positive(stiffness, context, "stiffness", /*allow_semidefinite=*/true);
    detail::require_non_negative(damping_ratio, context, "damping_ratio");
    const Eigen::SelfAdjointEigenSolver<Matrix6<double>> inertia_root(0.5 * (inertia + inertia.transpose()));
    const Matrix6<double> root = inertia_root.operatorSqrt();
    const Matrix6<double> inverse_root = inertia_root.operatorInverseSqrt();
    Matrix6<double> normalised = inverse_root * (0.5 * (stiffness + stiffness.transpose())) * inverse_root;
    normalised = 0.5 * (normalised + normalised.transpose()).eval();
    // (M^-1/2 K M^-1/2)^(1/2) from its eigen-decomposition; eigenvalues that rounding made
    // slightly negative (a semi-definite K) are clamped to zero.
    const Eigen::SelfAdjointEigenSolver<Matrix6<double>> modal(normalised);
    const Vector6<double> frequencies = modal.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    const Matrix6<double> modal_root =
        modal.eigenvectors() * frequencies.asDiagonal() * modal.eigenvectors().transpose();
    const Matrix6<double> damping = 2.0 * damping_ratio * root * modal_root * root;
    return 0.5 * (damping + damping.transpose());
}

/// \brief classical_damping of the apparent inertia and stiffness of Theorem 2.
COOPDYN_LAZY Matrix6<double> classical_damping(const ApparentImpedance<double>& impedance, double damping_ratio)
{
    return classical_damping(impedance.inertia, impedance.stiffness, damping_ratio);
}

/// \brief The model's arms with the synthesized stiffness gains k_i, kappa_i (whether or not the
/// target was achievable), to build a new Model from. Throws InvalidArgument on an arm-count
/// mismatch or a negative gain (naming the arm).
template <typename ModelType>
std::vector<typename ModelType::ArmType> arms_with_stiffness(const ModelType& model,
                                                             const SynthesisResult<double>& gains)
{
    detail::require_impedance_model<ModelType>();
    using EndEffector = typename ModelType::EndEffectorModel;
    return detail::arms_with_gains(model, gains, &EndEffector::translational_stiffness,
                                   &EndEffector::rotational_stiffness);
}

/// \brief The model's arms with the synthesized damping gains d_i, delta_i (whether or not the
/// target was achievable), to build a new Model from.
template <typename ModelType>
std::vector<typename ModelType::ArmType> arms_with_damping(const ModelType& model, const SynthesisResult<double>& gains)
{
    detail::require_impedance_model<ModelType>();
    using EndEffector = typename ModelType::EndEffectorModel;
    return detail::arms_with_gains(model, gains, &EndEffector::translational_damping, &EndEffector::rotational_damping);
}

/// \brief A copy of `model` with the synthesized stiffness gains (same object, grasp, gravity).
/// \throws InvalidArgument ('gains') when the synthesis was not achievable (use
///         arms_with_stiffness to apply closest-fit gains deliberately), was made for another
///         number of arms, or has a negative gain (naming the arm).
template <typename ModelType> ModelType with_stiffness(const ModelType& model, const SynthesisResult<double>& gains)
{
    detail::require_achievable(gains, "stiffness");
    return ModelType(model.object(), arms_with_stiffness(model, gains), model.gravity());
}

/// \brief A copy of `model` with the synthesized damping gains (same object, grasp, gravity).
/// \throws InvalidArgument as with_stiffness.
template <typename ModelType> ModelType with_damping(const ModelType& model, const SynthesisResult<double>& gains)
{
    detail::require_achievable(gains, "damping");
    return ModelType(model.object(), arms_with_damping(model, gains), model.gravity());
}

}  // namespace coopdyn
