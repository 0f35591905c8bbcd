/// \file
/// \brief Non-squeezing load distribution: the weighted generalized inverse of the grasp matrix
/// (paper (25), errata E2) and the desired end-effector wrenches (26); docs/coordination.md. The
/// inverse itself (detail::WeightedGrasp, shared with the unweighted G^+ of the projected
/// dynamics) is in model/grasp_inverse.hpp; this header validates the weights and distributes.
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
///   InvalidModel naming the weight and the arm (InvalidArgument for a mis-sized r or object
///   wrench);
/// - `try_distribute_load`: per tick, noexcept, returns false (output untouched) on degenerate
///   weights;
/// - `LoadDistribution::distribute`: per tick, noexcept, weights validated once at construction,
///   so it only asserts.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/input_check.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp_inverse.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/skew.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace coopdyn {
namespace detail {

/// Relative threshold below which J*_o counts as singular: the pivot policy's tolerance
/// (numerics/pivot_policy.hpp, 1000 eps of Scalar's precision), in double for the eigenvalue test
/// of LoadDistribution. Shared by the per-call test of the kernels (through regular_pivot) and the
/// per-Model test of LoadDistribution, so that weights the class accepts are never refused per
/// tick.
template <typename Scalar> double load_distribution_singularity_tolerance()
{
    return static_cast<double>(pivot_tolerance_ulps) * epsilon_of<Scalar>();
}

/// The weights of (25) in the stacked form: m*_i (N) and J*_i side by side (3 x 3N), read arm by
/// arm as the central inertia diag(m*_i I3, J*_i) (the lower triangle of J*_i).
template <typename DerivedMass, typename DerivedInertia> struct StackedLoadWeights {
    using Scalar = typename DerivedMass::Scalar;
    const Eigen::MatrixBase<DerivedMass>& mass;
    const Eigen::MatrixBase<DerivedInertia>& inertia;
    CentralInertia<Scalar> operator[](std::size_t arm) const noexcept
    {
        const Index i = static_cast<Index>(arm);
        return CentralInertia<Scalar>(mass(i), inertia.template block<3, 3>(0, 3 * i));
    }
    std::size_t size() const noexcept { return static_cast<std::size_t>(mass.size()); }
};

template <typename DerivedMass, typename DerivedInertia>
StackedLoadWeights<DerivedMass, DerivedInertia> stacked_load_weights(const Eigen::MatrixBase<DerivedMass>& mass,
                                                                     const Eigen::MatrixBase<DerivedInertia>& inertia) noexcept
{
    return StackedLoadWeights<DerivedMass, DerivedInertia>{mass, inertia};
}

/// A list of weights: a container (std::vector, std::array) of CentralInertia, one per arm.
template <typename Container, typename = void> struct is_load_weight_list : std::false_type {};
template <typename Container>
struct is_load_weight_list<Container, std::void_t<decltype(std::declval<const Container&>()[std::size_t(0)]),
                                                  decltype(std::declval<const Container&>().size())>>
    : std::is_same<std::decay_t<decltype(std::declval<const Container&>()[std::size_t(0)])>,
                   CentralInertia<typename std::decay_t<decltype(std::declval<const Container&>()[std::size_t(0)])>::Scalar>> {};
template <typename Container> inline constexpr bool is_load_weight_list_v = is_load_weight_list<Container>::value;

/// Run-time checks of one weight, naming the parameter and the arm: m*_i > 0 and J*_i symmetric
/// positive semi-definite.
template <typename Scalar>
void validate_load_weight(const Scalar& mass, const Matrix3<Scalar>& rotational, Index arm)
{
    require_positive(mass, load_distribution_context(arm), "mass_weights");
    require_symmetric_positive(rotational, load_distribution_context(arm), "inertia_weights", /*allow_semidefinite=*/true);
}

/// Run-time checks shared by the throwing kernels and LoadDistribution: sizes, then every weight.
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
        validate_load_weight(Scalar(mass_weights(i)), Matrix3<Scalar>(inertia_weights.template block<3, 3>(0, 3 * i)), i);
    }
}

/// The same for a list of weights (the rotational weight is symmetric by its type).
template <typename Weights, typename DerivedR>
void validate_load_weight_list(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r)
{
    if (r.rows() != 3) {
        fail(load_distribution_context(), "r", "must be 3 x N");
    }
    if (static_cast<Index>(weights.size()) != r.cols()) {
        fail(load_distribution_context(), "weights", "must have one entry per arm (" + std::to_string(r.cols()) + ")");
    }
    for (Index i = 0; i < r.cols(); ++i) {
        const auto& weight = weights[static_cast<std::size_t>(i)];
        validate_load_weight(weight.mass(), weight.rotational().matrix(), i);
    }
}

[[noreturn]] inline void fail_degenerate_grasp()
{
    fail(load_distribution_context(), "inertia_weights",
         "make J*_o singular (degenerate grasp: e.g. zero rotational weights with collinear grasp points); the "
         "object torque about that axis cannot be distributed");
}

/// G+_M column by column: column k is the distribution of the unit wrench e_k (no validation).
template <typename Weights, typename DerivedR>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 6>
weighted_grasp_inverse_of(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r)
{
    using Scalar = typename DerivedR::Scalar;
    const WeightedGrasp<Scalar> grasp(weights, r);
    if (!grasp.valid) {
        fail_degenerate_grasp();
    }
    Eigen::Matrix<Scalar, times_six(DerivedR::ColsAtCompileTime), 6> result(6 * r.cols(), 6);
    grasp.write_inverse(weights, r, result);
    return result;
}

/// h_i^d = -hbar_i into `desired_wrenches` (6N); false, output untouched, on degenerate weights.
template <typename Weights, typename DerivedR, typename DerivedWrench, typename DerivedOut>
bool try_distribute(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                    const Eigen::MatrixBase<DerivedWrench>& object_wrench,
                    const Eigen::MatrixBase<DerivedOut>& desired_wrenches_out) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    auto& desired_wrenches = const_cast<Eigen::MatrixBase<DerivedOut>&>(desired_wrenches_out);
    COOPDYN_ASSERT(desired_wrenches.size() == 6 * r.cols(), "desired wrenches must have 6N entries");
    COOPDYN_ASSERT(object_wrench.size() == 6, "the object wrench must have 6 entries");
    const WeightedGrasp<Scalar> grasp(weights, r);
    if (!grasp.valid) {
        return false;
    }
    const Motion<Scalar> motion = grasp.composite_motion(
        Force<Scalar>::make(object_wrench.template head<3>(), object_wrench.template tail<3>()));
    for (Index i = 0; i < r.cols(); ++i) {
        (-grasp.share(weights, r, i, motion)).write_to(desired_wrenches.template segment<6>(6 * i));
    }
    return true;
}

/// h'^d by value for validated weights; throws on a wrong-size object wrench or degenerate weights.
template <typename Weights, typename DerivedR, typename DerivedWrench>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>
load_distribution_of(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                     const Eigen::MatrixBase<DerivedWrench>& object_wrench)
{
    if (object_wrench.size() != 6) {
        fail(argument_context("load distribution"), "object_wrench", "must have 6 entries");
    }
    using Result = Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>;
    Result result = Result::Zero(6 * r.cols());
    if (!try_distribute(weights, r, object_wrench, result)) {
        fail_degenerate_grasp();
    }
    return result;
}

}  // namespace detail

/// \brief Weighted generalized inverse G+_M of the grasp matrix, 6N x 6, paper (25) with errata
/// E2 and the centroid shift of docs/coordination.md, so that G G+_M = I6 for any grasp.
/// \param r 3 x N grasp offsets in {w}.
/// \param mass_weights N positive weights m*_i.
/// \param inertia_weights 3 x 3N, the weights J*_i (symmetric positive semi-definite) side by side.
/// \throws InvalidModel naming the parameter (and the arm) if the sizes disagree, a mass weight is
///         not positive, a J*_i is not symmetric positive semi-definite, or the weights are
///         degenerate: J*_o singular by the pivot policy (relative 1000 eps,
///         numerics/pivot_policy.hpp; e.g. zero rotational weights with all grasp points on one
///         line, or two arms).
template <typename DerivedR, typename DerivedMass, typename DerivedInertia>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 6>
weighted_grasp_inverse(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                       const Eigen::MatrixBase<DerivedInertia>& inertia_weights)
{
    detail::validate_load_distribution_weights(r, mass_weights, inertia_weights);
    return detail::weighted_grasp_inverse_of(detail::stacked_load_weights(mass_weights, inertia_weights), r);
}

/// \brief weighted_grasp_inverse in the argument order of docs/conventions.md: the weights
/// M*_i = diag(m*_i I3, J*_i) as a list of CentralInertia (one per arm; e.g.
/// model.end_effector_inertia_list() for the non-squeezing weights), then r. Throws as above.
template <typename Weights, typename DerivedR, std::enable_if_t<detail::is_load_weight_list_v<Weights>, int> = 0>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 6>
weighted_grasp_inverse(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r)
{
    detail::validate_load_weight_list(weights, r);
    return detail::weighted_grasp_inverse_of(weights, r);
}

/// \brief Desired wrenches h_i^d = -(G+_M h_o^d)_i of (26) written into caller storage (6N), in
/// O(N) without forming G+_M. h_i^d is the desired wrench ON arm i (so the arms apply
/// hbar^d = G+_M h_o^d to the object). Arguments as in weighted_grasp_inverse; object_wrench is
/// h_o^d (6) at the object's centre of mass. Returns false, leaving `desired_wrenches_out`
/// untouched, when a mass weight is not positive or J*_o is singular by the pivot policy
/// (relative 1000 eps; the same test as weighted_grasp_inverse); sizes are checked by debug
/// assertions only. A Model-level user validates the weights once instead (LoadDistribution).
template <typename DerivedR, typename DerivedMass, typename DerivedInertia, typename DerivedWrench,
          typename DerivedOut>
bool try_distribute_load(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                         const Eigen::MatrixBase<DerivedInertia>& inertia_weights,
                         const Eigen::MatrixBase<DerivedWrench>& object_wrench,
                         const Eigen::MatrixBase<DerivedOut>& desired_wrenches_out) noexcept
{
    COOPDYN_ASSERT(mass_weights.size() == r.cols() && inertia_weights.cols() == 3 * r.cols(),
                   "one weight per arm: N mass weights, 3 x 3N inertia weights");
    return detail::try_distribute(detail::stacked_load_weights(mass_weights, inertia_weights), r, object_wrench,
                                  desired_wrenches_out);
}

/// \brief try_distribute_load in the argument order of docs/conventions.md: the weights as a list
/// of CentralInertia (as weighted_grasp_inverse(weights, r)), r, h_o^d, then the output.
template <typename Weights, typename DerivedR, typename DerivedWrench, typename DerivedOut,
          std::enable_if_t<detail::is_load_weight_list_v<Weights>, int> = 0>
bool try_distribute_load(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                         const Eigen::MatrixBase<DerivedWrench>& object_wrench,
                         const Eigen::MatrixBase<DerivedOut>& desired_wrenches_out) noexcept
{
    COOPDYN_ASSERT(static_cast<Index>(weights.size()) == r.cols(), "one weight per arm");
    return detail::try_distribute(weights, r, object_wrench, desired_wrenches_out);
}

/// \brief Desired end-effector wrenches h'^d (6N), h_i^d = -(G+_M h_o^d)_i, (26). Throws
/// InvalidModel on invalid or degenerate weights, naming the parameter and the arm (see
/// weighted_grasp_inverse), InvalidArgument when the object wrench is not a 6-vector.
template <typename DerivedR, typename DerivedMass, typename DerivedInertia, typename DerivedWrench>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>
load_distribution(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedMass>& mass_weights,
                  const Eigen::MatrixBase<DerivedInertia>& inertia_weights,
                  const Eigen::MatrixBase<DerivedWrench>& object_wrench)
{
    detail::validate_load_distribution_weights(r, mass_weights, inertia_weights);
    return detail::load_distribution_of(detail::stacked_load_weights(mass_weights, inertia_weights), r, object_wrench);
}

/// \brief load_distribution in the argument order of docs/conventions.md: the weights as a list
/// of CentralInertia, r, h_o^d. Throws as above.
template <typename Weights, typename DerivedR, typename DerivedWrench,
          std::enable_if_t<detail::is_load_weight_list_v<Weights>, int> = 0>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>
load_distribution(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                  const Eigen::MatrixBase<DerivedWrench>& object_wrench)
{
    detail::validate_load_weight_list(weights, r);
    return detail::load_distribution_of(weights, r, object_wrench);
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
    /// definite (to the pivot policy's relative 1000 eps) in every orientation, i.e. the grasp
    /// points must not be collinear unless sum J*_i is positive definite.
    LoadDistribution(const ModelType& model, MassWeights mass_weights, InertiaWeights inertia_weights)
        : mass_weights_(std::move(mass_weights)), inertia_weights_(std::move(inertia_weights))
    {
        detail::validate_load_distribution_weights(model.grasp_offsets_body(), mass_weights_, inertia_weights_);
        // The spread of the grasp points, sum m*_i S(r'_i) S(r'_i)^T (the rotational inertia about
        // the centroid of point masses m*_i at the grasp points), rotates with the object but
        // keeps its eigenvalues; it is singular exactly when the points are collinear. In any
        // orientation lambda_min(J*_o) >= max(lambda_min(spread), lambda_min(sum J*_i)) and
        // lambda_max(J*_o) <= lambda_max(spread) + lambda_max(sum J*_i), so requiring the first
        // above the tolerance times the second keeps J*_o well conditioned in every orientation,
        // and then the per-tick test of try_distribute_load (whose pivot ratio is never below
        // lambda_min / lambda_max, up to rounding) passes. Relative only: a common scale of all
        // weights changes nothing in (25).
        const auto& offsets = model.grasp_offsets_body();
        const InertiaWeights no_rotational_weights = InertiaWeights::Zero(3, 3 * model.arms());
        const auto weights = detail::stacked_load_weights(mass_weights_, inertia_weights_);
        const auto point_masses = detail::stacked_load_weights(mass_weights_, no_rotational_weights);
        const Vector3<Scalar> centroid = detail::composite_of_weights(weights, offsets, Vector3<Scalar>::Zero()).centre();
        const Matrix3<Scalar> spread = detail::composite_of_weights(point_masses, offsets, centroid).rotational().matrix();
        Symmetric3<Scalar> rotational_weight_sum;
        for (std::size_t i = 0; i < weights.size(); ++i) {
            rotational_weight_sum += weights[i].rotational();
        }
        const auto eigenvalues = [](const Matrix3<Scalar>& matrix) {
            return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(detail::values_of(matrix), Eigen::EigenvaluesOnly)
                .eigenvalues()
                .eval();
        };
        const Eigen::Vector3d spread_eigenvalues = eigenvalues(spread);
        const Eigen::Vector3d rotational_eigenvalues = eigenvalues(rotational_weight_sum.matrix());
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
        COOPDYN_REQUIRE_SHAPE(data.arms() == mass_weights_.size(), "Data was built for another number of arms");
        COOPDYN_REQUIRE_SHAPE(setpoints.arms() == mass_weights_.size(), "setpoints sized for another number of arms");
        COOPDYN_ASSERT_INPUTS((detail::all_finite(object_wrench) ? InputCheck{}
                                                                 : InputCheck{InputProblem::object_wrench, no_arm}));
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
