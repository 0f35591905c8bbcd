/// \file
/// \brief Structured O(N) interaction wrench of the rigid grasp (MODEL.md section 5): the
/// Udwadia-Kalaba solution (18) computed in the object's reduced coordinates.
///
/// With G_i = [[I3, 0], [S(r_i), I3]] and b_i = [S(w_o)^2 r_i; 0]:
///
///     Ma = M_o + sum_i G_i M_i G_i^T
///     Ma xdd_o = hSigma_o + sum_i G_i (hSigma_i - M_i b_i)
///     xdd_i = G_i^T xdd_o + b_i,   h_o = M_o xdd_o - hSigma_o,   h_i = M_i xdd_i - hSigma_i
///
/// This is (18) restricted to the constraint manifold A xdd = b: the accelerations are the
/// minimiser of Gauss's function (19), written in the N + 1 bodies' common rigid motion.
/// One 6x6 factorisation per tick; everything else is per-arm 3-vector algebra.
///
/// Two inertia structures have their own path, chosen at compile time by the caller:
/// - general SPD 6x6 end-effector inertias (e.g. the resolved-acceleration Lambda_i of (21)):
///   `interaction_wrenches`, a written-out 6x6 Cholesky of Ma;
/// - block-diagonal diag(m_i I3, J_i) (the impedance end-effector (1)):
///   `interaction_wrenches_block_diagonal`, where Ma's translational block is a multiple of I3,
///   so eliminating it by hand leaves one 3x3 Schur complement.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/fixed_cholesky.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/spatial/skew.hpp"

namespace coopdyn {
namespace detail {

/// Ma = M_o + sum G_i M_i G_i^T, symmetric; only its lower triangle is kept up to date, which is
/// all the Cholesky factorisation reads.
template <typename Scalar> struct GeneralCompositeInertia {
    Matrix6<Scalar> matrix;

    /// Solve Ma xdd_o = rhs.
    Vector6<Scalar> solve(const Vector6<Scalar>& rhs) const noexcept
    {
        FixedCholesky<Scalar, 6> factor;
        const bool positive_definite = factor.compute(matrix);
        COOPDYN_ASSERT(positive_definite, "composite inertia Ma must be positive definite");
        (void)positive_definite;
        return factor.solve(rhs);
    }
};

/// Ma for block-diagonal inertias: [[m I3, S(s)^T], [S(s), J]], with total mass m, first moment
/// s = sum m_i r_i and rotational block J = J_o + sum (J_i + m_i S(r_i) S(r_i)^T).
template <typename Scalar> struct BlockDiagonalCompositeInertia {
    Scalar mass;
    Vector3<Scalar> first_moment;
    Matrix3<Scalar> rotational;

    /// Solve Ma [a; alpha] = [f; t] by eliminating the translational block: with the composite
    /// centre of mass c = s / m, (J - m S(c) S(c)^T) alpha = t - c x f and a = f / m + c x alpha.
    Vector6<Scalar> solve(const Vector6<Scalar>& rhs) const noexcept
    {
        const Vector3<Scalar> centre = first_moment / mass;
        const Matrix3<Scalar> schur = rotational - mass * skew_gram(centre);
        FixedCholesky<Scalar, 3> factor;
        const bool positive_definite = factor.compute(schur);
        COOPDYN_ASSERT(positive_definite, "composite rotational inertia must be positive definite");
        (void)positive_definite;
        const Vector3<Scalar> force = rhs.template head<3>();
        Vector6<Scalar> solution;
        solution.template tail<3>() = factor.solve(rhs.template tail<3>() - centre.cross(force));
        solution.template head<3>() = force / mass + centre.cross(solution.template tail<3>());
        return solution;
    }
};

/// Object inertia given as a general 6x6 matrix.
template <typename Derived> struct GeneralObjectInertia {
    using Scalar = typename Derived::Scalar;
    const Eigen::MatrixBase<Derived>& matrix;

    void initialise(GeneralCompositeInertia<Scalar>& composite) const noexcept
    {
        composite.matrix = matrix;
    }
    Vector6<Scalar> apply(const Vector6<Scalar>& acceleration) const noexcept
    {
        return matrix * acceleration;
    }
};

/// Object inertia diag(m_o I3, J_o).
template <typename Derived> struct BlockDiagonalObjectInertia {
    using Scalar = typename Derived::Scalar;
    Scalar mass;
    const Eigen::MatrixBase<Derived>& rotational;

    void initialise(GeneralCompositeInertia<Scalar>& composite) const noexcept
    {
        composite.matrix.setZero();
        composite.matrix.template topLeftCorner<3, 3>().diagonal().setConstant(mass);
        composite.matrix.template bottomRightCorner<3, 3>() = rotational;
    }
    void initialise(BlockDiagonalCompositeInertia<Scalar>& composite) const noexcept
    {
        composite.mass = mass;
        composite.first_moment.setZero();
        composite.rotational = rotational;
    }
    Vector6<Scalar> apply(const Vector6<Scalar>& acceleration) const noexcept
    {
        Vector6<Scalar> result;
        result.template head<3>() = mass * acceleration.template head<3>();
        result.template tail<3>() = rotational * acceleration.template tail<3>();
        return result;
    }
};

/// End-effector inertias M_i as general SPD 6x6 blocks of a 6 x 6N stack.
template <typename Derived> struct GeneralEndEffectorInertias {
    using Scalar = typename Derived::Scalar;
    using Composite = GeneralCompositeInertia<Scalar>;
    const Eigen::MatrixBase<Derived>& stack;

    /// Ma += G_i M_i G_i^T. With M_i = [[A, B], [B^T, C]] and S = S(r_i):
    /// G_i M_i G_i^T = [[A, (S A)^T + B], [S A + B^T, S A S^T + S B + (S B)^T + C]].
    void add_to_composite(Index arm, const Vector3<Scalar>& r_i, Composite& composite) const noexcept
    {
        const auto inertia = stack.template block<6, 6>(0, 6 * arm);
        const Matrix3<Scalar> s = skew(r_i);
        const Matrix3<Scalar> s_a = s * inertia.template topLeftCorner<3, 3>();
        const Matrix3<Scalar> s_b = s * inertia.template topRightCorner<3, 3>();
        const Matrix3<Scalar> lower_left = s_a + inertia.template bottomLeftCorner<3, 3>();
        composite.matrix.template topLeftCorner<3, 3>() += inertia.template topLeftCorner<3, 3>();
        composite.matrix.template bottomLeftCorner<3, 3>() += lower_left;
        composite.matrix.template bottomRightCorner<3, 3>() +=
            s_a * s.transpose() + s_b + s_b.transpose() + inertia.template bottomRightCorner<3, 3>();
    }
    Vector6<Scalar> apply(Index arm, const Vector6<Scalar>& acceleration) const noexcept
    {
        return stack.template block<6, 6>(0, 6 * arm) * acceleration;
    }
    /// M_i [a; 0].
    Vector6<Scalar> apply_linear(Index arm, const Vector3<Scalar>& acceleration) const noexcept
    {
        return stack.template block<6, 3>(0, 6 * arm) * acceleration;
    }
};

/// End-effector inertias diag(m_i I3, J_i): masses (N) and rotational blocks (3 x 3N).
template <typename DerivedMasses, typename DerivedRotational> struct BlockDiagonalEndEffectorInertias {
    using Scalar = typename DerivedMasses::Scalar;
    using Composite = BlockDiagonalCompositeInertia<Scalar>;
    const Eigen::MatrixBase<DerivedMasses>& masses;
    const Eigen::MatrixBase<DerivedRotational>& rotational;

    /// Ma += G_i diag(m_i I3, J_i) G_i^T = [[m_i I3, m_i S(r_i)^T], [m_i S(r_i), J_i + m_i S S^T]].
    void add_to_composite(Index arm, const Vector3<Scalar>& r_i, Composite& composite) const noexcept
    {
        const Scalar mass = masses(arm);
        composite.mass += mass;
        composite.first_moment += mass * r_i;
        composite.rotational +=
            rotational.template block<3, 3>(0, 3 * arm) + mass * skew_gram(r_i);
    }
    Vector6<Scalar> apply(Index arm, const Vector6<Scalar>& acceleration) const noexcept
    {
        Vector6<Scalar> result;
        result.template head<3>() = masses(arm) * acceleration.template head<3>();
        result.template tail<3>() =
            rotational.template block<3, 3>(0, 3 * arm) * acceleration.template tail<3>();
        return result;
    }
    Vector6<Scalar> apply_linear(Index arm, const Vector3<Scalar>& acceleration) const noexcept
    {
        Vector6<Scalar> result;
        result.template head<3>() = masses(arm) * acceleration;
        result.template tail<3>().setZero();
        return result;
    }
};

/// The structured solve shared by every inertia structure (MODEL.md section 5).
template <typename ObjectInertia, typename EndEffectorInertias, typename DerivedR,
          typename DerivedOmega, typename DerivedSigma, typename DerivedAcceleration,
          typename DerivedWrench>
void solve_interaction(const ObjectInertia& object, const EndEffectorInertias& end_effectors,
                       const Eigen::MatrixBase<DerivedR>& r,
                       const Eigen::MatrixBase<DerivedOmega>& omega_o,
                       const Eigen::MatrixBase<DerivedSigma>& h_sigma,
                       const Eigen::MatrixBase<DerivedAcceleration>& accelerations_out,
                       const Eigen::MatrixBase<DerivedWrench>& wrenches_out) noexcept
{
    using Scalar = typename DerivedSigma::Scalar;
    // Eigen's documented idiom for writable expression arguments (blocks, maps, matrices).
    auto& accelerations = const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(accelerations_out);
    auto& wrenches = const_cast<Eigen::MatrixBase<DerivedWrench>&>(wrenches_out);
    const Index arms = r.cols();
    COOPDYN_ASSERT(arms >= 1, "at least one arm");
    COOPDYN_ASSERT(h_sigma.size() == 6 * (arms + 1), "h_sigma must have 6(N+1) entries");
    COOPDYN_ASSERT(accelerations.size() == 6 * (arms + 1), "accelerations must have 6(N+1) entries");
    COOPDYN_ASSERT(wrenches.size() == 6 * (arms + 1), "wrenches must have 6(N+1) entries");

    const Vector3<Scalar> omega = omega_o;
    typename EndEffectorInertias::Composite composite;
    object.initialise(composite);
    Vector6<Scalar> rhs = h_sigma.template head<6>();
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> r_i = r.col(i);
        end_effectors.add_to_composite(i, r_i, composite);
        const Vector6<Scalar> reduced_wrench =
            h_sigma.template segment<6>(6 * (i + 1)) -
            end_effectors.apply_linear(i, centripetal_acceleration(r_i, omega));
        rhs += grasp_map_wrench(r_i, reduced_wrench);
    }

    const Vector6<Scalar> object_acceleration = composite.solve(rhs);
    accelerations.template head<6>() = object_acceleration;
    wrenches.template head<6>() = object.apply(object_acceleration) - h_sigma.template head<6>();
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> r_i = r.col(i);
        Vector6<Scalar> acceleration = grasp_map_twist(r_i, object_acceleration);
        acceleration.template head<3>() += centripetal_acceleration(r_i, omega);
        accelerations.template segment<6>(6 * (i + 1)) = acceleration;
        wrenches.template segment<6>(6 * (i + 1)) =
            end_effectors.apply(i, acceleration) - h_sigma.template segment<6>(6 * (i + 1));
    }
}

/// Number of arms of a kernel call, fixed when any argument fixes it.
template <typename DerivedR, typename DerivedSigma> constexpr int kernel_arms() noexcept
{
    static_assert(sizes_agree(DerivedR::ColsAtCompileTime,
                              arms_from_full_rows(DerivedSigma::RowsAtCompileTime)),
                  "r (3 x N) and h_sigma (6(N+1)) disagree on N");
    return first_fixed(DerivedR::ColsAtCompileTime, arms_from_full_rows(DerivedSigma::RowsAtCompileTime));
}

}  // namespace detail

/// \brief Accelerations and interaction wrenches of the rigid grasp, general SPD inertias,
/// written into caller-owned storage (MODEL.md section 5; equals (18)). Never allocates.
/// \param object_inertia 6x6 SPD object inertia M_o in {w} (diag(m_o I3, J_o) for a body at its
///        centre of mass).
/// \param ee_inertia 6 x 6N, the end-effector inertias M_i side by side (SPD each).
/// \param r 3 x N grasp offsets r_i in {w}.
/// \param omega_o object angular velocity in {w} (3).
/// \param h_sigma 6(N+1): [hSigma_o; hSigma_1; ...; hSigma_N] of (15)-(16).
/// \param accelerations_out 6(N+1): xdd = [xdd_o; xdd_1; ...] (written).
/// \param wrenches_out 6(N+1): h = [h_o; h_1; ...], the wrenches acting on each body (written).
template <typename DerivedObject, typename DerivedInertia, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma, typename DerivedAcceleration, typename DerivedWrench>
void solve_interaction_dynamics(const Eigen::MatrixBase<DerivedObject>& object_inertia,
                                const Eigen::MatrixBase<DerivedInertia>& ee_inertia,
                                const Eigen::MatrixBase<DerivedR>& r,
                                const Eigen::MatrixBase<DerivedOmega>& omega_o,
                                const Eigen::MatrixBase<DerivedSigma>& h_sigma,
                                const Eigen::MatrixBase<DerivedAcceleration>& accelerations_out,
                                const Eigen::MatrixBase<DerivedWrench>& wrenches_out) noexcept
{
    constexpr int arms = detail::kernel_arms<DerivedR, DerivedSigma>();
    static_assert(detail::sizes_agree(DerivedInertia::ColsAtCompileTime, times_six(arms)),
                  "ee_inertia must be 6 x 6N");
    COOPDYN_ASSERT(ee_inertia.rows() == 6 && ee_inertia.cols() == 6 * r.cols(), "ee_inertia must be 6 x 6N");
    COOPDYN_ASSERT(object_inertia.rows() == 6 && object_inertia.cols() == 6, "object_inertia must be 6x6");
    detail::solve_interaction(detail::GeneralObjectInertia<DerivedObject>{object_inertia},
                              detail::GeneralEndEffectorInertias<DerivedInertia>{ee_inertia}, r,
                              omega_o, h_sigma, accelerations_out, wrenches_out);
}

/// \brief Interaction wrenches h = [h_o; h_1; ...; h_N] (6(N+1)) of the rigid grasp for general
/// SPD inertias: the structured O(N) form of (18), MODEL.md section 5. Arguments as in
/// solve_interaction_dynamics. Does not allocate when the arguments are fixed-size.
template <typename DerivedObject, typename DerivedInertia, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma>
FullStackVector<typename DerivedSigma::Scalar, detail::kernel_arms<DerivedR, DerivedSigma>()>
interaction_wrenches(const Eigen::MatrixBase<DerivedObject>& object_inertia,
                     const Eigen::MatrixBase<DerivedInertia>& ee_inertia,
                     const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                     const Eigen::MatrixBase<DerivedSigma>& h_sigma)
{
    using Result =
        FullStackVector<typename DerivedSigma::Scalar, detail::kernel_arms<DerivedR, DerivedSigma>()>;
    Result accelerations = Result::Zero(h_sigma.size());
    Result wrenches = Result::Zero(h_sigma.size());
    solve_interaction_dynamics(object_inertia, ee_inertia, r, omega_o, h_sigma, accelerations, wrenches);
    return wrenches;
}

/// \brief Accelerations and interaction wrenches for block-diagonal inertias
/// M_o = diag(m_o I3, J_o), M_i = diag(m_i I3, J_i) (the impedance end-effector (1)), written into
/// caller-owned storage. Same result as solve_interaction_dynamics with those matrices, about
/// seven times faster (one 3x3 factorisation instead of a 6x6 one). Never allocates.
/// \param object_mass m_o > 0.
/// \param object_rotational_inertia J_o in {w}, 3x3 symmetric positive semi-definite.
/// \param ee_masses N masses m_i > 0.
/// \param ee_rotational_inertias 3 x 3N, the J_i side by side (SPD each).
/// Other parameters as in solve_interaction_dynamics.
template <typename DerivedObjectRotational, typename DerivedMasses, typename DerivedRotational,
          typename DerivedR, typename DerivedOmega, typename DerivedSigma,
          typename DerivedAcceleration, typename DerivedWrench>
void solve_interaction_dynamics_block_diagonal(
    const typename DerivedSigma::Scalar& object_mass,
    const Eigen::MatrixBase<DerivedObjectRotational>& object_rotational_inertia,
    const Eigen::MatrixBase<DerivedMasses>& ee_masses,
    const Eigen::MatrixBase<DerivedRotational>& ee_rotational_inertias,
    const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
    const Eigen::MatrixBase<DerivedSigma>& h_sigma,
    const Eigen::MatrixBase<DerivedAcceleration>& accelerations_out,
    const Eigen::MatrixBase<DerivedWrench>& wrenches_out) noexcept
{
    constexpr int arms = detail::kernel_arms<DerivedR, DerivedSigma>();
    static_assert(detail::sizes_agree(DerivedMasses::SizeAtCompileTime, arms),
                  "ee_masses must have N entries");
    static_assert(detail::sizes_agree(DerivedRotational::ColsAtCompileTime, times_three(arms)),
                  "ee_rotational_inertias must be 3 x 3N");
    COOPDYN_ASSERT(ee_masses.size() == r.cols(), "ee_masses must have N entries");
    COOPDYN_ASSERT(ee_rotational_inertias.cols() == 3 * r.cols(), "ee_rotational_inertias must be 3 x 3N");
    detail::solve_interaction(
        detail::BlockDiagonalObjectInertia<DerivedObjectRotational>{object_mass, object_rotational_inertia},
        detail::BlockDiagonalEndEffectorInertias<DerivedMasses, DerivedRotational>{ee_masses,
                                                                                 ee_rotational_inertias},
        r, omega_o, h_sigma, accelerations_out, wrenches_out);
}

/// \brief Interaction wrenches h (6(N+1)) for block-diagonal inertias; see
/// solve_interaction_dynamics_block_diagonal.
template <typename DerivedObjectRotational, typename DerivedMasses, typename DerivedRotational,
          typename DerivedR, typename DerivedOmega, typename DerivedSigma>
FullStackVector<typename DerivedSigma::Scalar, detail::kernel_arms<DerivedR, DerivedSigma>()>
interaction_wrenches_block_diagonal(const typename DerivedSigma::Scalar& object_mass,
                                    const Eigen::MatrixBase<DerivedObjectRotational>& object_rotational_inertia,
                                    const Eigen::MatrixBase<DerivedMasses>& ee_masses,
                                    const Eigen::MatrixBase<DerivedRotational>& ee_rotational_inertias,
                                    const Eigen::MatrixBase<DerivedR>& r,
                                    const Eigen::MatrixBase<DerivedOmega>& omega_o,
                                    const Eigen::MatrixBase<DerivedSigma>& h_sigma)
{
    using Result =
        FullStackVector<typename DerivedSigma::Scalar, detail::kernel_arms<DerivedR, DerivedSigma>()>;
    Result accelerations = Result::Zero(h_sigma.size());
    Result wrenches = Result::Zero(h_sigma.size());
    solve_interaction_dynamics_block_diagonal(object_mass, object_rotational_inertia, ee_masses,
                                              ee_rotational_inertias, r, omega_o, h_sigma,
                                              accelerations, wrenches);
    return wrenches;
}

}  // namespace coopdyn
