/// \file
/// \brief Non-squeezing load distribution: the weighted generalized inverse of the grasp matrix
/// (paper (25), errata E2) and the desired end-effector wrenches (26); docs/coordination.md.
///
/// Weights: positive m*_i (scalar, "mass-like") and symmetric positive semi-definite J*_i (3x3,
/// "rotational inertia-like", in {w}). With the weighted centroid c = sum m*_i r_i / m*_o and
/// r'_i = r_i - c, m*_o = sum m*_i, J*_o = sum J*_i + sum m*_i S(r'_i) S(r'_i)^T, block row i of
/// the inverse for a wrench expressed at c is
///
///     [ (m*_i / m*_o) I3    m*_i S(r'_i)^T (J*_o)^-1 ]
///     [ 0_3                 J*_i (J*_o)^-1           ]
///
/// (the printed (25) has the factors of the upper-right block in the wrong order, E2). The object
/// wrench is first shifted from the centre of mass to c (t_c = t_o - c x f). The result satisfies
/// G G+_M = I6 for every grasp, and distributes the wrench as the rigid motion of bodies with
/// those inertias would: with the end-effector inertias as weights (m*_i = m_i, J*_i = J_i) it
/// produces no internal wrench ((53), docs/analysis.md).
///
/// Error policy, said in the names (docs/conventions.md, "Errors"):
/// - `weighted_grasp_inverse`, `load_distribution`: validate their arguments and throw
///   InvalidModel naming the weight and the arm;
/// - `try_distribute_load`: per tick, noexcept, returns false (output untouched) on degenerate
///   weights;
/// - `LoadDistribution::distribute`: per tick, noexcept, weights validated once at construction,
///   so it only asserts.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/fixed_cholesky.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/skew.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace coopdyn {
namespace detail {

/// Relative threshold below which J*_o counts as singular: 1e-12 in double, a few dozen ulps for
/// float (J*_o is a sum of N products, so its rounding noise is a few ulps of its largest
/// eigenvalue). Shared by the per-call test of the kernels and the per-Model test of
/// LoadDistribution, so that weights the class accepts are never refused per tick.
template <typename Scalar> double load_distribution_singularity_tolerance()
{
    return std::max(1e-12, 64.0 * epsilon_of<Scalar>());
}

/// Smallest over largest pivot of the diagonally pivoted L D L^T factorisation of a symmetric 3x3
/// matrix; not positive when the matrix is not positive definite (or holds NaN).
///
/// Why pivoted: for a symmetric positive semi-definite matrix every pivot lies between the
/// extreme eigenvalues, and with the largest remaining diagonal entry chosen first the last pivot
/// is within a small factor of the smallest eigenvalue (rank revealing: over random 3x3 matrices
/// the ratio returned here was between 1 and 16 times lambda_min / lambda_max, never below
/// it). The unpivoted factor is not: for a matrix that is
/// singular up to rounding (two grasp points with zero rotational weights) its smallest pivot can
/// stay far above the rounding level, or come out positive by chance, and the singular J*_o was
/// then inverted (it happened for about half of random degenerate two-arm grasps).
template <typename Scalar> Scalar pivot_ratio(const Matrix3<Scalar>& matrix) noexcept
{
    int first = 0;
    if (matrix(1, 1) > matrix(first, first)) {
        first = 1;
    }
    if (matrix(2, 2) > matrix(first, first)) {
        first = 2;
    }
    const int second = (first + 1) % 3;
    const int third = (first + 2) % 3;
    const Scalar largest = matrix(first, first);
    if (!(largest > Scalar(0))) {
        return Scalar(0);
    }
    // Schur complement of the first pivot on the remaining two indices.
    const Scalar s22 = matrix(second, second) - matrix(second, first) * matrix(second, first) / largest;
    const Scalar s33 = matrix(third, third) - matrix(third, first) * matrix(third, first) / largest;
    const Scalar s23 = matrix(second, third) - matrix(second, first) * matrix(third, first) / largest;
    const bool second_first = s22 >= s33;
    const Scalar middle = second_first ? s22 : s33;
    const Scalar other = second_first ? s33 : s22;
    if (!(middle > Scalar(0))) {
        return Scalar(0);
    }
    return (other - s23 * s23 / middle) / largest;
}

/// Centroid c, centred offsets r'_i and J*_o of a weighted grasp, with the factor of J*_o.
/// `valid` is false when a mass weight is not positive or J*_o is singular to the relative
/// tolerance load_distribution_singularity_tolerance (checked with pivot_ratio).
template <typename Scalar> struct WeightedGrasp {
    Scalar total_mass_weight;                    // m*_o
    Vector3<Scalar> centroid;                    // c, relative to the object's centre of mass
    FixedCholesky<Scalar, 3> rotational_factor;  // of J*_o
    bool valid;

    template <typename DerivedR, typename DerivedMass, typename DerivedInertia>
    WeightedGrasp(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                  const Eigen::MatrixBase<DerivedInertia>& inertia_weights) noexcept
    {
        const Index arms = r.cols();
        bool positive_masses = true;
        total_mass_weight = Scalar(0);
        centroid.setZero();
        for (Index i = 0; i < arms; ++i) {
            positive_masses = positive_masses && mass_weights(i) > Scalar(0);
            total_mass_weight += mass_weights(i);
            centroid += mass_weights(i) * r.col(i).template head<3>();
        }
        centroid /= total_mass_weight;
        // J*_o is the rotational inertia, about the centroid, of bodies with the weights as inertias
        // (25): the composite of diag(m*_i I3, J*_i) shifted to the centred offsets r'_i.
        SpatialInertia<Scalar> weights_about_centroid;
        for (Index i = 0; i < arms; ++i) {
            const Vector3<Scalar> centred = r.col(i).template head<3>() - centroid;
            weights_about_centroid.add_shifted(
                CentralInertia<Scalar>(mass_weights(i), Matrix3<Scalar>(inertia_weights.template block<3, 3>(0, 3 * i))),
                centred);
        }
        const Matrix3<Scalar> rotational = weights_about_centroid.rotational().matrix();
        const bool factored = rotational_factor.compute(rotational);
        valid = positive_masses && factored &&
                pivot_ratio(rotational) > Scalar(load_distribution_singularity_tolerance<Scalar>());
    }
};

/// Run-time checks shared by the throwing kernels: sizes, m*_i > 0 and J*_i symmetric positive
/// semi-definite, each failure naming the parameter (and the arm).
template <typename DerivedR, typename DerivedMass, typename DerivedInertia>
void validate_load_distribution_weights(const Eigen::MatrixBase<DerivedR>& r,
                                        const Eigen::MatrixBase<DerivedMass>& mass_weights,
                                        const Eigen::MatrixBase<DerivedInertia>& inertia_weights)
{
    using Scalar = typename DerivedR::Scalar;
    const Index arms = r.cols();
    if (r.rows() != 3) {
        fail(load_distribution_context(), "r", "must be 3 x N");
    }
    if (mass_weights.size() != arms) {
        fail(load_distribution_context(), "mass_weights", "must have one entry per arm (" + std::to_string(arms) + ")");
    }
    if (inertia_weights.rows() != 3 || inertia_weights.cols() != 3 * arms) {
        fail(load_distribution_context(), "inertia_weights", "must be 3 x 3N (N = " + std::to_string(arms) + ")");
    }
    for (Index i = 0; i < arms; ++i) {
        require_positive(mass_weights(i), load_distribution_context(i), "mass_weights");
        require_symmetric_positive(Matrix3<Scalar>(inertia_weights.template block<3, 3>(0, 3 * i)), load_distribution_context(i),
                                   "inertia_weights", /*allow_semidefinite=*/true);
    }
}

[[noreturn]] inline void fail_degenerate_grasp()
{
    fail(load_distribution_context(), "inertia_weights",
         "make J*_o singular (degenerate grasp: e.g. zero rotational weights with collinear grasp points); the "
         "object torque about that axis cannot be distributed");
}

}  // namespace detail

/// \brief Weighted generalized inverse G+_M of the grasp matrix, 6N x 6, paper (25) with errata
/// E2 and the centroid shift of docs/coordination.md, so that G G+_M = I6 for any grasp.
/// \param r 3 x N grasp offsets in {w}.
/// \param mass_weights N positive weights m*_i.
/// \param inertia_weights 3 x 3N, the weights J*_i (symmetric positive semi-definite) side by side.
/// \throws InvalidModel naming the parameter (and the arm) if the sizes disagree, a mass weight is
///         not positive, a J*_i is not symmetric positive semi-definite, or the weights are
///         degenerate: J*_o singular to a relative 1e-12 (e.g. zero rotational weights with all
///         grasp points on one line, or two arms).
template <typename DerivedR, typename DerivedMass, typename DerivedInertia>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 6>
weighted_grasp_inverse(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                       const Eigen::MatrixBase<DerivedInertia>& inertia_weights)
{
    using Scalar = typename DerivedR::Scalar;
    const Index arms = r.cols();
    detail::validate_load_distribution_weights(r, mass_weights, inertia_weights);
    const detail::WeightedGrasp<Scalar> grasp(r, mass_weights, inertia_weights);
    if (!grasp.valid) {
        detail::fail_degenerate_grasp();
    }
    // (J*_o)^-1 column by column.
    Matrix3<Scalar> rotational_inverse;
    for (int column = 0; column < 3; ++column) {
        rotational_inverse.col(column) = grasp.rotational_factor.solve(Vector3<Scalar>::Unit(column));
    }
    // Shift of the object wrench from the centre of mass to the centroid: t_c = t_o - c x f.
    Matrix6<Scalar> shift = Matrix6<Scalar>::Identity();
    shift.template bottomLeftCorner<3, 3>() = -skew(grasp.centroid);

    Eigen::Matrix<Scalar, times_six(DerivedR::ColsAtCompileTime), 6> result(6 * arms, 6);
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> centred = r.col(i).template head<3>() - grasp.centroid;
        Matrix6<Scalar> block = Matrix6<Scalar>::Zero();
        block.template topLeftCorner<3, 3>().diagonal().setConstant(mass_weights(i) / grasp.total_mass_weight);
        block.template topRightCorner<3, 3>() = mass_weights(i) * skew(centred).transpose() * rotational_inverse;
        block.template bottomRightCorner<3, 3>() = inertia_weights.template block<3, 3>(0, 3 * i) * rotational_inverse;
        result.template middleRows<6>(6 * i) = block * shift;
    }
    return result;
}

/// \brief Desired wrenches h_i^d = -(G+_M h_o^d)_i of (26) written into caller storage (6N), in
/// O(N) without forming G+_M. h_i^d is the desired wrench ON arm i (so the arms apply
/// hbar^d = G+_M h_o^d to the object). Arguments as in weighted_grasp_inverse; object_wrench is
/// h_o^d (6) at the object's centre of mass. Returns false, leaving `desired_wrenches_out`
/// untouched, when a mass weight is not positive or J*_o is singular to a relative 1e-12 (the
/// same test as weighted_grasp_inverse); sizes are checked by debug assertions only. A
/// Model-level user validates the weights once instead (LoadDistribution).
template <typename DerivedR, typename DerivedMass, typename DerivedInertia, typename DerivedWrench,
          typename DerivedOut>
bool try_distribute_load(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                     const Eigen::MatrixBase<DerivedInertia>& inertia_weights,
                     const Eigen::MatrixBase<DerivedWrench>& object_wrench,
                     const Eigen::MatrixBase<DerivedOut>& desired_wrenches_out) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    auto& desired_wrenches = const_cast<Eigen::MatrixBase<DerivedOut>&>(desired_wrenches_out);
    const Index arms = r.cols();
    COOPDYN_ASSERT(desired_wrenches.size() == 6 * arms, "desired wrenches must have 6N entries");
    const detail::WeightedGrasp<Scalar> grasp(r, mass_weights, inertia_weights);
    if (!grasp.valid) {
        return false;
    }
    const Vector3<Scalar> force = object_wrench.template head<3>();
    const Vector3<Scalar> torque_at_centroid = object_wrench.template tail<3>() - grasp.centroid.cross(force);
    const Vector3<Scalar> angular = grasp.rotational_factor.solve(torque_at_centroid);  // (J*_o)^-1 t_c
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> centred = r.col(i).template head<3>() - grasp.centroid;
        // hbar_i = [(m*_i/m*_o) f + m*_i S(r'_i)^T a; J*_i a] with a = (J*_o)^-1 t_c; h_i^d = -hbar_i.
        desired_wrenches.template segment<3>(6 * i) =
            -(mass_weights(i) / grasp.total_mass_weight) * force - mass_weights(i) * angular.cross(centred);
        desired_wrenches.template segment<3>(6 * i + 3) =
            -(inertia_weights.template block<3, 3>(0, 3 * i) * angular);
    }
    return true;
}

/// \brief Desired end-effector wrenches h'^d (6N), h_i^d = -(G+_M h_o^d)_i, (26). Throws
/// InvalidModel on invalid or degenerate weights, naming the parameter and the arm (see
/// weighted_grasp_inverse).
template <typename DerivedR, typename DerivedMass, typename DerivedInertia, typename DerivedWrench>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>
load_distribution(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                  const Eigen::MatrixBase<DerivedInertia>& inertia_weights,
                  const Eigen::MatrixBase<DerivedWrench>& object_wrench)
{
    detail::validate_load_distribution_weights(r, mass_weights, inertia_weights);
    if (object_wrench.size() != 6) {
        detail::fail(detail::argument_context("load distribution"), "object_wrench", "must have 6 entries");
    }
    Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1> result =
        Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>::Zero(6 * r.cols());
    if (!try_distribute_load(r, mass_weights, inertia_weights, object_wrench, result)) {
        detail::fail_degenerate_grasp();
    }
    return result;
}

/// \brief Load distribution (26) for a Model: validated weights, then an allocation-free,
/// noexcept per-tick distribution at the grasp configuration in a Data.
///
/// Default weights are the end-effector inertias (m*_i = m_i, J*_i = J_i): each arm then carries
/// the share of the load that the rigid motion of its own inertia would take. The J*_i are
/// constant in {w} like the J_i.
template <typename ModelType> class LoadDistribution {
public:
    using Scalar = typename ModelType::Scalar;
    static constexpr int Arms = ModelType::arms_at_compile_time;
    using MassWeights = Eigen::Matrix<Scalar, Arms, 1>;
    using InertiaWeights = PerArmMatrix3<Scalar, Arms>;

    /// Weights from the end-effector inertias.
    explicit LoadDistribution(const ModelType& model)
        : LoadDistribution(model, model.end_effector_masses(), model.end_effector_rotational_inertias())
    {
    }

    /// \param mass_weights N positive weights m*_i.
    /// \param inertia_weights 3 x 3N symmetric positive semi-definite J*_i.
    /// Throws InvalidModel (naming the parameter and the arm) on invalid weights, and when the
    /// weights are degenerate: J*_o = sum J*_i + sum m*_i S(r'_i) S(r'_i)^T must be positive
    /// definite (to a relative 1e-12) in every orientation, i.e. the grasp points must not be
    /// collinear unless sum J*_i is positive definite.
    LoadDistribution(const ModelType& model, MassWeights mass_weights, InertiaWeights inertia_weights)
        : mass_weights_(std::move(mass_weights)), inertia_weights_(std::move(inertia_weights))
    {
        const Index arms = model.arms();
        if (mass_weights_.size() != arms) {
            detail::fail(detail::load_distribution_context(), "mass_weights", "must have one entry per arm (" + std::to_string(arms) + ")");
        }
        if (inertia_weights_.rows() != 3 || inertia_weights_.cols() != 3 * arms) {
            detail::fail(detail::load_distribution_context(), "inertia_weights", "must be 3 x 3N");
        }
        Matrix3<Scalar> rotational_weight_sum = Matrix3<Scalar>::Zero();
        for (Index i = 0; i < arms; ++i) {
            detail::require_positive(mass_weights_(i), detail::load_distribution_context(i), "mass_weights");
            detail::require_symmetric_positive(Matrix3<Scalar>(inertia_weights_.template block<3, 3>(0, 3 * i)),
                                               detail::load_distribution_context(i), "inertia_weights", /*allow_semidefinite=*/true);
            rotational_weight_sum += inertia_weights_.template block<3, 3>(0, 3 * i);
        }
        // The spread of the grasp points, sum m*_i S(r'_i) S(r'_i)^T, rotates with the object but
        // keeps its eigenvalues; it is singular exactly when the points are collinear. In any
        // orientation lambda_min(J*_o) >= max(lambda_min(spread), lambda_min(sum J*_i)) and
        // lambda_max(J*_o) <= lambda_max(spread) + lambda_max(sum J*_i), so requiring the first
        // above the tolerance times the second keeps J*_o well conditioned in every orientation,
        // and then the per-tick test of try_distribute_load (whose pivot ratio is never below
        // lambda_min / lambda_max, up to rounding) passes. Relative only: a common scale of all
        // weights changes nothing in (25).
        const Vector3<Scalar> centroid = model.grasp_offsets_body() * mass_weights_ / mass_weights_.sum();
        Matrix3<Scalar> spread = Matrix3<Scalar>::Zero();
        for (Index i = 0; i < arms; ++i) {
            spread += mass_weights_(i) * skew_gram(Vector3<Scalar>(model.grasp_offsets_body().col(i) - centroid));
        }
        const auto eigenvalues = [](const Matrix3<Scalar>& matrix) {
            return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(detail::values_of(matrix), Eigen::EigenvaluesOnly)
                .eigenvalues()
                .eval();
        };
        const Eigen::Vector3d spread_eigenvalues = eigenvalues(spread);
        const Eigen::Vector3d rotational_eigenvalues = eigenvalues(rotational_weight_sum);
        const double smallest_bound = std::max(spread_eigenvalues(0), rotational_eigenvalues(0));
        const double largest_bound = spread_eigenvalues(2) + rotational_eigenvalues(2);
        if (!(smallest_bound > detail::load_distribution_singularity_tolerance<Scalar>() * largest_bound)) {
            detail::fail(detail::load_distribution_context(), "inertia_weights",
                         "are degenerate: the grasp points are collinear and the sum of the rotational weights "
                         "J*_i is singular, so J*_o is singular in some orientation and the torque about the grasp "
                         "line cannot be distributed");
        }
    }

    /// Desired end-effector wrenches h_i^d = -(G+_M h_o^d)_i (26) at the grasp configuration in
    /// `data` (after grasp_kinematics), written into setpoints.wrenches.
    template <typename DerivedWrench>
    void distribute(const Data<ModelType>& data, const Eigen::MatrixBase<DerivedWrench>& object_wrench,
                    Setpoints<Scalar, Arms>& setpoints) const noexcept
    {
        const bool distributed =
            try_distribute_load(data.grasp_offsets, mass_weights_, inertia_weights_, object_wrench, setpoints.wrenches);
        COOPDYN_ASSERT(distributed, "weights validated at construction cannot be degenerate");
        (void)distributed;
    }

    const MassWeights& mass_weights() const noexcept { return mass_weights_; }
    const InertiaWeights& inertia_weights() const noexcept { return inertia_weights_; }

private:
    MassWeights mass_weights_;
    InertiaWeights inertia_weights_;
};

}  // namespace coopdyn
