/// \file
/// \brief Structured O(N) interaction wrench of the rigid grasp (docs/dynamics.md): the
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

/// A twist-like or wrench-like 6-vector held as two 3-vectors.
///
/// Why not Vector6: the per-arm arithmetic is 3-vector algebra (cross products, 3x3 blocks). On a
/// Vector6, Eigen stores with 2- or 4-wide packets and the 3-vector halves are then reloaded with
/// loads that straddle those stores, which defeats store-to-load forwarding; measured, the N = 2
/// solve ran about 4x slower than with separate 3-vectors.
template <typename Scalar> struct SpatialPair {
    Vector3<Scalar> linear;
    Vector3<Scalar> angular;

    template <typename Derived> static SpatialPair from(const Eigen::MatrixBase<Derived>& six) noexcept
    {
        return SpatialPair{six.template head<3>(), six.template tail<3>()};
    }
    template <typename Derived> void write_to(const Eigen::MatrixBase<Derived>& six_out) const noexcept
    {
        auto& six = const_cast<Eigen::MatrixBase<Derived>&>(six_out);
        six.template head<3>() = linear;
        six.template tail<3>() = angular;
    }
};

/// y = X x for a general 6x6 X, block by block.
template <typename Derived, typename Scalar>
SpatialPair<Scalar> apply_blocks(const Eigen::MatrixBase<Derived>& matrix, const SpatialPair<Scalar>& x) noexcept
{
    return SpatialPair<Scalar>{
        matrix.template topLeftCorner<3, 3>() * x.linear + matrix.template topRightCorner<3, 3>() * x.angular,
        matrix.template bottomLeftCorner<3, 3>() * x.linear + matrix.template bottomRightCorner<3, 3>() * x.angular};
}

/// Ma = M_o + sum G_i M_i G_i^T, symmetric; only its lower triangle is kept up to date, which is
/// all the factorisation reads.
template <typename Scalar> struct GeneralCompositeInertia {
    Matrix6<Scalar> matrix;

    /// Solve Ma xdd_o = rhs.
    SpatialPair<Scalar> solve(const SpatialPair<Scalar>& rhs) const noexcept
    {
        FixedCholesky<Scalar, 6> factor;
        const bool positive_definite = factor.compute(matrix);
        COOPDYN_ASSERT(positive_definite, "composite inertia Ma must be positive definite");
        (void)positive_definite;
        Vector6<Scalar> stacked;
        stacked << rhs.linear, rhs.angular;
        return SpatialPair<Scalar>::from(factor.solve(stacked));
    }
};

/// Lower triangle of J += m S(a) S(a)^T = m (|a|^2 I3 - a a^T), the parallel-axis term, entry by
/// entry (the upper triangle is never read).
template <typename Scalar>
void add_parallel_axis_lower(Matrix3<Scalar>& inertia, const Scalar& mass, const Vector3<Scalar>& a) noexcept
{
    const Scalar xx = a(0) * a(0);
    const Scalar yy = a(1) * a(1);
    const Scalar zz = a(2) * a(2);
    inertia(0, 0) += mass * (yy + zz);
    inertia(1, 1) += mass * (xx + zz);
    inertia(2, 2) += mass * (xx + yy);
    inertia(1, 0) -= mass * a(1) * a(0);
    inertia(2, 0) -= mass * a(2) * a(0);
    inertia(2, 1) -= mass * a(2) * a(1);
}

/// Lower triangle of `target` += `source`.
template <typename Scalar, typename Derived>
void add_lower(Matrix3<Scalar>& target, const Eigen::MatrixBase<Derived>& source) noexcept
{
    target(0, 0) += source(0, 0);
    target(1, 0) += source(1, 0);
    target(2, 0) += source(2, 0);
    target(1, 1) += source(1, 1);
    target(2, 1) += source(2, 1);
    target(2, 2) += source(2, 2);
}

/// Solve A x = b for a symmetric positive definite 3x3 A given by its lower triangle, by the
/// adjugate (Cramer's rule): x = adj(A) b / det(A).
///
/// Why not a Cholesky factorisation: at 3x3 the factorisation is a serial chain of three
/// divisions (each pivot waits for the previous column), while the six cofactors are independent
/// and need a single division; on the 1 kHz path this halves the latency of the block-diagonal
/// solve. For an SPD matrix the cofactor expansion is as accurate as the factorisation to within
/// a small constant (error ~ cond(A) eps), and positive definiteness is checked for free with
/// Sylvester's criterion on the leading minors the cofactors already contain.
template <typename Scalar> struct SymmetricEntries3 {
    Scalar a00, a10, a20, a11, a21, a22;  // lower triangle, column by column
};

template <typename Scalar>
Vector3<Scalar> solve_symmetric_3x3_closed_form(const SymmetricEntries3<Scalar>& matrix,
                                                const Vector3<Scalar>& rhs) noexcept
{
    const auto& [a00, a10, a20, a11, a21, a22] = matrix;
    // Cofactors of the symmetric matrix (the adjugate is symmetric too).
    const Scalar c00 = a11 * a22 - a21 * a21;
    const Scalar c10 = a20 * a21 - a10 * a22;
    const Scalar c20 = a10 * a21 - a20 * a11;
    const Scalar c11 = a00 * a22 - a20 * a20;
    const Scalar c21 = a10 * a20 - a00 * a21;
    const Scalar c22 = a00 * a11 - a10 * a10;
    const Scalar determinant = a00 * c00 + a10 * c10 + a20 * c20;
    COOPDYN_ASSERT(a00 > Scalar(0) && c22 > Scalar(0) && determinant > Scalar(0),
                   "composite rotational inertia must be positive definite");
    const Scalar inverse_determinant = Scalar(1) / determinant;
    return Vector3<Scalar>((c00 * rhs(0) + c10 * rhs(1) + c20 * rhs(2)) * inverse_determinant,
                           (c10 * rhs(0) + c11 * rhs(1) + c21 * rhs(2)) * inverse_determinant,
                           (c20 * rhs(0) + c21 * rhs(1) + c22 * rhs(2)) * inverse_determinant);
}

/// Ma for block-diagonal inertias: [[m I3, S(s)^T], [S(s), J]], with total mass m, first moment
/// s = sum m_i r_i and rotational block J = J_o + sum (J_i + m_i S(r_i) S(r_i)^T); only J's lower
/// triangle is kept up to date.
template <typename Scalar> struct BlockDiagonalCompositeInertia {
    Scalar mass;
    Vector3<Scalar> first_moment;
    Matrix3<Scalar> rotational;

    /// Solve Ma [a; alpha] = [f; t] by eliminating the translational block: with the composite
    /// centre of mass c = s / m, (J - m S(c) S(c)^T) alpha = t - c x f and a = f / m + c x alpha.
    SpatialPair<Scalar> solve(const SpatialPair<Scalar>& rhs) const noexcept
    {
        const Scalar inverse_mass = Scalar(1) / mass;
        const Vector3<Scalar> centre = inverse_mass * first_moment;
        // Lower triangle of J - m S(c) S(c)^T = J - m (|c|^2 I3 - c c^T), entry by entry: copying
        // the whole 3x3 after entry-wise updates would defeat store-to-load forwarding.
        const Scalar xx = centre(0) * centre(0), yy = centre(1) * centre(1), zz = centre(2) * centre(2);
        const SymmetricEntries3<Scalar> schur{rotational(0, 0) - mass * (yy + zz),
                                              rotational(1, 0) + mass * centre(1) * centre(0),
                                              rotational(2, 0) + mass * centre(2) * centre(0),
                                              rotational(1, 1) - mass * (xx + zz),
                                              rotational(2, 1) + mass * centre(2) * centre(1),
                                              rotational(2, 2) - mass * (xx + yy)};
        const Vector3<Scalar> angular =
            solve_symmetric_3x3_closed_form(schur, Vector3<Scalar>(rhs.angular - centre.cross(rhs.linear)));
        return SpatialPair<Scalar>{inverse_mass * rhs.linear + centre.cross(angular), angular};
    }
};

/// Object inertia given as a general 6x6 matrix.
template <typename Derived> struct GeneralObjectInertia {
    using Scalar = typename Derived::Scalar;
    const Eigen::MatrixBase<Derived>& matrix;

    void initialise(GeneralCompositeInertia<Scalar>& composite) const noexcept { composite.matrix = matrix; }
    SpatialPair<Scalar> apply(const SpatialPair<Scalar>& acceleration) const noexcept
    {
        return apply_blocks(matrix, acceleration);
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
    SpatialPair<Scalar> apply(const SpatialPair<Scalar>& acceleration) const noexcept
    {
        return SpatialPair<Scalar>{mass * acceleration.linear, rotational * acceleration.angular};
    }
};

/// No object: the arms alone, constrained to one rigid motion (the reduced system of (53)).
template <typename Scalar> struct NoObject {
    void initialise(GeneralCompositeInertia<Scalar>& composite) const noexcept { composite.matrix.setZero(); }
    void initialise(BlockDiagonalCompositeInertia<Scalar>& composite) const noexcept
    {
        composite.mass = Scalar(0);
        composite.first_moment.setZero();
        composite.rotational.setZero();
    }
    SpatialPair<Scalar> apply(const SpatialPair<Scalar>&) const noexcept
    {
        return SpatialPair<Scalar>{Vector3<Scalar>::Zero(), Vector3<Scalar>::Zero()};
    }
};

/// End-effector inertias M_i as general SPD 6x6 blocks of a 6 x 6N stack.
template <typename Derived> struct GeneralEndEffectorInertias {
    using Scalar = typename Derived::Scalar;
    using Composite = GeneralCompositeInertia<Scalar>;
    const Eigen::MatrixBase<Derived>& stack;

    /// Ma += G_i M_i G_i^T (lower triangle). With M_i = [[A, B], [B^T, C]] and S = S(r_i):
    /// G_i M_i G_i^T = [[A, (S A)^T + B], [S A + B^T, S A S^T + S B + (S B)^T + C]].
    void add_to_composite(Index arm, const Vector3<Scalar>& r_i, Composite& composite) const noexcept
    {
        const auto inertia = stack.template block<6, 6>(0, 6 * arm);
        const Matrix3<Scalar> s = skew(r_i);
        const Matrix3<Scalar> s_a = s * inertia.template topLeftCorner<3, 3>();
        const Matrix3<Scalar> s_b = s * inertia.template topRightCorner<3, 3>();
        composite.matrix.template topLeftCorner<3, 3>() += inertia.template topLeftCorner<3, 3>();
        composite.matrix.template bottomLeftCorner<3, 3>() += s_a + inertia.template bottomLeftCorner<3, 3>();
        composite.matrix.template bottomRightCorner<3, 3>() +=
            s_a * s.transpose() + s_b + s_b.transpose() + inertia.template bottomRightCorner<3, 3>();
    }
    SpatialPair<Scalar> apply(Index arm, const SpatialPair<Scalar>& acceleration) const noexcept
    {
        return apply_blocks(stack.template block<6, 6>(0, 6 * arm), acceleration);
    }
    /// wrench -= M_i [a; 0].
    void subtract_linear(Index arm, const Vector3<Scalar>& acceleration, SpatialPair<Scalar>& wrench) const noexcept
    {
        wrench.linear -= stack.template block<3, 3>(0, 6 * arm) * acceleration;
        wrench.angular -= stack.template block<3, 3>(3, 6 * arm) * acceleration;
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
        add_lower(composite.rotational, rotational.template block<3, 3>(0, 3 * arm));
        add_parallel_axis_lower(composite.rotational, mass, r_i);
    }
    SpatialPair<Scalar> apply(Index arm, const SpatialPair<Scalar>& acceleration) const noexcept
    {
        return SpatialPair<Scalar>{masses(arm) * acceleration.linear,
                                   rotational.template block<3, 3>(0, 3 * arm) * acceleration.angular};
    }
    /// wrench -= M_i [a; 0] = [m_i a; 0].
    void subtract_linear(Index arm, const Vector3<Scalar>& acceleration, SpatialPair<Scalar>& wrench) const noexcept
    {
        wrench.linear -= masses(arm) * acceleration;
    }
};

/// The structured solve shared by every inertia structure (docs/dynamics.md). Writes the arms'
/// accelerations and wrenches (6N each) and returns the object's acceleration; the object's wrench
/// goes to `object_wrench`.
template <typename ObjectInertia, typename EndEffectorInertias, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma, typename DerivedAcceleration, typename DerivedWrench>
SpatialPair<typename DerivedSigma::Scalar>
solve_interaction(const ObjectInertia& object, const EndEffectorInertias& end_effectors,
                  const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                  const SpatialPair<typename DerivedSigma::Scalar>& object_h_sigma,
                  const Eigen::MatrixBase<DerivedSigma>& arm_h_sigma,
                  const Eigen::MatrixBase<DerivedAcceleration>& arm_accelerations_out,
                  const Eigen::MatrixBase<DerivedWrench>& arm_wrenches_out,
                  SpatialPair<typename DerivedSigma::Scalar>& object_wrench) noexcept
{
    using Scalar = typename DerivedSigma::Scalar;
    using Pair = SpatialPair<Scalar>;
    // Eigen's documented idiom for writable expression arguments (blocks, maps, matrices).
    auto& arm_accelerations = const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(arm_accelerations_out);
    auto& arm_wrenches = const_cast<Eigen::MatrixBase<DerivedWrench>&>(arm_wrenches_out);
    const Index arms = r.cols();
    COOPDYN_ASSERT(arms >= 1, "at least one arm");
    COOPDYN_ASSERT(arm_h_sigma.size() == 6 * arms, "h_sigma must have 6(N+1) entries");
    COOPDYN_ASSERT(arm_accelerations.size() == 6 * arms, "accelerations must have 6(N+1) entries");
    COOPDYN_ASSERT(arm_wrenches.size() == 6 * arms, "wrenches must have 6(N+1) entries");

    const Vector3<Scalar> omega = omega_o;
    typename EndEffectorInertias::Composite composite;
    object.initialise(composite);
    Pair rhs = object_h_sigma;
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> r_i = r.col(i).template head<3>();
        end_effectors.add_to_composite(i, r_i, composite);
        // G_i (hSigma_i - M_i b_i)
        Pair reduced = Pair::from(arm_h_sigma.template segment<6>(6 * i));
        end_effectors.subtract_linear(i, centripetal_acceleration(r_i, omega), reduced);
        rhs.linear += reduced.linear;
        rhs.angular += r_i.cross(reduced.linear) + reduced.angular;
    }

    const Pair object_acceleration = composite.solve(rhs);
    const Pair object_inertial = object.apply(object_acceleration);
    object_wrench = Pair{object_inertial.linear - object_h_sigma.linear, object_inertial.angular - object_h_sigma.angular};
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> r_i = r.col(i).template head<3>();
        // xdd_i = G_i^T xdd_o + b_i, h_i = M_i xdd_i - hSigma_i
        const Pair acceleration{object_acceleration.linear + object_acceleration.angular.cross(r_i) +
                                    centripetal_acceleration(r_i, omega),
                                object_acceleration.angular};
        acceleration.write_to(arm_accelerations.template segment<6>(6 * i));
        const Pair inertial = end_effectors.apply(i, acceleration);
        const Pair sigma = Pair::from(arm_h_sigma.template segment<6>(6 * i));
        Pair{inertial.linear - sigma.linear, inertial.angular - sigma.angular}.write_to(
            arm_wrenches.template segment<6>(6 * i));
    }
    return object_acceleration;
}

/// The end-effector part (last 6N entries) of a 6(N+1) stack, fixed-size when N is.
template <int Arms, typename Stack> auto arm_part(Stack& stack) noexcept
{
    if constexpr (Arms == Eigen::Dynamic) {
        return stack.tail(stack.size() - 6);
    } else {
        return stack.template tail<6 * Arms>();
    }
}

/// The full-stack form used by the public kernels: [object; arms] in and out.
template <int Arms, typename ObjectInertia, typename EndEffectorInertias, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma, typename DerivedAcceleration, typename DerivedWrench>
void solve_interaction_stacked(const ObjectInertia& object, const EndEffectorInertias& end_effectors,
                               const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                               const Eigen::MatrixBase<DerivedSigma>& h_sigma,
                               const Eigen::MatrixBase<DerivedAcceleration>& accelerations_out,
                               const Eigen::MatrixBase<DerivedWrench>& wrenches_out) noexcept
{
    using Scalar = typename DerivedSigma::Scalar;
    COOPDYN_ASSERT(h_sigma.size() == 6 * (r.cols() + 1), "h_sigma must have 6(N+1) entries");
    COOPDYN_ASSERT(accelerations_out.size() == 6 * (r.cols() + 1), "accelerations must have 6(N+1) entries");
    COOPDYN_ASSERT(wrenches_out.size() == 6 * (r.cols() + 1), "wrenches must have 6(N+1) entries");
    auto& accelerations = const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(accelerations_out);
    auto& wrenches = const_cast<Eigen::MatrixBase<DerivedWrench>&>(wrenches_out);
    SpatialPair<Scalar> object_wrench;
    const SpatialPair<Scalar> object_acceleration = solve_interaction(
        object, end_effectors, r, omega_o, SpatialPair<Scalar>::from(h_sigma.template head<6>()),
        arm_part<Arms>(h_sigma), arm_part<Arms>(accelerations), arm_part<Arms>(wrenches), object_wrench);
    object_acceleration.write_to(accelerations.template head<6>());
    object_wrench.write_to(wrenches.template head<6>());
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
/// written into caller-owned storage (docs/dynamics.md; equals (18)). Never allocates.
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
    detail::solve_interaction_stacked<arms>(detail::GeneralObjectInertia<DerivedObject>{object_inertia},
                                            detail::GeneralEndEffectorInertias<DerivedInertia>{ee_inertia}, r,
                                            omega_o, h_sigma, accelerations_out, wrenches_out);
}

/// \brief Interaction wrenches h = [h_o; h_1; ...; h_N] (6(N+1)) of the rigid grasp for general
/// SPD inertias: the structured O(N) form of (18), docs/dynamics.md. Arguments as in
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
    detail::solve_interaction_stacked<arms>(
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
