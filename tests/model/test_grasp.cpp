// Tests of coopdyn/model/grasp.hpp (docs/model.md, paper (10)-(14), (23)-(24)), with the grasp
// operators applied per contact (G w, G^T y, Gdot v, Gdot^T y, G G^T) against the dense grasp
// matrix and a central difference of it.
//
// Reference: exact rigid-body motion of an object, p_i(t) = p_o(t) + R(t) r_i_body, differentiated
// numerically (fourth-order central stencils). The grasp matrix is checked through the power
// balance with the (numerically verified) twist map, the constraint matrix against its
// block definition (14) entry by entry.

#include "coopdyn/model/grasp.hpp"
#include "coopdyn/model/grasp_inverse.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

namespace {

/// Scientific notation for recorded measurements.
std::string scientific(double value)
{
    std::ostringstream stream;
    stream << std::scientific << std::setprecision(2) << value;
    return stream.str();
}

using Matrix3d = Eigen::Matrix3d;
using Vector3d = Eigen::Vector3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Eigen::Dynamic;
using coopdyn_test::gaussian_quaternion;
using coopdyn_test::random_vector;
using coopdyn_test::random_vector6;
using coopdyn_test::vee_skew_part;

// --- Compile-time dimensions -----------------------------------------------------------------

using R2 = Eigen::Matrix<double, 3, 2>;
using R3 = Eigen::Matrix<double, 3, 3>;
using RX = Eigen::Matrix<double, 3, Dynamic>;
using RXX = Eigen::MatrixXd;

static_assert(std::is_same_v<decltype(coopdyn::grasp_matrix(std::declval<R2>())), Eigen::Matrix<double, 6, 12>>,
              "G is 6 x 6N");
static_assert(std::is_same_v<decltype(coopdyn::constraint_matrix(std::declval<R2>())),
                             Eigen::Matrix<double, 12, 18>>,
              "A is 6N x 6(N+1)");
static_assert(std::is_same_v<decltype(coopdyn::constraint_bias(std::declval<R2>(), std::declval<Vector3d>())),
                             Eigen::Matrix<double, 12, 1>>,
              "b has 6N entries");
static_assert(std::is_same_v<decltype(coopdyn::grasp_matrix(std::declval<R3>())), Eigen::Matrix<double, 6, 18>>,
              "G is 6 x 6N");
static_assert(std::is_same_v<decltype(coopdyn::constraint_matrix(std::declval<R3>())),
                             Eigen::Matrix<double, 18, 24>>,
              "A is 6N x 6(N+1)");
static_assert(std::is_same_v<decltype(coopdyn::grasp_matrix(std::declval<RX>())),
                             Eigen::Matrix<double, 6, Dynamic>>,
              "dynamic N stays dynamic");
static_assert(std::is_same_v<decltype(coopdyn::constraint_matrix(std::declval<RX>())),
                             Eigen::Matrix<double, Dynamic, Dynamic>>,
              "dynamic N stays dynamic");
static_assert(std::is_same_v<decltype(coopdyn::constraint_bias(std::declval<RX>(), std::declval<Vector3d>())),
                             Eigen::Matrix<double, Dynamic, 1>>,
              "dynamic N stays dynamic");
static_assert(std::is_same_v<decltype(coopdyn::grasp_matrix(std::declval<RXX>())),
                             Eigen::Matrix<double, 6, Dynamic>>,
              "fully dynamic r");
// A fixed-size block of a larger matrix fixes N.
static_assert(std::is_same_v<decltype(coopdyn::grasp_matrix(std::declval<R3>().leftCols<2>())),
                             Eigen::Matrix<double, 6, 12>>,
              "block expression with 2 columns");
static_assert(std::is_same_v<decltype(coopdyn::grasp_map_wrench(std::declval<Vector3d>(), std::declval<Vector6d>())),
                             Vector6d>,
              "per-arm maps return 6-vectors");
static_assert(std::is_same_v<decltype(coopdyn::centripetal_acceleration(std::declval<Vector3d>(),
                                                                        std::declval<Vector3d>())),
                             Vector3d>,
              "centripetal acceleration is a 3-vector");

// --- Helpers ---------------------------------------------------------------------------------

// random_vector(rng, scale), random_vector6, gaussian_quaternion and vee_skew_part:
// sample_systems.hpp.

/// Rotation matrix exp(S(phi)) from Eigen::AngleAxis.
Matrix3d exact_exp(const Vector3d& phi)
{
    const double angle = phi.norm();
    return angle == 0.0 ? Matrix3d::Identity() : Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

/// Fourth-order central first and second derivatives at t = 0.
template <typename T> T first_derivative(const std::function<T(double)>& f, double h)
{
    return (-f(2 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2 * h)) / (12.0 * h);
}
template <typename T> T second_derivative(const std::function<T(double)>& f, double h)
{
    return (-f(2 * h) + 16.0 * f(h) - 30.0 * f(0.0) + 16.0 * f(-h) - f(-2 * h)) / (12.0 * h * h);
}

/// An object in rigid motion with, at t = 0, velocity v0, acceleration a0, angular velocity w0
/// and angular acceleration alpha (all world frame):
/// p_o(t) = p0 + v0 t + a0 t^2 / 2, R(t) = exp(S(w0 t + alpha t^2 / 2)) R0.
/// (d/dt of R R^T gives w(0) = w0 and wdot(0) = alpha exactly; checked numerically below.)
struct RigidMotion {
    Vector3d p0, v0, a0, w0, alpha;
    Matrix3d R0;

    Vector3d position(double t) const { return p0 + v0 * t + 0.5 * a0 * t * t; }
    Matrix3d rotation(double t) const { return exact_exp(w0 * t + 0.5 * alpha * t * t) * R0; }
};

RigidMotion random_motion(std::mt19937& rng)
{
    return RigidMotion{random_vector(rng), random_vector(rng, 2.0), random_vector(rng, 3.0),
                       random_vector(rng, 2.0), random_vector(rng, 4.0),
                       gaussian_quaternion(rng).toRotationMatrix()};
}

/// Numerically differentiated kinematics of a frame attached to the object at body offset
/// r_body with body-fixed relative rotation R_rel: twist and acceleration at t = 0.
struct FrameDerivatives {
    Vector6d twist;
    Vector6d acceleration;
};

FrameDerivatives differentiate_frame(const RigidMotion& motion, const Vector3d& r_body, const Matrix3d& R_rel)
{
    const double h = 1e-3;
    const std::function<Vector3d(double)> point = [&](double t) -> Vector3d {
        return motion.position(t) + motion.rotation(t) * r_body;
    };
    const std::function<Matrix3d(double)> frame = [&](double t) -> Matrix3d {
        return motion.rotation(t) * R_rel;
    };
    const Matrix3d R = frame(0.0);
    const Matrix3d Rdot = first_derivative(frame, h);
    const Matrix3d Rddot = second_derivative(frame, h);
    FrameDerivatives result;
    result.twist << first_derivative(point, h), vee_skew_part(Rdot * R.transpose());
    // w = vee(Rdot R^T), wdot = vee(Rddot R^T + Rdot Rdot^T) = vee(Rddot R^T) (the second term is
    // symmetric).
    result.acceleration << second_derivative(point, h), vee_skew_part(Rddot * R.transpose());
    return result;
}

template <typename DerivedR> Eigen::VectorXd stack_object_first(const Vector6d& object, const DerivedR& rest)
{
    Eigen::VectorXd result(6 + rest.size());
    result << object, rest;
    return result;
}

// --- Kinematics against finite differences of the rigid motion (10)-(13) ---------------------

TEST(GraspKinematics, ConstraintReproducesTrueGraspPointAccelerations)
{
    std::mt19937 rng(41001);
    constexpr int arms = 3;
    double worst_constraint = 0.0;
    double worst_twist = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
        const RigidMotion motion = random_motion(rng);
        Eigen::Matrix<double, 3, arms> r_body;
        for (int i = 0; i < arms; ++i) {
            r_body.col(i) = random_vector(rng, 0.8);
        }
        const Eigen::Matrix<double, 3, arms> r = motion.R0 * r_body;  // world-frame offsets at t = 0
        Vector6d object_twist;
        object_twist << motion.v0, motion.w0;
        Vector6d object_acceleration;
        object_acceleration << motion.a0, motion.alpha;

        // Sanity of the reference itself: the object's own frame has w0 and alpha.
        const FrameDerivatives object_frame = differentiate_frame(motion, Vector3d::Zero(), Matrix3d::Identity());
        ASSERT_LT((object_frame.twist - object_twist).norm(), 1e-9);
        ASSERT_LT((object_frame.acceleration - object_acceleration).norm(), 1e-7);

        Eigen::Matrix<double, 6 * arms, 1> true_twists;
        Eigen::Matrix<double, 6 * arms, 1> true_accelerations;
        for (int i = 0; i < arms; ++i) {
            const FrameDerivatives frame =
                differentiate_frame(motion, r_body.col(i), gaussian_quaternion(rng).toRotationMatrix());
            true_twists.segment<6>(6 * i) = frame.twist;
            true_accelerations.segment<6>(6 * i) = frame.acceleration;
        }

        // (13): A xdd = b with the true accelerations.
        const auto A = coopdyn::constraint_matrix(r);
        const auto b = coopdyn::constraint_bias(r, motion.w0);
        Eigen::Matrix<double, 6 * (arms + 1), 1> xdd;
        xdd << object_acceleration, true_accelerations;
        const double residual = (A * xdd - b).norm() / std::max(1.0, b.norm());
        worst_constraint = std::max(worst_constraint, residual);
        EXPECT_LT(residual, 1e-7) << "trial " << trial;
        // The bias matters: without it, the residual is the centripetal term.
        EXPECT_GT((A * xdd).norm(), 1e-2) << "trial " << trial;

        // (10): twists of the grasp frames, per arm and via G^T.
        const auto G = coopdyn::grasp_matrix(r);
        const Eigen::Matrix<double, 6 * arms, 1> mapped = G.transpose() * object_twist;
        worst_twist = std::max(worst_twist, (mapped - true_twists).norm());
        EXPECT_LT((mapped - true_twists).norm(), 1e-9) << "trial " << trial;
        for (int i = 0; i < arms; ++i) {
            const Vector6d per_arm = coopdyn::grasp_map_twist(r.col(i), object_twist);
            EXPECT_LT((per_arm - true_twists.segment<6>(6 * i)).norm(), 1e-9);
            // (11)-(12): pdd_i = pdd_o + wd_o x r_i + w_o x (w_o x r_i), wd_i = wd_o.
            const Vector3d centripetal = coopdyn::centripetal_acceleration(r.col(i), motion.w0);
            const Vector3d tangential_free =
                true_accelerations.segment<3>(6 * i) - motion.a0 - motion.alpha.cross(r.col(i));
            EXPECT_LT((centripetal - tangential_free).norm(), 1e-7);
            EXPECT_LT((true_accelerations.segment<3>(6 * i + 3) - motion.alpha).norm(), 1e-7);
            // Equivalent per-arm form xdd_i = G_i^T xdd_o + b_i.
            Vector6d predicted = coopdyn::grasp_map_twist(r.col(i), object_acceleration);
            predicted.head<3>() += centripetal;
            EXPECT_LT((predicted - true_accelerations.segment<6>(6 * i)).norm(), 1e-7);
        }
    }
    RecordProperty("worst_constraint_residual", scientific(worst_constraint));
    RecordProperty("worst_twist_error", scientific(worst_twist));
}

TEST(GraspKinematics, ConstraintBiasIsCentripetalClosedForm)
{
    // Uniform rotation about z through the centre of mass: a point at distance rho from the axis
    // accelerates towards it with w^2 rho.
    const double w = 2.5;
    Eigen::Matrix<double, 3, 2> r;
    r.col(0) = Vector3d(0.4, 0.0, 0.3);
    r.col(1) = Vector3d(0.0, -0.2, -1.0);
    const auto b = coopdyn::constraint_bias(r, Vector3d(0.0, 0.0, w));
    EXPECT_LT((b.segment<3>(0) - Vector3d(-w * w * 0.4, 0.0, 0.0)).norm(), 1e-14);
    EXPECT_LT((b.segment<3>(6) - Vector3d(0.0, w * w * 0.2, 0.0)).norm(), 1e-14);
    EXPECT_EQ(b.segment<3>(3), Vector3d::Zero());
    EXPECT_EQ(b.segment<3>(9), Vector3d::Zero());
}

// --- Grasp matrix: power balance (23)-(24) ---------------------------------------------------

TEST(GraspMatrix, PowerBalanceWithTwistMap)
{
    std::mt19937 rng(41002);
    for (int arms = 1; arms <= 5; ++arms) {
        for (int trial = 0; trial < 10; ++trial) {
            Eigen::Matrix3Xd r(3, arms);
            for (int i = 0; i < arms; ++i) {
                r.col(i) = random_vector(rng);
            }
            Eigen::VectorXd hbar(6 * arms);
            for (int i = 0; i < arms; ++i) {
                hbar.segment<6>(6 * i) = random_vector6(rng, 10.0);
            }
            const Vector6d object_twist = random_vector6(rng, 2.0);
            const auto G = coopdyn::grasp_matrix(r);
            ASSERT_EQ(G.rows(), 6);
            ASSERT_EQ(G.cols(), 6 * arms);

            // Power delivered at the grasp points equals power delivered to the object.
            Eigen::VectorXd grasp_twists(6 * arms);
            Vector6d summed_wrench = Vector6d::Zero();
            for (int i = 0; i < arms; ++i) {
                grasp_twists.segment<6>(6 * i) = coopdyn::grasp_map_twist(r.col(i), object_twist);
                summed_wrench += coopdyn::grasp_map_wrench(r.col(i), hbar.segment<6>(6 * i));
            }
            const double power_grasp = hbar.dot(grasp_twists);
            const double power_object = (G * hbar).dot(object_twist);
            EXPECT_NEAR(power_grasp, power_object, 1e-12 * std::max(1.0, std::abs(power_grasp)));
            EXPECT_LT((G.transpose() * object_twist - grasp_twists).norm(), 1e-13);
            EXPECT_LT((G * hbar - summed_wrench).norm(), 1e-12);
        }
    }
}

TEST(GraspMatrix, ForceAtGraspPointProducesMomentAboutCentreOfMass)
{
    // A pure force f applied at grasp point i: torque about the centre of mass r_i x f, written
    // out by components; a pure couple passes unchanged.
    const Vector3d r_i(0.3, -0.5, 0.2);
    const Vector3d f(1.0, 2.0, -4.0);
    Vector6d wrench;
    wrench << f, Vector3d::Zero();
    const Vector3d expected_torque(r_i.y() * f.z() - r_i.z() * f.y(), r_i.z() * f.x() - r_i.x() * f.z(),
                                   r_i.x() * f.y() - r_i.y() * f.x());
    const Vector6d mapped = coopdyn::grasp_map_wrench(r_i, wrench);
    EXPECT_EQ(mapped.head<3>(), f);
    EXPECT_LT((mapped.tail<3>() - expected_torque).norm(), 1e-15);
    Vector6d couple;
    couple << Vector3d::Zero(), Vector3d(0.1, 0.2, 0.3);
    EXPECT_EQ(coopdyn::grasp_map_wrench(r_i, couple), couple);
}

// --- Constraint matrix block structure (14) --------------------------------------------------

TEST(ConstraintMatrix, BlockStructure)
{
    std::mt19937 rng(41003);
    for (int arms = 1; arms <= 4; ++arms) {
        Eigen::Matrix3Xd r(3, arms);
        for (int i = 0; i < arms; ++i) {
            r.col(i) = random_vector(rng);
        }
        const Eigen::MatrixXd A = coopdyn::constraint_matrix(r);
        ASSERT_EQ(A.rows(), 6 * arms);
        ASSERT_EQ(A.cols(), 6 * (arms + 1));
        const Matrix3d I3 = Matrix3d::Identity();
        for (int i = 0; i < arms; ++i) {
            EXPECT_EQ(Matrix3d(A.block<3, 3>(6 * i, 0)), -I3);
            EXPECT_EQ(Matrix3d(A.block<3, 3>(6 * i + 3, 0)), Matrix3d::Zero());
            EXPECT_EQ(Matrix3d(A.block<3, 3>(6 * i + 3, 3)), -I3);
            // Upper-right object block is S(r_i): S(r_i) x = r_i x x for every x.
            for (int j = 0; j < 3; ++j) {
                const Vector3d e = Vector3d::Unit(j);
                EXPECT_LT((A.block<3, 3>(6 * i, 3) * e - r.col(i).cross(e)).norm(), 1e-15);
            }
            for (int k = 0; k < arms; ++k) {
                const Eigen::Matrix<double, 6, 6> block = A.block<6, 6>(6 * i, 6 * (k + 1));
                if (k == i) {
                    EXPECT_EQ(block, (Eigen::Matrix<double, 6, 6>::Identity()));
                } else {
                    EXPECT_EQ(block, (Eigen::Matrix<double, 6, 6>::Zero()));
                }
            }
        }
        // Object columns are -G^T.
        EXPECT_EQ(Eigen::MatrixXd(A.leftCols(6)), Eigen::MatrixXd(-coopdyn::grasp_matrix(r).transpose()));
        // Full row rank 6N: its null space is the 6-dimensional rigid motion.
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
        EXPECT_EQ(lu.rank(), 6 * arms);
    }
}

// --- Fixed and dynamic sizes give identical results ------------------------------------------

TEST(GraspKernels, FixedAndDynamicSizesAgreeExactly)
{
    std::mt19937 rng(41004);
    Eigen::Matrix<double, 3, 3> r_fixed;
    for (int i = 0; i < 3; ++i) {
        r_fixed.col(i) = random_vector(rng);
    }
    const Eigen::Matrix3Xd r_cols = r_fixed;
    const Eigen::MatrixXd r_dynamic = r_fixed;
    const Vector3d omega = random_vector(rng, 2.0);

    const auto G_fixed = coopdyn::grasp_matrix(r_fixed);
    EXPECT_EQ(Eigen::MatrixXd(G_fixed), Eigen::MatrixXd(coopdyn::grasp_matrix(r_cols)));
    EXPECT_EQ(Eigen::MatrixXd(G_fixed), Eigen::MatrixXd(coopdyn::grasp_matrix(r_dynamic)));
    const auto A_fixed = coopdyn::constraint_matrix(r_fixed);
    EXPECT_EQ(Eigen::MatrixXd(A_fixed), Eigen::MatrixXd(coopdyn::constraint_matrix(r_cols)));
    EXPECT_EQ(Eigen::MatrixXd(A_fixed), Eigen::MatrixXd(coopdyn::constraint_matrix(r_dynamic)));
    const auto b_fixed = coopdyn::constraint_bias(r_fixed, omega);
    EXPECT_EQ(Eigen::VectorXd(b_fixed), Eigen::VectorXd(coopdyn::constraint_bias(r_cols, omega)));
    EXPECT_EQ(Eigen::VectorXd(b_fixed), Eigen::VectorXd(coopdyn::constraint_bias(r_dynamic, omega)));
    // Block-expression arguments (a view into a larger matrix) give the same.
    Eigen::Matrix<double, 3, 5> wide = Eigen::Matrix<double, 3, 5>::Zero();
    wide.middleCols<3>(1) = r_fixed;
    EXPECT_EQ(Eigen::MatrixXd(G_fixed), Eigen::MatrixXd(coopdyn::grasp_matrix(wide.middleCols<3>(1))));
    EXPECT_EQ(Eigen::VectorXd(b_fixed), Eigen::VectorXd(coopdyn::constraint_bias(wide.middleCols<3>(1), omega)));
}

TEST(GraspKernels, FloatInstantiation)
{
    Eigen::Matrix<float, 3, 2> r;
    r << 0.1f, -0.1f, 0.2f, 0.3f, 0.0f, 0.5f;
    const Eigen::Matrix<float, 6, 12> G = coopdyn::grasp_matrix(r);
    const Eigen::Matrix<float, 12, 18> A = coopdyn::constraint_matrix(r);
    const Eigen::Matrix<float, 12, 1> b = coopdyn::constraint_bias(r, Eigen::Vector3f(0.0f, 1.0f, 2.0f));
    EXPECT_EQ(Eigen::MatrixXf(A.leftCols<6>()), Eigen::MatrixXf(-G.transpose()));
    EXPECT_TRUE(b.allFinite());
}

// --- Grasp operators applied per contact, against the dense grasp matrix ----------------------

/// Gdot = d/dt G(R(t) r) at t = 0 for contacts turning with the object at omega: a fourth-order
/// central difference of the literal grasp matrix (24) (no coopdyn code).
Eigen::MatrixXd numerical_grasp_rate(const Eigen::MatrixXd& r, const Vector3d& omega)
{
    const double step = 1e-3;
    const auto at = [&](double t) {
        const Eigen::MatrixXd turned =
            coopdyn_test::rotation_matrix(coopdyn_test::rotation_exponential(t * omega)) * r;
        return coopdyn_test::literal_grasp_matrix(turned);
    };
    return (-at(2 * step) + 8 * at(step) - 8 * at(-step) + at(-2 * step)) / (12 * step);
}

/// The operators at r (3 x K, fixed rows) as dense results: G w, G^T y, Gdot v, Gdot^T y.
struct OperatorResults {
    Eigen::VectorXd grasp_w, grasp_transpose_y, rate_v, rate_transpose_y;
};

template <typename DerivedR>
OperatorResults apply_operators(const Eigen::MatrixBase<DerivedR>& r, const Vector3d& omega, const Eigen::VectorXd& w,
                                const Vector6d& y)
{
    OperatorResults result;
    result.grasp_w = coopdyn::detail::grasp_times(r, w).vector();
    result.grasp_transpose_y = Eigen::VectorXd::Zero(6 * r.cols());
    coopdyn::detail::write_grasp_transpose_times(r, coopdyn::Motion<double>::from(y), result.grasp_transpose_y);
    result.rate_v = coopdyn::detail::grasp_rate_times(r, omega, w);
    result.rate_transpose_y = Eigen::VectorXd::Zero(6 * r.cols());
    coopdyn::detail::grasp_rate_transpose_times(r, omega, y, result.rate_transpose_y);
    return result;
}

TEST(GraspOperators, MatchTheDenseGraspMatrixAndItsRate)
{
    std::mt19937 rng(41005);
    double worst_exact = 0.0, worst_rate = 0.0, worst_fixed = 0.0;
    for (Eigen::Index arms = 2; arms <= 4; ++arms) {
        for (int draw = 0; draw < 10; ++draw) {
            const Eigen::MatrixXd r = coopdyn_test::off_centre_offsets(arms, rng);
            const Eigen::Matrix3Xd offsets = r;
            const Vector3d omega = random_vector(rng, 2.0);
            const Eigen::VectorXd w = coopdyn_test::random_vector(6 * arms, rng);
            const Vector6d y = random_vector6(rng);
            const Eigen::MatrixXd G = coopdyn_test::literal_grasp_matrix(r);
            const Eigen::MatrixXd G_rate = numerical_grasp_rate(r, omega);
            const OperatorResults ops = apply_operators(offsets, omega, w, y);
            const auto relative = [](const Eigen::MatrixXd& value, const Eigen::MatrixXd& reference) {
                return (value - reference).norm() / std::max(reference.norm(), 1e-300);
            };
            worst_exact = std::max({worst_exact, relative(ops.grasp_w, G * w),
                                    relative(ops.grasp_transpose_y, G.transpose() * y),
                                    relative(coopdyn::detail::grasp_gram(G), G * G.transpose()),
                                    relative(coopdyn::detail::grasp_gram_inertia(offsets).matrix(), G * G.transpose())});
            worst_rate = std::max({worst_rate, relative(ops.rate_v, G_rate * w),
                                   relative(ops.rate_transpose_y, G_rate.transpose() * y)});
            if (arms == 3) {
                const Eigen::Matrix3d fixed = r;
                const OperatorResults fixed_ops = apply_operators(fixed, omega, w, y);
                worst_fixed = std::max({worst_fixed, relative(fixed_ops.grasp_w, ops.grasp_w),
                                        relative(fixed_ops.grasp_transpose_y, ops.grasp_transpose_y),
                                        relative(fixed_ops.rate_v, ops.rate_v),
                                        relative(fixed_ops.rate_transpose_y, ops.rate_transpose_y)});
            }
        }
    }
    RecordProperty("worst_products", scientific(worst_exact));
    RecordProperty("worst_rates", scientific(worst_rate));
    std::printf("grasp operators: products %.2e, rates against central differences %.2e, fixed vs dynamic %.2e\n",
                worst_exact, worst_rate, worst_fixed);
    EXPECT_LT(worst_exact, 1e-15);
    EXPECT_LT(worst_rate, 1e-11);
    EXPECT_LT(worst_fixed, 1e-15);
}

}  // namespace
