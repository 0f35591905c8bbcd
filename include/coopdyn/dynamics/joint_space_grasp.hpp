/// \file
/// \brief Joint-space rigid grasp: K serial arms, each welded at its palm to one rigid object,
/// solved by Gauss's principle (18)-(19) through the structured kernel of
/// interaction_wrenches.hpp (docs/dynamics.md, "Arms in joint space").
///
/// Arm i has n_i joints and the unconstrained dynamics M_i qdd_i = u_i (u_i = tau_i - c_i: the
/// joint torques less the Coriolis, centrifugal and gravity torques). Its palm moves with
/// xdd_i = J_i qdd_i + Jdot_i qdot_i; the weld holds the palm's point on the object's point r_i
/// and turns it with the object,
///
///     J_i qdd_i + Jdot_i qdot_i = G_i^T xdd_o + b_i + beta_i,     b_i = [S(w_o)^2 r_i; 0],
///
/// with G_i of (24) and beta_i an optional stabilisation term (Baumgarte's; zero for the ideal
/// weld). The object obeys M_o xdd_o = hSigma_o - sum_i G_i h_i, h_i the object's wrench on
/// palm i (so the arm feels J_i^T h_i). Since the arms share no joint (M and J block diagonal),
/// each arm reduces to its palm as one body of the first paper (Khatib's operational-space form):
///
///     X_i = M_i^-1 J_i^T,   qdd0_i = M_i^-1 u_i                     (n_i x 7, one factorisation)
///     Lambda_i = (J_i X_i)^-1,   a_i = J_i qdd0_i + Jdot_i qdot_i  (the palm's free acceleration)
///     Lambda_i xdd_i = Lambda_i a_i + h_i                          (the palm as a body, (15)-(16))
///
/// so the weld is the first paper's N + 1 bodies with M_i = Lambda_i and hSigma_i = Lambda_i a_i,
/// solved by interaction_wrenches in the object's reduced coordinates (structured (18)). beta_i
/// enters as hSigma_i - Lambda_i beta_i (the kernel then returns xdd_i - beta_i and the same h_i).
/// Back in joint space,
///
///     qdd_i = M_i^-1 (u_i + J_i^T h_i) = qdd0_i + X_i h_i.
///
/// This is exactly the minimiser of Gauss's function (19) over the joint and object coordinates
/// under the welds (the dense KKT system of the whole chain; tests/dynamics/test_joint_space_grasp.cpp).
/// Cost: per arm one n_i x n_i and one 6 x 6 factorisation; one 6 x 6 solve for the object.
///
/// Sizes: Arms (K) and Joints (every arm's n_i) fixed at compile time, or Eigen::Dynamic; with
/// Joints = Dynamic the arms may have different joint counts (given at construction). Storage is
/// allocated once, at construction: solve() never allocates, fixed or dynamic.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/numerics/fixed_ldlt.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"
#include "coopdyn/spatial/inertia.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <initializer_list>
#include <type_traits>
#include <vector>

namespace coopdyn {
namespace detail {

/// The factorisation of an arm's M_i: FixedLdlt (L D L^T, unrolled) for a compile-time size,
/// Eigen's LLT (allocated once, at construction) otherwise, behind one interface.
template <typename Scalar, int Joints> class JointInertiaFactor {
public:
    explicit JointInertiaFactor(Index) noexcept {}
    void resize(Index) noexcept {}
    template <typename Derived> COOPDYN_INLINE bool compute(const Eigen::MatrixBase<Derived>& inertia) noexcept
    {
        return factor_.compute(inertia);
    }
    template <typename Derived> COOPDYN_INLINE void solve_in_place(const Eigen::MatrixBase<Derived>& X) const noexcept
    {
        factor_.solve_in_place(X);
    }

private:
    FixedLdlt<Scalar, Joints> factor_;
};

template <typename Scalar> class JointInertiaFactor<Scalar, Eigen::Dynamic> {
public:
    explicit JointInertiaFactor(Index joints) : factor_(joints) { resize(joints); }
    /// Sized by factorising the identity: Eigen's LLT(Index) leaves info() unset, and copying the
    /// unset enum (as a std::vector of arms does) is undefined behaviour (UBSan reports it).
    void resize(Index joints)
    {
        factor_.compute(Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>::Identity(joints, joints));
    }
    template <typename Derived> bool compute(const Eigen::MatrixBase<Derived>& inertia) noexcept
    {
        factor_.compute(inertia);
        return factor_.info() == Eigen::Success;
    }
    template <typename Derived> void solve_in_place(const Eigen::MatrixBase<Derived>& X) const noexcept
    {
        factor_.solve_lower_in_place(X);
        factor_.solve_upper_in_place(X);
    }

private:
    DynamicLlt<Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>> factor_;
};

}  // namespace detail

/// \brief The joint-space rigid grasp of K arms welded to one object (file comment,
/// docs/dynamics.md): load each arm's terms with set_arm(), then solve(); read the object's
/// acceleration, the palms' wrenches h_i and the joint accelerations.
/// \tparam Arms K, or Eigen::Dynamic.
/// \tparam Joints every arm's joint count n_i, or Eigen::Dynamic (then each arm's own, given at
///         construction).
template <typename Scalar, int Arms = Eigen::Dynamic, int Joints = Eigen::Dynamic> class JointSpaceGrasp {
    static_assert(Arms == Eigen::Dynamic || Arms >= 1, "at least one arm");
    static_assert(Joints == Eigen::Dynamic || Joints >= 1, "at least one joint per arm");

public:
    static constexpr int stack_rows = Arms == Eigen::Dynamic ? Eigen::Dynamic : 6 * (Arms + 1);
    using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
    using Stack = Eigen::Matrix<Scalar, stack_rows, 1>;
    using JointVector = Eigen::Matrix<Scalar, Joints, 1>;

    /// Fixed K and n_i: nothing to size.
    JointSpaceGrasp()
    {
        static_assert(Arms != Eigen::Dynamic && Joints != Eigen::Dynamic,
                      "JointSpaceGrasp: give the arms' joint counts when K or n_i is dynamic");
        initialise(std::vector<Index>(static_cast<std::size_t>(Arms), Index(Joints)));
    }
    /// n_i per arm (K entries; each equal to Joints when it is fixed). Allocates all storage.
    explicit JointSpaceGrasp(const std::vector<Index>& joint_counts) { initialise(joint_counts); }
    JointSpaceGrasp(std::initializer_list<Index> joint_counts) { initialise(std::vector<Index>(joint_counts)); }

    Index arms() const noexcept { return static_cast<Index>(arms_.size()); }
    Index joints(Index arm) const noexcept { return arms_[static_cast<std::size_t>(arm)].joints; }
    /// sum_i n_i: the size of solve()'s joint accelerations.
    Index total_joints() const noexcept { return total_joints_; }

    /// Arm i's terms at the current state: M_i (n_i x n_i SPD, lower triangle read), J_i (6 x n_i,
    /// the palm's twist [v; w] in {w}), u_i = tau_i - c_i (n_i), Jdot_i qdot_i (6) and beta_i (6).
    /// Factorises M_i and keeps [J_i^T, u_i]; solve() solves M_i^-1 [J_i^T, u_i] for every arm in
    /// one stage (so that the arms' independent substitutions overlap, as the factorisations of
    /// consecutive set_arm calls do). Returns false when M_i is not positive definite (solve()
    /// must not be called then).
    template <typename DerivedM, typename DerivedJ, typename DerivedU, typename DerivedRate, typename DerivedBeta>
    COOPDYN_INLINE bool set_arm(Index arm, const Eigen::MatrixBase<DerivedM>& inertia, const Eigen::MatrixBase<DerivedJ>& jacobian,
                                const Eigen::MatrixBase<DerivedU>& free_torque,
                                const Eigen::MatrixBase<DerivedRate>& jacobian_rate_qdot,
                                const Eigen::MatrixBase<DerivedBeta>& stabilisation) noexcept
    {
        ArmWork& work = arms_[static_cast<std::size_t>(arm)];
        COOPDYN_ASSERT(inertia.rows() == work.joints && inertia.cols() == work.joints, "M_i must be n_i x n_i");
        COOPDYN_ASSERT(jacobian.rows() == 6 && jacobian.cols() == work.joints, "J_i must be 6 x n_i");
        COOPDYN_ASSERT(free_torque.size() == work.joints, "u_i must have n_i entries");
        if (!work.factor.compute(inertia)) {
            return false;
        }
        work.jacobian = jacobian;
        work.jacobian_rate_qdot = jacobian_rate_qdot;
        work.stabilisation = stabilisation;
        work.solution.template leftCols<6>() = jacobian.transpose();
        work.solution.col(free_column) = free_torque;
        work.solution.col(columns - 1).setZero();
        work.substituted = false;
        return true;
    }

    /// Solves the weld of the arms loaded by set_arm(): the object's inertia M_o (any type
    /// interaction_wrenches takes: CentralInertia, SpatialInertia, ArticulatedInertia, dense 6x6),
    /// the weld points r_i (3 x K, {w}, from the object's reference point), its angular velocity
    /// w_o and unconstrained wrench hSigma_o (6). Writes qdd (sum n_i, arm after arm). Returns false,
    /// writing nothing, when a palm's J_i M_i^-1 J_i^T is not safely positive definite (the arm is
    /// singular: the palm cannot move in every direction); a caller then falls back to a
    /// rank-robust form of (18) (udwadia_kalaba).
    template <typename ObjectInertia, typename DerivedR, typename DerivedOmega, typename DerivedSigma, typename DerivedQdd>
    bool solve(const ObjectInertia& object_inertia, const Eigen::MatrixBase<DerivedR>& r,
               const Eigen::MatrixBase<DerivedOmega>& omega_o, const Eigen::MatrixBase<DerivedSigma>& object_h_sigma,
               const Eigen::MatrixBase<DerivedQdd>& joint_accelerations_out) noexcept
    {
        using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;
        COOPDYN_ASSERT(r.rows() == 3 && r.cols() == arms(), "r must be 3 x K");
        auto& joint_accelerations = const_cast<Eigen::MatrixBase<DerivedQdd>&>(joint_accelerations_out);
        COOPDYN_ASSERT(joint_accelerations.size() == total_joints_, "qdd must have sum n_i entries");
        // Each stage runs over every arm before the next: the arms' serial chains (pivot after
        // pivot, substitution after substitution) are independent, so the processor overlaps them.
        for (ArmWork& work : arms_) {
            if (!work.substituted) {  // once per set_arm: solve() may be called again
                work.factor.solve_in_place(work.solution);  // [X_i, qdd0_i, 0]
                work.substituted = true;
            }
        }
        for (ArmWork& work : arms_) {
            // Lambda_i^-1 = J_i X_i, as n_i rank-one updates: each a multiply-add of whole columns
            // (Eigen's lazy product at this size goes element by element).
            Matrix6 mobility = work.jacobian.col(0) * work.solution.row(0).template head<6>();
            for (Index k = 1; k < work.joints; ++k) {
                mobility.noalias() += work.jacobian.col(k) * work.solution.row(k).template head<6>();
            }
            // The library's pivot policy (numerics/pivot_policy.hpp): a palm that cannot move in
            // every direction is a singular arm.
            if (!work.mobility_factor.compute(mobility) ||
                !regular_pivots(work.mobility_factor.pivots(), mobility.diagonal().maxCoeff())) {
                return false;
            }
            work.palm.template leftCols<6>().setIdentity();
            // a_i - beta_i = J_i qdd0_i + Jdot_i qdot_i - beta_i
            work.palm.col(free_column) =
                work.jacobian * work.solution.col(free_column) + work.jacobian_rate_qdot - work.stabilisation;
            work.palm.col(columns - 1).setZero();
        }
        h_sigma_.template head<6>() = object_h_sigma;
        for (std::size_t i = 0; i < arms_.size(); ++i) {
            ArmWork& work = arms_[i];
            work.mobility_factor.solve_in_place(work.palm);  // [Lambda_i, Lambda_i (a_i - beta_i), 0]
            palm_inertia_[i] = ArticulatedInertia<Scalar>(work.palm.template leftCols<6>());
            h_sigma_.template segment<6>(6 + 6 * static_cast<Index>(i)) = work.palm.col(free_column);
        }
        interaction_wrenches(object_inertia, palm_inertia_, r, omega_o, h_sigma_, accelerations_, wrenches_);
        Index joint = 0;
        for (std::size_t i = 0; i < arms_.size(); ++i) {
            const ArmWork& work = arms_[i];
            // qdd_i = M_i^-1 (u_i + J_i^T h_i) = qdd0_i + X_i h_i
            const auto h_i = wrenches_.template segment<6>(6 + 6 * static_cast<Index>(i));
            if constexpr (Joints == Eigen::Dynamic) {
                // In two statements: Eigen evaluates a sum's dynamic-size product into a heap temporary.
                auto qdd_i = joint_accelerations.segment(joint, work.joints);
                qdd_i = work.solution.col(free_column);
                qdd_i.noalias() += work.solution.template leftCols<6>() * h_i;
            } else {
                joint_accelerations.template segment<Joints>(joint) =
                    work.solution.col(free_column) + work.solution.template leftCols<6>() * h_i;
            }
            joint += work.joints;
        }
        return true;
    }

    /// xdd_o = [a; alpha] of the object's reference point, {w}, of the last solve().
    auto object_acceleration() const noexcept { return accelerations_.template head<6>(); }
    /// h_o = M_o xdd_o - hSigma_o: the wrench the palms apply to the object, about its reference point.
    auto object_wrench() const noexcept { return wrenches_.template head<6>(); }
    /// h_i: the object's wrench on palm i, about the palm's point, {w} (the arm feels J_i^T h_i;
    /// the palm's wrench on the object is -h_i).
    auto palm_wrench(Index arm) const noexcept { return wrenches_.template segment<6>(6 + 6 * arm); }
    /// xdd_i - beta_i: palm i's acceleration [a_i; alpha_i] less the stabilisation term.
    auto palm_acceleration(Index arm) const noexcept { return accelerations_.template segment<6>(6 + 6 * arm); }

private:
    // The right-hand sides side by side, row-major: FixedLdlt::solve_in_place then updates a
    // whole row per step, vectorised across them. One padding column: whole rows of 8 fill the
    // vector registers.
    static constexpr int columns = 8;
    static constexpr int free_column = 6;

    struct ArmWork {
        ArmWork() : ArmWork(Joints == Eigen::Dynamic ? 0 : Joints) {}
        explicit ArmWork(Index n) : joints(n), factor(n), jacobian(6, n), solution(n, columns) {}
        void resize(Index n)
        {
            joints = n;
            factor.resize(n);
            jacobian.resize(6, n);
            solution.resize(n, columns);
        }
        Index joints;
        detail::JointInertiaFactor<Scalar, Joints> factor;
        Eigen::Matrix<Scalar, 6, Joints> jacobian;                                   // J_i
        Eigen::Matrix<Scalar, Joints, columns, Eigen::RowMajor> solution;            // [X_i, qdd0_i, 0]
        FixedLdlt<Scalar, 6> mobility_factor;                               // Lambda_i^-1
        Eigen::Matrix<Scalar, 6, columns, Eigen::RowMajor> palm;                     // [Lambda_i, hSigma_i - Lambda_i beta_i, 0]
        Vector6 jacobian_rate_qdot;                                                  // Jdot_i qdot_i
        Vector6 stabilisation;                                                       // beta_i
        bool substituted = false;  // solution holds M_i^-1 [J_i^T, u_i] (solve() did it since set_arm)
    };

    template <typename T>
    using Storage = std::conditional_t<Arms == Eigen::Dynamic, std::vector<T>, std::array<T, static_cast<std::size_t>(Arms == Eigen::Dynamic ? 1 : Arms)>>;

    void initialise(const std::vector<Index>& joint_counts)
    {
        COOPDYN_ASSERT(Arms == Eigen::Dynamic || static_cast<Index>(joint_counts.size()) == Arms,
                       "one joint count per arm");
        COOPDYN_ASSERT(!joint_counts.empty(), "at least one arm");
        const auto count = joint_counts.size();
        if constexpr (Arms == Eigen::Dynamic) {
            arms_.reserve(count);
            palm_inertia_.resize(count);
        }
        for (std::size_t i = 0; i < count; ++i) {
            const Index n = joint_counts[i];
            COOPDYN_ASSERT(n >= 1 && (Joints == Eigen::Dynamic || n == Joints), "n_i must be positive (and Joints when fixed)");
            if constexpr (Arms == Eigen::Dynamic) {
                arms_.emplace_back(n);
            } else {
                arms_[i].resize(n);
            }
            total_joints_ += n;
        }
        const Index rows = 6 * (static_cast<Index>(count) + 1);
        h_sigma_.setZero(rows);
        accelerations_.setZero(rows);
        wrenches_.setZero(rows);
    }

    Storage<ArmWork> arms_{};  // a std::vector (dynamic K) is sized at construction only
    Storage<ArticulatedInertia<Scalar>> palm_inertia_{};
    Stack h_sigma_, accelerations_, wrenches_;
    Index total_joints_ = 0;
};

}  // namespace coopdyn
