// Tests of the friction constraints of one contact (include/coopdyn/control/friction.hpp), Lin et
// al. L(17)-(19) with errata E9. References: the geometric meaning of each row (a wrench on the
// boundary of a constraint makes its row an equality, a wrench inside satisfies every row), the
// inscribed pyramid's edges on the Coulomb cone, the patch's corners for the centre of pressure,
// and the frame change written out by hand.

#include "coopdyn/control/friction.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using coopdyn_test::Matrix3d;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using Index = Eigen::Index;
using Rows = Eigen::Matrix<double, 15, 6>;
using Bounds = Eigen::Matrix<double, 15, 1>;

coopdyn::ContactFriction<double> palm()
{
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = 0.6;
    friction.torsional_coefficient = 0.02;
    friction.patch_half_length_x = 0.04;
    friction.patch_half_length_y = 0.03;
    friction.minimum_normal_force = 2.0;
    friction.pyramid_edges = 8;
    return friction;
}

Bounds slack(const coopdyn::ContactFriction<double>& friction, const Vector6d& wrench)
{
    Rows rows;
    Bounds bounds;
    coopdyn::contact_frame_friction_rows(friction, rows, bounds);
    return bounds - rows * wrench;
}

TEST(Friction, RowsHaveThePaperOrderAndCount)
{
    static_assert(coopdyn::friction_rows(8) == 15, "n + 7 rows: 15 for the paper's n = 8");
    const auto friction = palm();
    // At rest with 10 N normal force and nothing else: every row holds strictly, and the slacks
    // are the distances to each boundary, scaled by the row: f_z - f_min; mu cos(pi/8) f_z per
    // facet; gamma f_z (torsion); delta_y f_z, delta_x f_z (centre of pressure, E9).
    Vector6d wrench = Vector6d::Zero();
    wrench(2) = 10.0;
    const Bounds s = slack(friction, wrench);
    EXPECT_DOUBLE_EQ(s(0), 8.0);
    for (int k = 0; k < 8; ++k) {
        EXPECT_NEAR(s(1 + k), 0.6 * std::cos(coopdyn::pi<double>() / 8) * 10.0, 1e-14);
    }
    EXPECT_NEAR(s(9), 0.2, 1e-15);
    EXPECT_NEAR(s(10), 0.2, 1e-15);
    EXPECT_NEAR(s(11), 0.3, 1e-15);  // t_x bounded by delta_y f_z = 0.03 * 10
    EXPECT_NEAR(s(13), 0.4, 1e-15);  // t_y bounded by delta_x f_z = 0.04 * 10
}

TEST(Friction, PyramidEdgesLieOnTheConeAndFacetsInsideIt)
{
    auto friction = palm();
    for (const int edges : {3, 4, 8, 12}) {
        friction.pyramid_edges = edges;
        Eigen::MatrixXd rows(edges + 7, 6);
        Eigen::VectorXd bounds(edges + 7);
        coopdyn::contact_frame_friction_rows(friction, rows, bounds);
        const double f_z = 10.0;
        for (int k = 0; k < edges; ++k) {
            // Edge k at angle 2 pi k / n on the cone |f_t| = mu f_z: two facets bind, the rest hold.
            const double angle = 2.0 * coopdyn::pi<double>() * k / edges;
            Vector6d wrench = Vector6d::Zero();
            wrench << 0.6 * f_z * std::cos(angle), 0.6 * f_z * std::sin(angle), f_z, 0, 0, 0;
            const Eigen::VectorXd s = bounds - rows * wrench;
            int binding = 0;
            for (int facet = 0; facet < edges; ++facet) {
                EXPECT_GT(s(1 + facet), -1e-12) << "n = " << edges << ", edge " << k;
                binding += std::abs(s(1 + facet)) < 1e-12 ? 1 : 0;
            }
            EXPECT_EQ(binding, 2) << "n = " << edges << ", edge " << k;
            // A little beyond the edge violates a facet.
            const Eigen::VectorXd beyond = bounds - rows * (1.001 * wrench - 0.001 * f_z * Vector6d::Unit(2));
            EXPECT_LT(beyond.segment(1, edges).minCoeff(), 0.0);
        }
        // Along a facet's normal the pyramid reaches only mu cos(pi / n) f_z.
        const double facet_angle = 2.0 * coopdyn::pi<double>() * 0.5 / edges;
        Vector6d wrench = Vector6d::Zero();
        const double reach = 0.6 * std::cos(coopdyn::pi<double>() / edges) * f_z;
        wrench << reach * std::cos(facet_angle), reach * std::sin(facet_angle), f_z, 0, 0, 0;
        EXPECT_NEAR((bounds - rows * wrench)(1), 0.0, 1e-12) << "n = " << edges;
    }
}

TEST(Friction, TorsionAndCentreOfPressureBindAtTheirLimitsErrata9)
{
    const auto friction = palm();
    const double f_z = 20.0;
    // A normal force applied at the patch corner (x, y) = (delta_x, delta_y) gives t = r x f =
    // (delta_y f_z, -delta_x f_z, 0): both centre-of-pressure rows bind (E9: t_x with delta_y).
    Vector6d corner = Vector6d::Zero();
    corner(2) = f_z;
    corner.tail<3>() = Vector3d(0.04, 0.03, 0.0).cross(Vector3d(0, 0, f_z));
    const Bounds s = slack(friction, corner);
    EXPECT_NEAR(s(11), 0.0, 1e-13);  // +t_x = delta_y f_z
    EXPECT_NEAR(s(14), 0.0, 1e-13);  // -t_y = delta_x f_z
    EXPECT_GT(s(12), 0.0);
    EXPECT_GT(s(13), 0.0);
    // The printed L(19) swaps the half-extents: |t_y| <= delta_y f_z would refuse this force,
    // applied inside the patch (at its corner), since |t_y| = delta_x f_z = 0.8 > 0.6.
    EXPECT_GT(std::abs(corner(4)), friction.patch_half_length_y * f_z);
    // Torsion: |t_z| = gamma f_z binds.
    Vector6d twist = Vector6d::Zero();
    twist(2) = f_z;
    twist(5) = -friction.torsional_coefficient * f_z;
    EXPECT_NEAR(slack(friction, twist)(10), 0.0, 1e-14);
    // Unilateral: f_z = f_min binds.
    Vector6d light = Vector6d::Zero();
    light(2) = friction.minimum_normal_force;
    EXPECT_NEAR(slack(friction, light)(0), 0.0, 1e-15);
}

TEST(Friction, WorldFrameRowsActOnTheRotatedWrench)
{
    Rng rng(7);
    const auto friction = palm();
    for (int trial = 0; trial < 20; ++trial) {
        const Matrix3d rotation = coopdyn_test::random_unit_quaternion(rng).toRotationMatrix();  // {c} -> {w}
        Rows world_rows, contact_rows;
        Bounds world_bounds, contact_bounds;
        coopdyn::friction_rows(friction, rotation, world_rows, world_bounds);
        coopdyn::contact_frame_friction_rows(friction, contact_rows, contact_bounds);
        const Vector6d world_wrench = 10.0 * Vector6d(coopdyn_test::random_vector(6, rng));
        Vector6d in_contact;
        in_contact << rotation.transpose() * world_wrench.head<3>(), rotation.transpose() * world_wrench.tail<3>();
        EXPECT_LT((world_rows * world_wrench - contact_rows * in_contact).norm(), 1e-12);
        EXPECT_EQ(world_bounds, contact_bounds);
    }
}

TEST(Friction, MarginIsTheDistanceToTheNearestBoundary)
{
    const auto friction = palm();
    const double reach = 0.6 * std::cos(coopdyn::pi<double>() / 8);  // facets at mu cos(pi/n) f_z

    // 10 N along the normal only: the nearest boundary is a centre-of-pressure plane |t_x| =
    // delta_y f_z, at distance delta_y f_z / sqrt(1 + delta_y^2) from w (the row (+-1, -delta_y)
    // in (t_x, f_z)); the unilateral plane is 8 N away, the facets reach f_z / sqrt(1 + reach^2).
    Vector6d wrench = Vector6d::Zero();
    wrench(2) = 10.0;
    EXPECT_NEAR(coopdyn::friction_margin(friction, wrench), 0.02 * 10.0 / std::sqrt(1.0 + 0.02 * 0.02), 1e-14);

    // A tangential force along facet 0's normal (angle pi/8) with no moments and a large patch:
    // the facet binds first, at (reach f_z - |f_t|) / sqrt(1 + reach^2).
    auto wide = friction;
    wide.torsional_coefficient = 1.0;
    wide.patch_half_length_x = wide.patch_half_length_y = 1.0;
    const double tangential = 3.0;
    wrench << tangential * std::cos(coopdyn::pi<double>() / 8), tangential * std::sin(coopdyn::pi<double>() / 8), 10.0,
        0.0, 0.0, 0.0;
    const double facet_distance = (reach * 10.0 - tangential) / std::sqrt(1.0 + reach * reach);
    EXPECT_NEAR(coopdyn::friction_margin(wide, wrench), facet_distance, 1e-13);
    // Pushed outside the pyramid along the same direction: negative, by the same formula.
    wrench.head<2>() *= 3.0;
    EXPECT_NEAR(coopdyn::friction_margin(wide, wrench), (reach * 10.0 - 3.0 * tangential) / std::sqrt(1.0 + reach * reach),
                1e-13);
    // Pulling (f_z below f_min): the unilateral row is violated by f_min - f_z.
    wrench << 0.0, 0.0, -1.0, 0.0, 0.0, 0.0;
    EXPECT_NEAR(coopdyn::friction_margin(wide, wrench), -3.0, 1e-14);

    // Rows built once give the same margins as rebuilding them per call, for random wrenches.
    Rows rows;
    Bounds bounds;
    coopdyn::contact_frame_friction_rows(friction, rows, bounds);
    Rng rng(17);
    for (int trial = 0; trial < 50; ++trial) {
        const Vector6d random = coopdyn_test::random_vector(6, rng, -20.0, 20.0);
        EXPECT_EQ(coopdyn::friction_margin(rows, bounds, random), coopdyn::friction_margin(friction, random));
    }
}

TEST(Friction, InvalidParametersAreNamedWithTheContact)
{
    const auto expect_refused = [](coopdyn::ContactFriction<double> friction, const std::string& parameter) {
        try {
            friction.validate(1);
            ADD_FAILURE() << parameter << " was accepted";
        } catch (const coopdyn::InvalidModel& error) {
            EXPECT_EQ(error.parameter(), parameter);
            EXPECT_EQ(error.arm(), 1);
        }
    };
    auto friction = palm();
    EXPECT_NO_THROW(friction.validate(0));
    friction.friction_coefficient = -0.1;
    expect_refused(friction, "friction_coefficient");
    friction = palm();
    friction.patch_half_length_x = 0.0;
    expect_refused(friction, "patch_half_length_x");
    friction = palm();
    friction.patch_half_length_y = std::nan("");
    expect_refused(friction, "patch_half_length_y");
    friction = palm();
    friction.torsional_coefficient = -1.0;
    expect_refused(friction, "torsional_coefficient");
    friction = palm();
    friction.minimum_normal_force = -1.0;
    expect_refused(friction, "minimum_normal_force");
    friction = palm();
    friction.pyramid_edges = 2;
    expect_refused(friction, "pyramid_edges");
}

}  // namespace
