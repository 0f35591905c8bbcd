// Tests of coopdyn/spatial/inertia.hpp: CentralInertia, SpatialInertia and ArticulatedInertia
// (docs/spatial.md, paper (1), (9), (21), (24), (31)), and that their operations allocate nothing.
//
// References are independent of the code under test:
// - rigid bodies made of point masses m_k at x_k, whose spatial inertia about a point o is summed
//   by brute force, sum m_k [[I3, S(x_k - o)^T], [S(x_k - o), S(x_k - o) S(x_k - o)^T]], and whose
//   momentum and kinetic energy are summed over the points moving rigidly;
// - dense 6x6 formulas written out here: the congruence G(r) M G(r)^T with a literal
//   G(r) = [[I3, 0], [S(r), I3]], diag(R, R) M diag(R, R)^T, M x, Eigen's LDLT solve;
// - central finite differences (kinetic-energy gradient, autodiff derivatives with respect to r).
// Typed over double and float (tolerances scaled by the scalar's epsilon; inputs are rounded to the
// scalar first so that the double references see the same numbers).

// Replaces the global allocation functions of this executable: must come first.
#include "../allocation_counter.hpp"

#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/quaternion.hpp"
#include "spatial_references.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/AutoDiff>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

// Every non-template member compiles for the supported scalars.
template class coopdyn::CentralInertia<double>;
template class coopdyn::CentralInertia<float>;
template class coopdyn::SpatialInertia<double>;
template class coopdyn::SpatialInertia<float>;
template class coopdyn::ArticulatedInertia<double>;
template class coopdyn::ArticulatedInertia<float>;

namespace {

using coopdyn_test::epsilon;
using coopdyn_test::literal_grasp_map;
using coopdyn_test::literal_skew;
using coopdyn_test::random_rotation;
using coopdyn_test::random_six;
using coopdyn_test::random_vector;
using coopdyn_test::relative_error;
using coopdyn_test::round_to;
using coopdyn_test::rounded;
using coopdyn_test::scientific;

using coopdyn::ArticulatedInertia;
using coopdyn::CentralInertia;
using coopdyn::Force;
using coopdyn::Motion;
using coopdyn::SpatialInertia;
using coopdyn::Symmetric3;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using AutoDiff = Eigen::AutoDiffScalar<Eigen::VectorXd>;

// --- Literal references ----------------------------------------------------------------------------

/// diag(R, R).
Matrix6d literal_block_rotation(const Matrix3d& rotation)
{
    Matrix6d result = Matrix6d::Zero();
    result.topLeftCorner<3, 3>() = rotation;
    result.bottomRightCorner<3, 3>() = rotation;
    return result;
}

/// Spatial inertia of a point mass m at x (from the reference point): m [[I3, S(x)^T], [S(x), S(x) S(x)^T]].
Matrix6d point_mass_inertia(double mass, const Vector3d& x)
{
    Matrix6d result;
    result.topLeftCorner<3, 3>() = mass * Matrix3d::Identity();
    result.bottomLeftCorner<3, 3>() = mass * literal_skew(x);
    result.topRightCorner<3, 3>() = mass * literal_skew(x).transpose();
    result.bottomRightCorner<3, 3>() = mass * literal_skew(x) * literal_skew(x).transpose();
    return result;
}

/// A rigid body made of point masses at positions x_k (in a fixed frame).
struct PointMassBody {
    std::vector<double> masses;
    std::vector<Vector3d> points;

    double mass() const
    {
        double sum = 0.0;
        for (const double m : masses) {
            sum += m;
        }
        return sum;
    }
    Vector3d centre() const
    {
        Vector3d sum = Vector3d::Zero();
        for (std::size_t k = 0; k < masses.size(); ++k) {
            sum += masses[k] * points[k];
        }
        return sum / mass();
    }
    /// Brute force: the sum of the point masses' inertias about `origin`.
    Matrix6d inertia_about(const Vector3d& origin) const
    {
        Matrix6d sum = Matrix6d::Zero();
        for (std::size_t k = 0; k < masses.size(); ++k) {
            sum += point_mass_inertia(masses[k], points[k] - origin);
        }
        return sum;
    }
    /// Rotational inertia about the centre of mass, brute force.
    Matrix3d rotational_about_centre() const
    {
        return inertia_about(centre()).bottomRightCorner<3, 3>();
    }
};

/// `count` point masses in [0.1, 2] kg spread over a box of the given half-extents around `centre`.
PointMassBody random_body(std::mt19937& rng, int count, const Vector3d& extents, const Vector3d& centre)
{
    std::uniform_real_distribution<double> mass(0.1, 2.0);
    PointMassBody body;
    for (int k = 0; k < count; ++k) {
        body.masses.push_back(mass(rng));
        body.points.push_back(centre + random_vector(rng).cwiseProduct(extents));
    }
    return body;
}

/// A rigid body's rotational inertia with principal extents 10^[log10(smallest), log10(largest)].
Matrix3d random_rigid_body_inertia(std::mt19937& rng, double mass, double smallest, double largest)
{
    std::uniform_real_distribution<double> exponent(std::log10(smallest), std::log10(largest));
    const Vector3d extents(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)));
    const Matrix3d rotation = random_rotation(rng);
    const Matrix3d second_moment = mass * rotation * extents.cwiseAbs2().asDiagonal() * rotation.transpose();
    const Matrix3d inertia = second_moment.trace() * Matrix3d::Identity() - second_moment;
    return 0.5 * (inertia + inertia.transpose());
}

/// Rounds every entry of a double inertia to Scalar (so that cast<Scalar>() is exact).
template <typename Scalar> Symmetric3<double> round_symmetric(const Symmetric3<double>& s)
{
    return Symmetric3<double>(round_to<Scalar>(s.xx), round_to<Scalar>(s.yx), round_to<Scalar>(s.zx), round_to<Scalar>(s.yy),
                              round_to<Scalar>(s.zy), round_to<Scalar>(s.zz));
}

/// A random rigid-body SpatialInertia about a point at `offset_scale` from its centre of mass
/// (asymmetric), built densely here (not with from_centre), entries representable in Scalar.
template <typename Scalar>
SpatialInertia<double> random_spatial_inertia(std::mt19937& rng, double offset_scale, double smallest = 0.05, double largest = 0.5)
{
    std::uniform_real_distribution<double> mass_distribution(0.5, 20.0);
    const double mass = round_to<Scalar>(mass_distribution(rng));
    const Vector3d centre = random_vector(rng, offset_scale).cwiseProduct(Vector3d(1.0, 0.35, 1.6));
    const Vector3d first_moment = rounded<Scalar>(Vector3d(mass * centre));
    const Matrix3d about_centre = random_rigid_body_inertia(rng, mass, smallest, largest);
    const Matrix3d rotational = about_centre + literal_skew(first_moment) * literal_skew(first_moment).transpose() / mass;
    return SpatialInertia<double>(mass, first_moment, round_symmetric<Scalar>(Symmetric3<double>(rotational)));
}

template <typename Scalar> CentralInertia<double> random_central_inertia(std::mt19937& rng)
{
    std::uniform_real_distribution<double> mass_distribution(0.5, 20.0);
    const double mass = round_to<Scalar>(mass_distribution(rng));
    return CentralInertia<double>(mass, round_symmetric<Scalar>(Symmetric3<double>(random_rigid_body_inertia(rng, mass, 0.05, 0.5))));
}

/// A general SPD 6x6 (not a rigid body's), scale (B B^T + floor I6), entries representable in Scalar.
template <typename Scalar> Matrix6d random_spd6(std::mt19937& rng, double scale = 1.0, double floor = 0.5)
{
    Matrix6d factor;
    for (int k = 0; k < 36; ++k) {
        factor(k) = random_vector(rng)(0);
    }
    Matrix6d spd = scale * (factor * factor.transpose() + floor * Matrix6d::Identity());
    spd = rounded<Scalar>(spd);
    return 0.5 * (spd + spd.transpose());  // exact: both triangles are the same rounded numbers
}

template <typename Inertia> Matrix6d dense(const Inertia& inertia) { return inertia.matrix().template cast<double>(); }
template <typename Scalar> Vector6d dense(const Motion<Scalar>& motion) { return motion.vector().template cast<double>(); }
template <typename Scalar> Vector6d dense(const Force<Scalar>& force) { return force.vector().template cast<double>(); }

/// Records the worst of a measured error for the test's XML output.
struct Worst {
    std::string name;
    double value = 0.0;
    void operator()(double error) { value = std::max(value, error); }
    ~Worst() { ::testing::Test::RecordProperty(name, scientific(value)); }
};

template <typename Scalar> class InertiaTyped : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(InertiaTyped, Scalars);

// --- Layout and construction ----------------------------------------------------------------------

TYPED_TEST(InertiaTyped, MatrixLayoutIsMassFirstMomentRotational)
{
    using Scalar = TypeParam;
    const Scalar mass(2.5);
    const coopdyn::Vector3<Scalar> h(Scalar(0.5), Scalar(-0.25), Scalar(1.0));
    const Symmetric3<Scalar> rotational(Scalar(3), Scalar(0.25), Scalar(-0.5), Scalar(4), Scalar(0.125), Scalar(5));
    const SpatialInertia<Scalar> inertia(mass, h, rotational);
    Matrix6d expected;
    // [[m I3, S(h)^T], [S(h), I]] written out for h = (0.5, -0.25, 1).
    expected << 2.5, 0.0, 0.0, 0.0, 1.0, 0.25,     //
        0.0, 2.5, 0.0, -1.0, 0.0, 0.5,             //
        0.0, 0.0, 2.5, -0.25, -0.5, 0.0,           //
        0.0, -1.0, -0.25, 3.0, 0.25, -0.5,         //
        1.0, 0.0, -0.5, 0.25, 4.0, 0.125,          //
        0.25, 0.5, 0.0, -0.5, 0.125, 5.0;
    EXPECT_EQ(dense(inertia), expected);
    EXPECT_EQ(inertia.mass(), mass);
    EXPECT_EQ(inertia.first_moment(), h);
    EXPECT_EQ(inertia.rotational(), rotational);
    EXPECT_EQ(inertia.centre(), (h / mass).eval());

    // block_diagonal, from a Symmetric3 or a dense 3x3 (its upper triangle is not read).
    coopdyn::Matrix3<Scalar> lower = rotational.matrix();
    lower(0, 1) = lower(0, 2) = lower(1, 2) = Scalar(-99);
    const SpatialInertia<Scalar> diagonal = SpatialInertia<Scalar>::block_diagonal(mass, rotational);
    EXPECT_EQ(dense(SpatialInertia<Scalar>::block_diagonal(mass, lower)), dense(diagonal));
    Matrix6d block = Matrix6d::Zero();
    block.topLeftCorner<3, 3>() = 2.5 * Matrix3d::Identity();
    block.bottomRightCorner<3, 3>() = rotational.matrix().template cast<double>();
    EXPECT_EQ(dense(diagonal), block);
    EXPECT_EQ(diagonal.first_moment(), coopdyn::Vector3<Scalar>::Zero());

    // A central inertia: same matrix, as itself, converted, or as a general one.
    const CentralInertia<Scalar> central(mass, rotational);
    EXPECT_EQ(dense(central), block);
    EXPECT_EQ(dense(CentralInertia<Scalar>(mass, lower)), block);
    const SpatialInertia<Scalar> converted = central;
    EXPECT_EQ(dense(converted), block);
    EXPECT_EQ(dense(ArticulatedInertia<Scalar>(central)), block);
    EXPECT_EQ(dense(ArticulatedInertia<Scalar>(inertia)), expected);

    // A general inertia from a dense 6x6 reads its lower triangle.
    Matrix6d lower6 = expected;
    for (int j = 1; j < 6; ++j) {
        for (int i = 0; i < j; ++i) {
            lower6(i, j) = -1234.0;
        }
    }
    const ArticulatedInertia<Scalar> general(lower6.cast<Scalar>());
    EXPECT_EQ(dense(general), expected);
    EXPECT_EQ(Matrix3d(general.coupling().template cast<double>()), literal_skew(h.template cast<double>()));

    // Zeros.
    EXPECT_EQ(dense(SpatialInertia<Scalar>()), Matrix6d::Zero());
    EXPECT_EQ(dense(SpatialInertia<Scalar>::Zero()), Matrix6d::Zero());
    EXPECT_EQ(dense(CentralInertia<Scalar>::Zero()), Matrix6d::Zero());
    EXPECT_EQ(dense(ArticulatedInertia<Scalar>::Zero()), Matrix6d::Zero());
}

// --- Point-mass bodies: the parallel-axis theorem by brute force ---------------------------------

TYPED_TEST(InertiaTyped, FromCentreShiftedAndSumsMatchPointMassBodies)
{
    using Scalar = TypeParam;
    using Vector3s = coopdyn::Vector3<Scalar>;
    std::mt19937 rng(41);
    Worst worst{"worst_relative_error_over_eps"};
    const double tolerance = 16.0 * epsilon<Scalar>();
    const int counts[] = {4, 7, 12};
    const Vector3d extents[] = {Vector3d(0.5, 0.1, 0.02), Vector3d(0.3, 0.3, 0.3), Vector3d(1.0, 0.05, 0.4)};
    for (int trial = 0; trial < 30; ++trial) {
        const PointMassBody body = random_body(rng, counts[trial % 3], extents[(trial / 3) % 3], random_vector(rng, 0.7));
        const PointMassBody other_body = random_body(rng, counts[(trial + 1) % 3], extents[trial % 3], random_vector(rng, 0.9));
        const double mass = body.mass();
        const Vector3d centre = body.centre();
        const Symmetric3<Scalar> about_centre(body.rotational_about_centre().cast<Scalar>());
        const Vector3d origin = random_vector(rng, 1.2);   // O
        const Vector3d attached = random_vector(rng, 0.8);  // A
        const Matrix6d expected = body.inertia_about(origin);
        const auto error_of = [&](const Matrix6d& value, const Matrix6d& reference) {
            const double error = relative_error(value, reference);
            worst(error / epsilon<Scalar>());
            return error;
        };

        // About O from its centre, mass and central inertia.
        const SpatialInertia<Scalar> about_origin =
            SpatialInertia<Scalar>::from_centre(static_cast<Scalar>(mass), Vector3s((centre - origin).cast<Scalar>()), about_centre);
        EXPECT_LT(error_of(dense(about_origin), expected), tolerance);
        // About A, then shifted to O: shifted(r) takes an inertia about A to the point O = A - r.
        const SpatialInertia<Scalar> about_attached =
            SpatialInertia<Scalar>::from_centre(static_cast<Scalar>(mass), Vector3s((centre - attached).cast<Scalar>()), about_centre);
        const Vector3s r = (attached - origin).cast<Scalar>();
        EXPECT_LT(error_of(dense(about_attached.shifted(r)), expected), tolerance);
        // A central inertia shifted by c - O.
        const CentralInertia<Scalar> central(static_cast<Scalar>(mass), about_centre);
        const Vector3s to_centre = (centre - origin).cast<Scalar>();
        EXPECT_LT(error_of(dense(central.shifted(to_centre)), expected), tolerance);
        EXPECT_LT(error_of(dense(ArticulatedInertia<Scalar>(about_attached).shifted(r)), expected), tolerance);

        // The composite of two bodies: the brute-force sum over the union of their point masses.
        const Matrix6d union_expected = expected + other_body.inertia_about(origin);
        const Symmetric3<Scalar> other_about_centre(other_body.rotational_about_centre().cast<Scalar>());
        const Vector3d other_attached = random_vector(rng, 0.8);
        const SpatialInertia<Scalar> other_about_attached = SpatialInertia<Scalar>::from_centre(
            static_cast<Scalar>(other_body.mass()), Vector3s((other_body.centre() - other_attached).cast<Scalar>()), other_about_centre);
        const Vector3s other_r = (other_attached - origin).cast<Scalar>();
        SpatialInertia<Scalar> composite;
        composite.add_shifted(about_attached, r);
        composite.add_shifted(other_about_attached, other_r);
        EXPECT_LT(error_of(dense(composite), union_expected), tolerance);
        SpatialInertia<Scalar> from_central = about_attached.shifted(r);
        from_central.add_shifted(CentralInertia<Scalar>(static_cast<Scalar>(other_body.mass()), other_about_centre),
                                 Vector3s((other_body.centre() - origin).cast<Scalar>()));
        EXPECT_LT(error_of(dense(from_central), union_expected), tolerance);
        SpatialInertia<Scalar> summed = about_origin;
        summed += other_about_attached.shifted(other_r);
        EXPECT_LT(error_of(dense(summed), union_expected), tolerance);
        EXPECT_LT(error_of(dense(about_origin + other_about_attached.shifted(other_r)), union_expected), tolerance);
        ArticulatedInertia<Scalar> general_composite;
        general_composite.add_shifted(about_attached, r);
        general_composite.add_shifted(ArticulatedInertia<Scalar>(other_about_attached), other_r);
        EXPECT_LT(error_of(dense(general_composite), union_expected), tolerance);

        // Derived quantities: mass, centre and central inertia are those of the point masses.
        EXPECT_NEAR(static_cast<double>(composite.mass()), mass + other_body.mass(), tolerance * (mass + other_body.mass()));
        const Vector3d union_centre = (mass * centre + other_body.mass() * other_body.centre()) / (mass + other_body.mass());
        EXPECT_LT((composite.centre().template cast<double>() - (union_centre - origin)).norm(), tolerance * 4.0);
        const Matrix3d union_about_centre = (expected + other_body.inertia_about(origin)).bottomRightCorner<3, 3>() -
                                            (mass + other_body.mass()) * literal_skew(union_centre - origin) *
                                                literal_skew(union_centre - origin).transpose();
        EXPECT_LT(relative_error(composite.rotational_about_centre().matrix().template cast<double>(), union_about_centre),
                  100.0 * tolerance);  // a difference of two larger matrices
        EXPECT_LT(relative_error(about_origin.rotational_about_centre().matrix().template cast<double>(),
                                 body.rotational_about_centre()),
                  100.0 * tolerance);
    }
}

TYPED_TEST(InertiaTyped, MomentumAndKineticEnergyAreThoseOfThePointMasses)
{
    // The body moves rigidly with twist [v; w] at O: point k moves at v_k = v + w x (x_k - O).
    // M xdot = [sum m_k v_k; sum (x_k - O) x m_k v_k] (momentum, angular momentum about O) and
    // 1/2 xdot^T M xdot = sum 1/2 m_k |v_k|^2.
    using Scalar = TypeParam;
    std::mt19937 rng(42);
    Worst worst_momentum{"worst_momentum_relative_error_over_eps"};
    Worst worst_energy{"worst_energy_relative_error_over_eps"};
    for (int trial = 0; trial < 30; ++trial) {
        const PointMassBody body = random_body(rng, 5 + trial % 6, Vector3d(0.4, 0.15, 0.05), random_vector(rng, 0.6));
        const Vector3d origin = random_vector(rng, 0.5);
        const Vector6d twist = random_six(rng, 1.0, 3.0);
        Vector3d momentum = Vector3d::Zero();
        Vector3d angular_momentum = Vector3d::Zero();
        double energy = 0.0;
        for (std::size_t k = 0; k < body.masses.size(); ++k) {
            const Vector3d arm = body.points[k] - origin;
            const Vector3d velocity = twist.head<3>() + twist.tail<3>().cross(arm);
            momentum += body.masses[k] * velocity;
            angular_momentum += arm.cross(body.masses[k] * velocity);
            energy += 0.5 * body.masses[k] * velocity.squaredNorm();
        }
        Vector6d expected;
        expected << momentum, angular_momentum;

        const SpatialInertia<Scalar> inertia = SpatialInertia<Scalar>::from_centre(
            static_cast<Scalar>(body.mass()), coopdyn::Vector3<Scalar>((body.centre() - origin).cast<Scalar>()),
            Symmetric3<Scalar>(body.rotational_about_centre().cast<Scalar>()));
        const Motion<Scalar> motion = Motion<Scalar>::from(twist.cast<Scalar>());
        const double momentum_error = (dense(inertia * motion) - expected).norm() / expected.norm();
        const double energy_error = std::abs(static_cast<double>(inertia.kinetic_energy(motion)) - energy) / energy;
        worst_momentum(momentum_error / epsilon<Scalar>());
        worst_energy(energy_error / epsilon<Scalar>());
        EXPECT_LT(momentum_error, 30.0 * epsilon<Scalar>());
        EXPECT_LT(energy_error, 30.0 * epsilon<Scalar>());
        // The same through the general type.
        const ArticulatedInertia<Scalar> general(inertia);
        EXPECT_LT((dense(general * motion) - expected).norm() / expected.norm(), 30.0 * epsilon<Scalar>());
        EXPECT_LT(std::abs(static_cast<double>(general.kinetic_energy(motion)) - energy) / energy, 30.0 * epsilon<Scalar>());
    }
}

TEST(Inertia, KineticEnergyGradientIsTheMomentum_FiniteDifferences)
{
    // d(1/2 xdot^T M xdot) / d xdot = M xdot, by central differences, for all three types.
    std::mt19937 rng(43);
    double worst = 0.0;
    for (int trial = 0; trial < 10; ++trial) {
        const SpatialInertia<double> spatial = random_spatial_inertia<double>(rng, 0.5);
        const CentralInertia<double> central = random_central_inertia<double>(rng);
        const ArticulatedInertia<double> general(random_spd6<double>(rng, 2.0));
        const Vector6d twist = random_six(rng, 1.0, 2.0);
        const auto check = [&](const auto& inertia) {
            const Vector6d momentum = dense(inertia * Motion<double>::from(twist));
            Vector6d gradient;
            for (int k = 0; k < 6; ++k) {
                const double h = 1e-5;
                gradient(k) = (inertia.kinetic_energy(Motion<double>::from(Vector6d(twist + h * Vector6d::Unit(k)))) -
                               inertia.kinetic_energy(Motion<double>::from(Vector6d(twist - h * Vector6d::Unit(k))))) / (2.0 * h);
            }
            const double error = (gradient - momentum).norm() / momentum.norm();
            worst = std::max(worst, error);
            EXPECT_LT(error, 1e-9);
        };
        check(spatial);
        check(central);
        check(general);
    }
    RecordProperty("worst_relative_error_vs_central_differences", scientific(worst));
}

// --- Dense formulas: G(r) M G(r)^T, diag(R, R) M diag(R, R)^T, M x --------------------------------

TYPED_TEST(InertiaTyped, ShiftedIsTheLiteralCongruenceWithTheGraspMap)
{
    using Scalar = TypeParam;
    std::mt19937 rng(44);
    Worst worst{"worst_relative_error_over_eps"};
    for (const double offset : {1e-3, 0.1, 0.5, 2.0}) {
        for (int trial = 0; trial < 15; ++trial) {
            const Vector3d r = rounded<Scalar>(Vector3d(random_vector(rng, offset).cwiseProduct(Vector3d(1.0, 1.7, 0.4))));
            const coopdyn::Vector3<Scalar> r_s = r.cast<Scalar>();
            const Matrix6d g = literal_grasp_map(r);
            const auto check = [&](const Matrix6d& value, const Matrix6d& reference, const char* what) {
                const double error = relative_error(value, reference);
                worst(error / epsilon<Scalar>());
                EXPECT_LT(error, 16.0 * epsilon<Scalar>()) << what << ", offset " << offset;
            };

            const SpatialInertia<double> spatial = random_spatial_inertia<Scalar>(rng, 0.4);
            const SpatialInertia<Scalar> spatial_s = spatial.template cast<Scalar>();
            check(dense(spatial_s.shifted(r_s)), g * dense(spatial) * g.transpose(), "SpatialInertia::shifted");
            const CentralInertia<double> central = random_central_inertia<Scalar>(rng);
            const CentralInertia<Scalar> central_s = central.template cast<Scalar>();
            check(dense(central_s.shifted(r_s)), g * dense(central) * g.transpose(), "CentralInertia::shifted");
            const Matrix6d general = random_spd6<Scalar>(rng, 3.0);
            const ArticulatedInertia<Scalar> general_s(general.cast<Scalar>());
            check(dense(general_s.shifted(r_s)), g * general * g.transpose(), "ArticulatedInertia::shifted");

            // add_shifted onto an accumulator: this + G other G^T.
            const SpatialInertia<double> start = random_spatial_inertia<Scalar>(rng, 0.3);
            SpatialInertia<Scalar> accumulated = start.template cast<Scalar>();
            accumulated.add_shifted(spatial_s, r_s);
            check(dense(accumulated), dense(start) + g * dense(spatial) * g.transpose(), "SpatialInertia::add_shifted");
            accumulated = start.template cast<Scalar>();
            accumulated.add_shifted(central_s, r_s);
            check(dense(accumulated), dense(start) + g * dense(central) * g.transpose(), "SpatialInertia::add_shifted(central)");
            ArticulatedInertia<Scalar> general_accumulated = general_s;
            general_accumulated.add_shifted(general_s, r_s);
            check(dense(general_accumulated), general + g * general * g.transpose(), "ArticulatedInertia::add_shifted");
            general_accumulated = general_s;
            general_accumulated.add_shifted(spatial_s, r_s);
            check(dense(general_accumulated), general + g * dense(spatial) * g.transpose(), "ArticulatedInertia::add_shifted(spatial)");
            general_accumulated = general_s;
            general_accumulated.add_shifted(central_s, r_s);
            check(dense(general_accumulated), general + g * dense(central) * g.transpose(), "ArticulatedInertia::add_shifted(central)");
        }
    }
}

TYPED_TEST(InertiaTyped, AddShiftedOfItselfIsThisPlusItsShift)
{
    // this.add_shifted(this, r): the argument aliases the accumulator.
    using Scalar = TypeParam;
    std::mt19937 rng(45);
    for (int trial = 0; trial < 10; ++trial) {
        const Vector3d r = rounded<Scalar>(random_vector(rng, 0.6));
        const Matrix6d g = literal_grasp_map(r);
        const SpatialInertia<double> spatial = random_spatial_inertia<Scalar>(rng, 0.4);
        SpatialInertia<Scalar> self = spatial.template cast<Scalar>();
        self.add_shifted(self, r.cast<Scalar>());
        EXPECT_LT(relative_error(dense(self), (dense(spatial) + g * dense(spatial) * g.transpose()).eval()), 16.0 * epsilon<Scalar>());
        const Matrix6d general = random_spd6<Scalar>(rng);
        ArticulatedInertia<Scalar> general_self(general.cast<Scalar>());
        general_self.add_shifted(general_self, r.cast<Scalar>());
        EXPECT_LT(relative_error(dense(general_self), (general + g * general * g.transpose()).eval()), 16.0 * epsilon<Scalar>());
    }
}

TYPED_TEST(InertiaTyped, ShiftsComposeInvertAndKeepTheCentralInertia)
{
    using Scalar = TypeParam;
    using Vector3s = coopdyn::Vector3<Scalar>;
    std::mt19937 rng(46);
    Worst worst{"worst_relative_error_over_eps"};
    const double tolerance = 32.0 * epsilon<Scalar>();
    for (int trial = 0; trial < 40; ++trial) {
        const SpatialInertia<Scalar> inertia = random_spatial_inertia<Scalar>(rng, 0.5).template cast<Scalar>();
        const ArticulatedInertia<Scalar> general(random_spd6<Scalar>(rng).template cast<Scalar>());
        const Vector3s a = random_vector(rng, 0.6).cast<Scalar>();
        const Vector3s b = random_vector(rng, 0.9).cast<Scalar>();
        const Vector3s sum = a + b;
        const Vector3s minus_a = -a;
        const auto check = [&](const Matrix6d& value, const Matrix6d& reference) {
            const double error = relative_error(value, reference);
            worst(error / epsilon<Scalar>());
            EXPECT_LT(error, tolerance);
        };
        // G(b) G(a) = G(a + b), G(-a) G(a) = I.
        check(dense(inertia.shifted(a).shifted(b)), dense(inertia.shifted(sum)));
        check(dense(inertia.shifted(a).shifted(minus_a)), dense(inertia));
        check(dense(general.shifted(a).shifted(b)), dense(general.shifted(sum)));
        check(dense(general.shifted(a).shifted(minus_a)), dense(general));
        EXPECT_EQ(dense(inertia.shifted(Vector3s::Zero())), dense(inertia));

        // Mass is invariant, the centre moves by r, the central inertia does not change.
        const SpatialInertia<Scalar> moved = inertia.shifted(a);
        EXPECT_EQ(moved.mass(), inertia.mass());
        EXPECT_LT((moved.centre() - inertia.centre() - a).norm(), tolerance * 2.0);
        EXPECT_LT(relative_error(moved.rotational_about_centre().matrix(), inertia.rotational_about_centre().matrix()),
                  8.0 * tolerance);

        // Kinetic energy does not depend on the point: 1/2 xdot^T (G M G^T) xdot = 1/2 (G^T xdot)^T M (G^T xdot).
        const Motion<Scalar> twist = Motion<Scalar>::from(random_six(rng, 1.0, 2.0).cast<Scalar>());
        const double energy = static_cast<double>(inertia.kinetic_energy(twist.at_point(a)));
        EXPECT_NEAR(static_cast<double>(moved.kinetic_energy(twist)), energy, tolerance * energy * 4.0);
        const double general_energy = static_cast<double>(general.kinetic_energy(twist.at_point(a)));
        EXPECT_NEAR(static_cast<double>(general.shifted(a).kinetic_energy(twist)), general_energy, tolerance * general_energy * 4.0);
        // And the momentum transforms as a force: (G M G^T) xdot = G (M (G^T xdot)).
        const Force<Scalar> momentum = (inertia * twist.at_point(a)).shifted(a);
        EXPECT_LT((dense(moved * twist) - dense(momentum)).norm(), tolerance * 4.0 * dense(momentum).norm());
    }
}

TYPED_TEST(InertiaTyped, RotatedIsTheLiteralBlockDiagonalCongruence)
{
    using Scalar = TypeParam;
    std::mt19937 rng(47);
    Worst worst{"worst_relative_error_over_eps"};
    for (int trial = 0; trial < 30; ++trial) {
        const Matrix3d rotation = rounded<Scalar>(random_rotation(rng));
        const coopdyn::Matrix3<Scalar> rotation_s = rotation.cast<Scalar>();
        const coopdyn::Matrix3<Scalar> back = rotation_s.transpose();
        const Matrix6d block = literal_block_rotation(rotation);
        const auto check = [&](const Matrix6d& value, const Matrix6d& reference, double factor) {
            const double error = relative_error(value, reference);
            worst(error / epsilon<Scalar>());
            EXPECT_LT(error, factor * epsilon<Scalar>());
        };
        const SpatialInertia<double> spatial = random_spatial_inertia<Scalar>(rng, 0.5);
        const SpatialInertia<Scalar> spatial_s = spatial.template cast<Scalar>();
        check(dense(spatial_s.rotated(rotation_s)), block * dense(spatial) * block.transpose(), 24.0);
        check(dense(spatial_s.rotated(rotation_s).rotated(back)), dense(spatial), 48.0);
        const CentralInertia<double> central = random_central_inertia<Scalar>(rng);
        const CentralInertia<Scalar> central_s = central.template cast<Scalar>();
        check(dense(central_s.rotated(rotation_s)), block * dense(central) * block.transpose(), 24.0);
        check(dense(central_s.rotated(rotation_s).rotated(back)), dense(central), 48.0);
        const Matrix6d general = random_spd6<Scalar>(rng, 2.0);
        const ArticulatedInertia<Scalar> general_s(general.cast<Scalar>());
        check(dense(general_s.rotated(rotation_s)), block * general * block.transpose(), 24.0);
        check(dense(general_s.rotated(rotation_s).rotated(back)), general, 32.0);
    }
    // A point-mass body rotated about the reference point has the rotated inertia.
    const PointMassBody body = random_body(rng, 6, Vector3d(0.5, 0.2, 0.1), Vector3d(0.3, -0.1, 0.2));
    const Matrix3d rotation = random_rotation(rng);
    PointMassBody turned = body;
    for (Vector3d& point : turned.points) {
        point = rotation * point;
    }
    const SpatialInertia<double> inertia(SpatialInertia<double>::from_centre(body.mass(), body.centre(),
                                                                             Symmetric3<double>(body.rotational_about_centre())));
    EXPECT_LT(relative_error(dense(inertia.rotated(rotation)), turned.inertia_about(Vector3d::Zero())), 16.0 * epsilon<double>());
}

TYPED_TEST(InertiaTyped, ProductsAndSumsMatchDenseMatrices)
{
    using Scalar = TypeParam;
    std::mt19937 rng(48);
    Worst worst{"worst_relative_error_over_eps"};
    const double tolerance = 16.0 * epsilon<Scalar>();
    for (int trial = 0; trial < 30; ++trial) {
        const SpatialInertia<double> spatial = random_spatial_inertia<Scalar>(rng, 0.5);
        const CentralInertia<double> central = random_central_inertia<Scalar>(rng);
        const Matrix6d general = random_spd6<Scalar>(rng, 2.0);
        const SpatialInertia<Scalar> spatial_s = spatial.template cast<Scalar>();
        const CentralInertia<Scalar> central_s = central.template cast<Scalar>();
        const ArticulatedInertia<Scalar> general_s(general.cast<Scalar>());
        const Vector6d twist = rounded<Scalar>(random_six(rng, 1.0, 3.0));
        const Vector3d translation = rounded<Scalar>(random_vector(rng, 2.0));
        Vector6d translation_only;
        translation_only << translation, Vector3d::Zero();
        const Motion<Scalar> motion = Motion<Scalar>::from(twist.cast<Scalar>());
        const coopdyn::Vector3<Scalar> translation_s = translation.cast<Scalar>();

        const auto check_product = [&](const auto& inertia, const Matrix6d& m) {
            const double scale = m.norm();
            const double product_error = (dense(inertia * motion) - m * twist).norm() / (scale * twist.norm());
            const double translation_error =
                (dense(inertia.apply_translation(translation_s)) - m * translation_only).norm() / (scale * translation.norm());
            const double energy = 0.5 * twist.dot(m * twist);
            const double energy_error = std::abs(static_cast<double>(inertia.kinetic_energy(motion)) - energy) / (scale * twist.squaredNorm());
            worst(std::max({product_error, translation_error, energy_error}) / epsilon<Scalar>());
            EXPECT_LT(product_error, tolerance);
            EXPECT_LT(translation_error, tolerance);
            EXPECT_LT(energy_error, tolerance);
        };
        check_product(spatial_s, dense(spatial));
        check_product(central_s, dense(central));
        check_product(general_s, general);

        // Sums and differences.
        const SpatialInertia<double> other = random_spatial_inertia<Scalar>(rng, 0.2);
        const SpatialInertia<Scalar> other_s = other.template cast<Scalar>();
        EXPECT_LT(relative_error(dense(spatial_s + other_s), (dense(spatial) + dense(other)).eval()), tolerance);
        SpatialInertia<Scalar> accumulated = spatial_s;
        accumulated += other_s;
        EXPECT_EQ(dense(accumulated), dense(spatial_s + other_s));
        accumulated -= other_s;
        EXPECT_LT(relative_error(dense(accumulated), dense(spatial)), 4.0 * tolerance);
        EXPECT_LT(relative_error(dense(general_s + ArticulatedInertia<Scalar>(spatial_s)), (general + dense(spatial)).eval()), tolerance);
        ArticulatedInertia<Scalar> general_accumulated = general_s;
        general_accumulated += spatial_s;
        EXPECT_LT(relative_error(dense(general_accumulated), (general + dense(spatial)).eval()), tolerance);
        general_accumulated += general_s;
        EXPECT_LT(relative_error(dense(general_accumulated), (2.0 * general + dense(spatial)).eval()), tolerance);
    }
}

TYPED_TEST(InertiaTyped, CastsRoundEachEntryOnce)
{
    using Scalar = TypeParam;
    std::mt19937 rng(49);
    const SpatialInertia<double> spatial = random_spatial_inertia<double>(rng, 0.5);
    const CentralInertia<double> central = random_central_inertia<double>(rng);
    const ArticulatedInertia<double> general(random_spd6<double>(rng));
    EXPECT_EQ(dense(spatial.template cast<Scalar>()), rounded<Scalar>(dense(spatial)));
    EXPECT_EQ(dense(central.template cast<Scalar>()), rounded<Scalar>(dense(central)));
    EXPECT_EQ(dense(general.template cast<Scalar>()), rounded<Scalar>(dense(general)));
    // Widening to double is exact. (From inputs already representable in Scalar: g++ 12.2 at -O2
    // folds an inlined double -> float -> double round trip, spatial.cast<float>().cast<double>(),
    // to the identity on some SLP-vectorised lanes, so the float object and its widened copy
    // would disagree. A compiler bug, not coopdyn's.)
    const SpatialInertia<Scalar> narrow = random_spatial_inertia<Scalar>(rng, 0.5).template cast<Scalar>();
    EXPECT_EQ(dense(narrow.template cast<double>()), dense(narrow));
    const CentralInertia<Scalar> narrow_central = random_central_inertia<Scalar>(rng).template cast<Scalar>();
    EXPECT_EQ(dense(narrow_central.template cast<double>()), dense(narrow_central));
    const ArticulatedInertia<Scalar> narrow_general(random_spd6<Scalar>(rng).template cast<Scalar>());
    EXPECT_EQ(dense(narrow_general.template cast<double>()), dense(narrow_general));
}

// --- Solve -------------------------------------------------------------------------------------------

TYPED_TEST(InertiaTyped, SolveResidualIsAtRoundingForWellConditionedInertias)
{
    // Well-conditioned: unit-scale mass, radius of gyration ~ 1 and offsets <= 0.5 (cond(M) < 30).
    using Scalar = TypeParam;
    std::mt19937 rng(50);
    Worst worst_residual{"worst_relative_residual_over_eps"};
    Worst worst_error{"worst_error_vs_ldlt_over_eps"};
    double largest_condition = 0.0;
    for (int trial = 0; trial < 60; ++trial) {
        const Vector6d wrench = rounded<Scalar>(random_six(rng, 5.0, 2.0));
        const Force<Scalar> force = Force<Scalar>::from(wrench.cast<Scalar>());
        const auto check = [&](const auto& inertia, const char* what) {
            const Matrix6d m = dense(inertia);
            const Vector6d solution = dense(inertia.solve(force));
            const double residual = (m * solution - wrench).norm() / wrench.norm();
            const Vector6d reference = m.ldlt().solve(wrench);
            const double error = (solution - reference).norm() / reference.norm();
            const Eigen::Matrix<double, 6, 1> eigenvalues = Eigen::SelfAdjointEigenSolver<Matrix6d>(m).eigenvalues();
            largest_condition = std::max(largest_condition, eigenvalues(5) / eigenvalues(0));
            worst_residual(residual / epsilon<Scalar>());
            worst_error(error / epsilon<Scalar>());
            EXPECT_LT(residual, 16.0 * epsilon<Scalar>()) << what;
            EXPECT_LT(error, 64.0 * epsilon<Scalar>()) << what;
        };
        std::uniform_real_distribution<double> unit_mass(0.7, 1.5);
        const double mass = round_to<Scalar>(unit_mass(rng));
        const Matrix3d about_centre = random_rigid_body_inertia(rng, mass, 0.6, 1.2);
        const Vector3d first_moment = rounded<Scalar>(Vector3d(mass * random_vector(rng, 0.5)));
        const Matrix3d rotational = about_centre + literal_skew(first_moment) * literal_skew(first_moment).transpose() / mass;
        const SpatialInertia<double> spatial(mass, first_moment, round_symmetric<Scalar>(Symmetric3<double>(rotational)));
        check(spatial.template cast<Scalar>(), "SpatialInertia");
        check(CentralInertia<double>(mass, round_symmetric<Scalar>(Symmetric3<double>(about_centre))).template cast<Scalar>(),
              "CentralInertia");
        check(ArticulatedInertia<Scalar>(random_spd6<Scalar>(rng, 1.0, 2.0).template cast<Scalar>()), "ArticulatedInertia");
    }
    EXPECT_LT(largest_condition, 30.0);
}

TYPED_TEST(InertiaTyped, SolveErrorIsBoundedByConditionForPhysicalInertias)
{
    // Physical scales: 0.5-20 kg, radii of gyration 2 cm - 0.5 m, offsets up to 1 m (cond(M) up to
    // ~1e4). Forward error against LDLT relative to cond(M) eps, and M solve(M x) = M x.
    using Scalar = TypeParam;
    std::mt19937 rng(51);
    Worst worst_ratio{"worst_error_over_condition_eps"};
    Worst worst_round_trip{"worst_round_trip_over_condition_eps"};
    double largest_condition = 0.0;
    for (const double offset : {0.01, 0.2, 1.0}) {
        for (int trial = 0; trial < 40; ++trial) {
            const SpatialInertia<double> spatial = random_spatial_inertia<Scalar>(rng, offset, 0.02, 0.5);
            const Matrix6d m = dense(spatial);
            const Eigen::Matrix<double, 6, 1> eigenvalues = Eigen::SelfAdjointEigenSolver<Matrix6d>(m).eigenvalues();
            const double condition = eigenvalues(5) / eigenvalues(0);
            largest_condition = std::max(largest_condition, condition);
            const Vector6d wrench = rounded<Scalar>(random_six(rng, 20.0, 2.0));
            const Vector6d solution = dense(spatial.template cast<Scalar>().solve(Force<Scalar>::from(wrench.cast<Scalar>())));
            const Vector6d reference = m.ldlt().solve(wrench);
            const double ratio = (solution - reference).norm() / reference.norm() / (condition * epsilon<Scalar>());
            worst_ratio(ratio);
            EXPECT_LT(ratio, 8.0) << "offset " << offset << " condition " << condition;
            const Vector6d twist = rounded<Scalar>(random_six(rng, 1.0, 1.0));
            const Motion<Scalar> motion = Motion<Scalar>::from(twist.cast<Scalar>());
            const SpatialInertia<Scalar> inertia_s = spatial.template cast<Scalar>();
            const double round_trip = (dense(inertia_s.solve(inertia_s * motion)) - twist).norm() / twist.norm() /
                                      (condition * epsilon<Scalar>());
            worst_round_trip(round_trip);
            EXPECT_LT(round_trip, 8.0);
        }
    }
    EXPECT_GT(largest_condition, 1e3);
}

// --- Autodiff: derivatives with respect to the offset r --------------------------------------------

/// r as three seeded autodiff variables.
coopdyn::Vector3<AutoDiff> seeded(const Vector3d& r)
{
    coopdyn::Vector3<AutoDiff> result;
    for (int k = 0; k < 3; ++k) {
        result(k) = AutoDiff(r(k), 3, k);
    }
    return result;
}

/// d value(i) / d r(k), zero where autodiff carried no derivative.
template <int Rows> Eigen::Matrix<double, Rows, 3> jacobian_of(const Eigen::Matrix<AutoDiff, Rows, 1>& value)
{
    Eigen::Matrix<double, Rows, 3> result = Eigen::Matrix<double, Rows, 3>::Zero();
    for (int i = 0; i < Rows; ++i) {
        if (value(i).derivatives().size() == 3) {
            result.row(i) = value(i).derivatives().transpose();
        }
    }
    return result;
}

/// Central differences of f: R^3 -> R^6 at r.
template <typename F> Eigen::Matrix<double, 6, 3> central_differences(const F& f, const Vector3d& r, double h)
{
    Eigen::Matrix<double, 6, 3> result;
    for (int k = 0; k < 3; ++k) {
        result.col(k) = (f(Vector3d(r + h * Vector3d::Unit(k))) - f(Vector3d(r - h * Vector3d::Unit(k)))) / (2.0 * h);
    }
    return result;
}

TEST(InertiaAutodiff, SolveOfTheShiftedInertiaMatchesCentralDifferences)
{
    // a(r) = (G(r) M G(r)^T)^-1 h for the three inertia types, d a / d r.
    std::mt19937 rng(52);
    Worst worst{"worst_relative_error_vs_central_differences"};
    for (int trial = 0; trial < 10; ++trial) {
        const SpatialInertia<double> spatial = random_spatial_inertia<double>(rng, 0.3);
        const CentralInertia<double> central = random_central_inertia<double>(rng);
        const ArticulatedInertia<double> general(random_spd6<double>(rng, 2.0));
        const Vector6d wrench = random_six(rng, 10.0, 2.0);
        const Vector3d r = random_vector(rng, 0.5);
        const Force<AutoDiff> force_ad = Force<AutoDiff>::from(wrench.cast<AutoDiff>());
        const coopdyn::Vector3<AutoDiff> r_ad = seeded(r);
        const auto check = [&](const auto& inertia, const auto& inertia_ad, const char* what) {
            const Eigen::Matrix<AutoDiff, 6, 1> solution = inertia_ad.shifted(r_ad).solve(force_ad).vector();
            const auto f = [&](const Vector3d& at) { return dense(inertia.shifted(at).solve(Force<double>::from(wrench))); };
            const Eigen::Matrix<double, 6, 3> difference = central_differences(f, r, 1e-6);
            const double error = (jacobian_of<6>(solution) - difference).norm() / difference.norm();
            worst(error);
            EXPECT_LT(error, 1e-7) << what;
            for (int i = 0; i < 6; ++i) {
                EXPECT_NEAR(solution(i).value(), f(r)(i), 1e-13 * f(r).norm()) << what;
            }
        };
        check(spatial, spatial.cast<AutoDiff>(), "SpatialInertia");
        check(central, central.cast<AutoDiff>(), "CentralInertia");
        check(general, general.cast<AutoDiff>(), "ArticulatedInertia");
    }
}

TEST(InertiaAutodiff, ShiftedMatrixDerivativeIsTheDerivativeOfTheCongruence)
{
    // d/dr_k [G(r) M G(r)^T] = E_k M G^T + G M E_k^T with E_k = [[0, 0], [S(e_k), 0]]; the
    // entries are quadratic in r, so central differences are exact up to rounding.
    std::mt19937 rng(53);
    Worst worst{"worst_relative_error_vs_central_differences"};
    for (int trial = 0; trial < 10; ++trial) {
        const SpatialInertia<double> spatial = random_spatial_inertia<double>(rng, 0.5);
        const Vector3d r = random_vector(rng, 0.7);
        const SpatialInertia<AutoDiff> shifted = spatial.cast<AutoDiff>().shifted(seeded(r));
        const Eigen::Matrix<AutoDiff, 6, 6> matrix = shifted.matrix();
        const Matrix6d m = dense(spatial);
        const Matrix6d g = literal_grasp_map(r);
        for (int k = 0; k < 3; ++k) {
            Matrix6d derivative;
            for (int j = 0; j < 6; ++j) {
                for (int i = 0; i < 6; ++i) {
                    derivative(i, j) = matrix(i, j).derivatives().size() == 3 ? matrix(i, j).derivatives()(k) : 0.0;
                }
            }
            Matrix6d e = Matrix6d::Zero();
            e.block<3, 3>(3, 0) = literal_skew(Vector3d::Unit(k));
            const Matrix6d exact = e * m * g.transpose() + g * m * e.transpose();
            EXPECT_LT(relative_error(derivative, exact), 1e-14) << "k " << k;
            const double h = 1e-4;
            const Matrix6d difference =
                (dense(spatial.shifted(Vector3d(r + h * Vector3d::Unit(k)))) - dense(spatial.shifted(Vector3d(r - h * Vector3d::Unit(k))))) /
                (2.0 * h);
            const double error = relative_error(derivative, difference);
            worst(error);
            EXPECT_LT(error, 1e-10) << "k " << k;
        }
    }
}

// --- Allocation ---------------------------------------------------------------------------------------

TEST(InertiaNoAllocation, DetectorIsArmedInThisExecutable)
{
    const allocation_counter::Allocations eigen = allocation_counter::count_allocations([] {
        Eigen::VectorXd values = Eigen::VectorXd::Ones(64);
        allocation_counter::sink = values.data();
    });
    EXPECT_GE(eigen.eigen, 1);
    const allocation_counter::Allocations plain = allocation_counter::count_allocations([] {
        std::vector<double> values(64, 1.0);
        allocation_counter::sink = values.data();
    });
    EXPECT_GE(plain.operator_new, 1);
}

template <typename Scalar> void expect_spatial_layer_does_not_allocate()
{
    using Vector3s = coopdyn::Vector3<Scalar>;
    std::mt19937 rng(54);
    const SpatialInertia<Scalar> spatial = random_spatial_inertia<Scalar>(rng, 0.4).template cast<Scalar>();
    const CentralInertia<Scalar> central = random_central_inertia<Scalar>(rng).template cast<Scalar>();
    const ArticulatedInertia<Scalar> general(random_spd6<Scalar>(rng).template cast<Scalar>());
    const Vector3s r = random_vector(rng, 0.5).cast<Scalar>();
    const coopdyn::Matrix3<Scalar> rotation = random_rotation(rng).cast<Scalar>();
    const Motion<Scalar> twist = Motion<Scalar>::from(random_six(rng, 1.0, 2.0).cast<Scalar>());
    const Force<Scalar> wrench = Force<Scalar>::from(random_six(rng, 5.0, 1.0).cast<Scalar>());
    const coopdyn::Quaternion<Scalar> orientation(random_rotation(rng).cast<Scalar>());
    // Stacks of K = 3 spatial vectors, sized before the counting window (dynamic and fixed).
    using DynamicStack = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
    const DynamicStack dynamic_in = DynamicStack::Constant(18, 12, Scalar(0.5));
    DynamicStack dynamic_out = DynamicStack::Zero(18, 12);
    const Eigen::Matrix<Scalar, Eigen::Dynamic, 1> dynamic_vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>::Ones(18);
    Eigen::Matrix<Scalar, Eigen::Dynamic, 1> dynamic_vector_out = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>::Zero(18);
    Eigen::Matrix<Scalar, 3, Eigen::Dynamic> dynamic_rotations(3, 9);
    dynamic_rotations << rotation, rotation.transpose(), rotation;
    Eigen::Matrix<Scalar, 18, 12> fixed_stack = Eigen::Matrix<Scalar, 18, 12>::Constant(Scalar(0.25));
    const Eigen::Matrix<Scalar, 3, 9> fixed_rotations = dynamic_rotations;
    Scalar checksum(0);
    const allocation_counter::Allocations allocations = allocation_counter::count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            // Symmetric3
            Symmetric3<Scalar> s = spatial.rotational();
            s.add_skew_square(Scalar(2), r);
            s += Symmetric3<Scalar>::skew_square(r);
            s = s.rotated(rotation);
            checksum += s.solve(r).sum() + s.inverse().trace() + s.determinant() + (s * r).sum() + s.matrix().sum();
            checksum += s.is_positive_definite() ? Scalar(1) : Scalar(0);
            // Motion / Force
            const Motion<Scalar> moved = twist.at_point(r) + twist;
            const Force<Scalar> shifted = wrench.shifted(r) - wrench;
            checksum += moved.dot(shifted) + (Scalar(2) * moved).vector().sum() + (-shifted).vector().sum();
            checksum += coopdyn::centripetal_acceleration(r, twist.angular).sum();
            // Rotations of spatial vectors and of stacks
            checksum += twist.rotated(rotation).dot(wrench.rotated_back(rotation)) +
                        twist.rotated_back(rotation).linear.sum() + wrench.rotated(rotation).angular.sum();
            coopdyn::rotate_stack(rotation, dynamic_in, dynamic_out);
            coopdyn::rotate_stack_back(rotation, dynamic_out, dynamic_out);
            coopdyn::rotate_stack_per_block(dynamic_rotations, dynamic_vector, dynamic_vector_out);
            coopdyn::rotate_stack_per_block_back(dynamic_rotations, dynamic_out, dynamic_out);
            coopdyn::rotate_stack(rotation, fixed_stack, fixed_stack);
            coopdyn::rotate_stack_per_block_back(fixed_rotations, fixed_stack, fixed_stack);
            checksum += dynamic_out.sum() + dynamic_vector_out.sum() + fixed_stack.sum();
            checksum += s.rotated_back(rotation).trace() + Symmetric3<Scalar>::rotated_diagonal(r, rotation).trace();
            // SpatialInertia
            SpatialInertia<Scalar> composite = SpatialInertia<Scalar>::from_centre(spatial.mass(), r, s);
            composite.add_shifted(spatial, r);
            composite.add_shifted(central, r);
            composite += spatial.shifted(r).rotated(rotation);
            composite = composite + central.shifted(r);
            checksum += composite.solve(wrench).vector().sum() + (composite * twist).vector().sum();
            checksum += composite.kinetic_energy(twist) + composite.apply_translation(r).vector().sum();
            checksum += composite.rotational_about_centre().trace() + composite.centre().sum() + composite.matrix().sum();
            // CentralInertia
            checksum += central.solve(wrench).vector().sum() + (central * twist).vector().sum() + central.kinetic_energy(twist);
            checksum += central.rotated(rotation).rotational().trace() + central.apply_translation(r).vector().sum();
            // ArticulatedInertia
            ArticulatedInertia<Scalar> articulated = general.shifted(r);
            articulated.add_shifted(general, r);
            articulated.add_shifted(spatial, r);
            articulated.add_shifted(central, r);
            articulated += spatial;
            articulated = articulated.rotated(rotation) + general;
            checksum += articulated.solve(wrench).vector().sum() + (articulated * twist).vector().sum();
            checksum += articulated.kinetic_energy(twist) + articulated.apply_translation(r).vector().sum() + articulated.matrix().sum();
            // Quaternions
            checksum += coopdyn::quaternion_log(orientation).sum() + coopdyn::quaternion_exp(r).w();
        }
    });
    EXPECT_EQ(allocations.operator_new, 0);
    EXPECT_EQ(allocations.eigen, 0);
    EXPECT_TRUE(std::isfinite(static_cast<double>(checksum)));
}

TEST(InertiaNoAllocation, SpatialLayerAllocatesNothingDouble) { expect_spatial_layer_does_not_allocate<double>(); }
TEST(InertiaNoAllocation, SpatialLayerAllocatesNothingFloat) { expect_spatial_layer_does_not_allocate<float>(); }

}  // namespace
