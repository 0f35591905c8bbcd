// Tests of coopdyn/numerics/matrix_exponential.hpp against references it was not derived from
// (it is a Pade approximant with scaling and squaring):
// - closed forms: Rodrigues' formula for a rotation generator, the finite series of a nilpotent
//   matrix, diagonal matrices, the 2x2 damped oscillator exp(A t) = e^{s t} (cos(w t) I +
//   sin(w t) / w (A - s I));
// - eigen-decompositions: A = Q diag(l) Q^T (symmetric) and A = V diag(l) V^-1 (non-normal);
// - a Taylor series summed in long double for moderate norms;
// - identities: exp(A (s + t)) = exp(A s) exp(A t) and exp(A) exp(-A) = I.
// Sizes 1 .. 12 and norms from 1e-3 to 100, so that every Pade degree (3, 5, 7, 9, 13) and the
// squaring are exercised. Every error printed is a measurement; every bound is a few times it.
#include "coopdyn/numerics/matrix_exponential.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace {

using coopdyn::numerics::matrix_exponential;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;

MatrixXd random_matrix(Index rows, Index cols, std::mt19937& rng)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    MatrixXd result(rows, cols);
    for (Index k = 0; k < result.size(); ++k) {
        result(k) = uniform(rng);
    }
    return result;
}

double one_norm(const MatrixXd& a) { return a.cwiseAbs().colwise().sum().maxCoeff(); }

double relative_difference(const MatrixXd& value, const MatrixXd& reference)
{
    return (value - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

/// exp(a) by its Taylor series in long double, summed until the terms vanish (a's norm <= 8:
/// the largest term is below 8^8 / 8! = 416, so about 3 of long double's 19 digits are lost).
MatrixXd taylor_exponential(const MatrixXd& a)
{
    const LongMatrix x = a.cast<long double>();
    LongMatrix term = LongMatrix::Identity(a.rows(), a.cols());
    LongMatrix sum = term;
    for (int order = 1; order < 200; ++order) {
        term = (term * x / static_cast<long double>(order)).eval();
        sum += term;
        if (term.cwiseAbs().maxCoeff() < 1e-30L) {
            break;
        }
    }
    return sum.cast<double>();
}

TEST(MatrixExponential, RodriguesFormulaForRotationGenerators)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle_distribution(1e-3, 40.0);  // up to several turns
    double worst = 0.0;
    for (int trial = 0; trial < 60; ++trial) {
        const Eigen::Vector3d axis = random_matrix(3, 1, rng).normalized();
        const double angle = angle_distribution(rng);
        Eigen::Matrix3d generator;
        generator << 0, -axis(2), axis(1), axis(2), 0, -axis(0), -axis(1), axis(0), 0;
        const MatrixXd exponential = matrix_exponential(MatrixXd(angle * generator));
        const Eigen::Matrix3d rodrigues = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
        // exp is well conditioned on skew matrices only up to the angle's own rounding: allow eps * angle.
        worst = std::max(worst, (exponential - rodrigues).cwiseAbs().maxCoeff() / std::max(1.0, angle));
    }
    std::printf("[ measured ] exp(theta S(u)) vs Rodrigues: worst %.2e (per radian)\n", worst);
    EXPECT_LT(worst, 2e-15);
}

TEST(MatrixExponential, NilpotentMatricesGiveTheirFiniteSeries)
{
    // A strictly upper triangular n x n matrix N has N^n = 0: exp(N) = sum_{k < n} N^k / k!.
    std::mt19937 rng(5);
    double worst = 0.0;
    for (Index size : {2, 3, 5, 8, 12}) {
        for (double scale : {0.01, 1.0, 4.0}) {
            const MatrixXd nilpotent =
                scale * MatrixXd(random_matrix(size, size, rng).triangularView<Eigen::StrictlyUpper>());
            MatrixXd term = MatrixXd::Identity(size, size);
            MatrixXd series = term;
            for (Index k = 1; k < size; ++k) {
                term = (term * nilpotent / static_cast<double>(k)).eval();
                series += term;
            }
            worst = std::max(worst, relative_difference(matrix_exponential(nilpotent), series));
        }
    }
    std::printf("[ measured ] nilpotent vs finite series: worst relative %.2e\n", worst);
    EXPECT_LT(worst, 4e-15);
}

TEST(MatrixExponential, DiagonalMatricesExponentiateTheirEntries)
{
    const VectorXd diagonal = (VectorXd(6) << -50.0, -1e-3, 0.0, 0.7, 20.0, 90.0).finished();
    const MatrixXd exponential = matrix_exponential(MatrixXd(diagonal.asDiagonal()));
    // e^x has relative condition number |x|, and the 2^s squarings that the largest entry needs
    // (s = 5 here) amplify the rounding of every entry: errors are measured per (1 + |A|_1).
    double worst = 0.0;
    for (Index k = 0; k < diagonal.size(); ++k) {
        worst = std::max(worst, std::abs(exponential(k, k) / std::exp(diagonal(k)) - 1.0) /
                                    (1.0 + diagonal.cwiseAbs().maxCoeff()));
    }
    const double off_diagonal = (exponential - MatrixXd(exponential.diagonal().asDiagonal())).cwiseAbs().maxCoeff();
    std::printf("[ measured ] diagonal: worst relative %.2e per (1 + |A|_1), off-diagonal %.1e\n", worst, off_diagonal);
    EXPECT_LT(worst, 2e-15);
    EXPECT_EQ(off_diagonal, 0.0);
}

TEST(MatrixExponential, DampedOscillatorClosedForm)
{
    // A = [[0, 1], [-k/m, -d/m]] times T: the identification's matrix. Eigenvalues s +- i w.
    double worst = 0.0;
    for (const auto& [m, d, k] : {std::array<double, 3>{21.75, 360.0, 600.0}, std::array<double, 3>{2.0, 4.0, 800.0},
                                  std::array<double, 3>{1.0, 0.1, 1e4}}) {
        for (double t : {1e-3, 0.1, 2.0}) {
            Eigen::Matrix2d a;
            a << 0.0, 1.0, -k / m, -d / m;
            const double s = -d / (2.0 * m);
            const double discriminant = k / m - s * s;
            Eigen::Matrix2d reference;
            const Eigen::Matrix2d shifted = a - s * Eigen::Matrix2d::Identity();
            if (discriminant > 0.0) {  // underdamped: sin(w t) / w
                const double w = std::sqrt(discriminant);
                reference = std::exp(s * t) * (std::cos(w * t) * Eigen::Matrix2d::Identity() + std::sin(w * t) / w * shifted);
            } else {  // overdamped: sinh(g t) / g
                const double g = std::sqrt(-discriminant);
                reference = std::exp(s * t) * (std::cosh(g * t) * Eigen::Matrix2d::Identity() + std::sinh(g * t) / g * shifted);
            }
            // Conditioning grows with |A t| (up to 2e4 here): errors are measured per (1 + |A t|_1).
            worst = std::max(worst, relative_difference(matrix_exponential(MatrixXd(a * t)), reference) /
                                        (1.0 + one_norm(a * t)));
        }
    }
    std::printf("[ measured ] damped oscillator vs closed form: worst relative %.2e per (1 + |A t|_1)\n", worst);
    EXPECT_LT(worst, 5e-15);
}

TEST(MatrixExponential, EigenDecompositions)
{
    std::mt19937 rng(17);
    double worst_symmetric = 0.0;
    double worst_general = 0.0;
    for (Index size : {1, 2, 4, 8, 12}) {
        for (double scale : {1e-3, 0.1, 0.8, 2.0, 5.0, 30.0}) {
            // Symmetric: A = Q diag(l) Q^T, exp(A) = Q diag(e^l) Q^T (perfectly conditioned).
            const MatrixXd b = random_matrix(size, size, rng);
            const MatrixXd symmetric = scale * (b + b.transpose()) / 2.0;
            const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(symmetric);
            const MatrixXd reference = eigen.eigenvectors() * eigen.eigenvalues().array().exp().matrix().asDiagonal() *
                                       eigen.eigenvectors().transpose();
            worst_symmetric = std::max(worst_symmetric, relative_difference(matrix_exponential(symmetric), reference));

            // Non-normal: A = V diag(l) V^-1 with V = I + E/2 (condition number a few units).
            const MatrixXd v = MatrixXd::Identity(size, size) + 0.5 * random_matrix(size, size, rng) / std::sqrt(static_cast<double>(size));
            const VectorXd eigenvalues = scale * random_matrix(size, 1, rng);
            const Eigen::PartialPivLU<MatrixXd> v_lu(v);
            const MatrixXd general = v * eigenvalues.asDiagonal() * v_lu.inverse();
            const MatrixXd general_reference = v * eigenvalues.array().exp().matrix().asDiagonal() * v_lu.inverse();
            const double condition = v.norm() * v_lu.inverse().norm();
            worst_general = std::max(worst_general, relative_difference(matrix_exponential(general), general_reference) /
                                                        (condition * std::max(1.0, one_norm(general))));
        }
    }
    std::printf("[ measured ] vs eigen-decomposition: symmetric worst relative %.2e; non-normal worst relative "
                "%.2e per (cond(V) max(1, |A|_1))\n",
                worst_symmetric, worst_general);
    EXPECT_LT(worst_symmetric, 1e-12);
    EXPECT_LT(worst_general, 2e-15);
}

TEST(MatrixExponential, LongDoubleTaylorSeries)
{
    // Norms around every Pade threshold theta_m (0.015, 0.25, 0.95, 2.1, 5.4) and beyond.
    std::mt19937 rng(23);
    double worst = 0.0;
    for (Index size : {1, 3, 6, 12}) {
        for (double norm : {1e-3, 0.014, 0.016, 0.24, 0.26, 0.9, 1.0, 2.0, 2.2, 5.3, 5.5, 8.0}) {
            MatrixXd a = random_matrix(size, size, rng);
            a *= norm / one_norm(a);
            const MatrixXd reference = taylor_exponential(a);
            // exp's condition number is at most e^{|A|} / |exp(A)|-ish; normalise by |A|_1 + 1.
            worst = std::max(worst, relative_difference(matrix_exponential(a), reference) / (1.0 + norm));
        }
    }
    std::printf("[ measured ] vs long double Taylor series: worst relative %.2e per (1 + |A|_1)\n", worst);
    EXPECT_LT(worst, 2e-14);
}

TEST(MatrixExponential, SemigroupAndInverse)
{
    std::mt19937 rng(3);
    double worst_semigroup = 0.0;
    double worst_inverse = 0.0;
    for (Index size : {2, 4, 8}) {
        for (double scale : {0.1, 1.0, 3.0, 10.0}) {
            for (int trial = 0; trial < 5; ++trial) {
                const MatrixXd a = scale * random_matrix(size, size, rng);
                const MatrixXd whole = matrix_exponential(MatrixXd(0.7 * a));
                const MatrixXd split = matrix_exponential(MatrixXd(0.3 * a)) * matrix_exponential(MatrixXd(0.4 * a));
                worst_semigroup = std::max(worst_semigroup, relative_difference(split, whole));
                const MatrixXd product = matrix_exponential(a) * matrix_exponential(MatrixXd(-a));
                // exp(A) exp(-A) loses |exp(A)| |exp(-A)| eps to cancellation: normalise by it.
                const double amplification =
                    matrix_exponential(a).cwiseAbs().maxCoeff() * matrix_exponential(MatrixXd(-a)).cwiseAbs().maxCoeff();
                worst_inverse = std::max(worst_inverse, (product - MatrixXd::Identity(size, size)).cwiseAbs().maxCoeff() /
                                                            amplification);
            }
        }
    }
    std::printf("[ measured ] exp(0.7 A) vs exp(0.3 A) exp(0.4 A): worst relative %.2e; exp(A) exp(-A) - I: worst "
                "%.2e per |exp(A)| |exp(-A)|\n",
                worst_semigroup, worst_inverse);
    EXPECT_LT(worst_semigroup, 3e-14);
    EXPECT_LT(worst_inverse, 1e-14);
}

TEST(MatrixExponential, EdgeCases)
{
    EXPECT_EQ(matrix_exponential(MatrixXd(0, 0)).size(), 0);
    EXPECT_EQ(matrix_exponential(MatrixXd::Zero(3, 3)), MatrixXd::Identity(3, 3));
    EXPECT_NEAR(matrix_exponential(MatrixXd::Constant(1, 1, 1.0))(0, 0), std::exp(1.0), 2e-15);

    // Refusals are NaN, never a wrong finite number.
    MatrixXd infinite = MatrixXd::Identity(2, 2);
    infinite(0, 0) = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(matrix_exponential(infinite).array().isNaN().all());
    MatrixXd not_a_number = MatrixXd::Identity(2, 2);
    not_a_number(1, 0) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(matrix_exponential(not_a_number).array().isNaN().all());
    // Overflow is not silently finite.
    EXPECT_FALSE(matrix_exponential(MatrixXd::Constant(1, 1, 1000.0)).allFinite());
    // Underflow to zero is fine and finite.
    EXPECT_EQ(matrix_exponential(MatrixXd::Constant(1, 1, -1000.0))(0, 0), 0.0);
}

}  // namespace
