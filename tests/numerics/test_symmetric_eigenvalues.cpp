// Tests of coopdyn/numerics/symmetric_eigenvalues.hpp (cyclic Jacobi) against references it was
// not derived from:
// - matrices built with known spectra, A = Q diag(l) Q^T with Q from the QR of a random matrix:
//   distinct, clustered, repeated, indefinite, semi-definite (zero eigenvalues), graded 1e-8 .. 1;
// - Eigen's SelfAdjointEigenSolver (tridiagonal QR) on random symmetric matrices;
// - edge cases: 1 x 1, diagonal, zero, NaN.
// Fixed sizes 3 and 6 (the sizes the input checks use) and dynamic sizes 1 .. 10.
#include "coopdyn/numerics/symmetric_eigenvalues.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

using coopdyn::numerics::symmetric_eigenvalues;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double eps = std::numeric_limits<double>::epsilon();

MatrixXd random_orthogonal(Index n, std::mt19937& rng)
{
    std::normal_distribution<double> normal;
    MatrixXd g(n, n);
    for (Index k = 0; k < g.size(); ++k) {
        g(k) = normal(rng);
    }
    return Eigen::HouseholderQR<MatrixXd>(g).householderQ();
}

MatrixXd with_spectrum(const VectorXd& spectrum, std::mt19937& rng)
{
    const MatrixXd q = random_orthogonal(spectrum.size(), rng);
    return q * spectrum.asDiagonal() * q.transpose();
}

VectorXd sorted(VectorXd values)
{
    std::sort(values.data(), values.data() + values.size());
    return values;
}

// Weyl: building A in floating point perturbs it by about n eps ||A||, which moves every
// eigenvalue by as much; the solver adds a few eps ||A||_F.
double tolerance_for(const MatrixXd& a) { return 20.0 * static_cast<double>(a.rows()) * eps * a.norm(); }

TEST(SymmetricEigenvalues, KnownSpectraAtEverySize)
{
    std::mt19937 rng(20261125);
    std::uniform_real_distribution<double> uniform(-10.0, 10.0);
    double worst = 0.0;
    for (Index n = 1; n <= 10; ++n) {
        for (int trial = 0; trial < 20; ++trial) {
            VectorXd spectrum(n);
            for (Index k = 0; k < n; ++k) {
                spectrum(k) = uniform(rng);
            }
            if (trial % 4 == 1 && n > 1) {
                spectrum.tail(n / 2).setConstant(spectrum(0));  // repeated
            }
            if (trial % 4 == 2) {
                spectrum = spectrum.cwiseAbs();
                spectrum(0) = 0.0;  // semi-definite
            }
            if (trial % 4 == 3) {
                for (Index k = 0; k < n; ++k) {
                    spectrum(k) = std::pow(10.0, -8.0 * static_cast<double>(k) / static_cast<double>(n));  // graded
                }
            }
            const MatrixXd a = with_spectrum(spectrum, rng);
            const VectorXd computed = symmetric_eigenvalues(a);
            const double error = (computed - sorted(spectrum)).cwiseAbs().maxCoeff();
            ASSERT_LE(error, tolerance_for(a)) << "n = " << n << ", trial " << trial;
            worst = std::max(worst, error / a.norm());
        }
    }
    std::printf("largest error / ||A||_F against the built spectra: %.2e\n", worst);
}

TEST(SymmetricEigenvalues, AgreesWithEigensSolverAtTheFixedSizesTheChecksUse)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        Eigen::Matrix3d g3;
        Eigen::Matrix<double, 6, 6> g6;
        for (Index k = 0; k < 9; ++k) {
            g3(k) = uniform(rng);
        }
        for (Index k = 0; k < 36; ++k) {
            g6(k) = uniform(rng);
        }
        const Eigen::Matrix3d a3 = g3 + g3.transpose();
        const Eigen::Matrix<double, 6, 6> a6 = g6 * g6.transpose();  // positive semi-definite
        const Eigen::Vector3d e3 = symmetric_eigenvalues(a3);
        const Eigen::Matrix<double, 6, 1> e6 = symmetric_eigenvalues(a6);
        const Eigen::Vector3d r3 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(a3, Eigen::EigenvaluesOnly).eigenvalues();
        const Eigen::Matrix<double, 6, 1> r6 =
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(a6, Eigen::EigenvaluesOnly).eigenvalues();
        ASSERT_LE((e3 - r3).cwiseAbs().maxCoeff(), tolerance_for(a3)) << trial;
        ASSERT_LE((e6 - r6).cwiseAbs().maxCoeff(), tolerance_for(a6)) << trial;
    }
}

TEST(SymmetricEigenvalues, UsesTheSymmetricPartOnly)
{
    Eigen::Matrix2d a;
    a << 2.0, 1.0, 3.0, 2.0;  // symmetric part [[2, 2], [2, 2]]: eigenvalues 0 and 4
    const Eigen::Vector2d e = symmetric_eigenvalues(a);
    EXPECT_NEAR(e(0), 0.0, 4 * eps);
    EXPECT_NEAR(e(1), 4.0, 8 * eps);
}

TEST(SymmetricEigenvalues, EdgeCases)
{
    EXPECT_EQ(symmetric_eigenvalues(Eigen::Matrix<double, 1, 1>::Constant(-3.0))(0), -3.0);
    const Eigen::Vector3d diagonal = symmetric_eigenvalues(Eigen::Vector3d(3.0, -1.0, 2.0).asDiagonal().toDenseMatrix());
    EXPECT_EQ(diagonal, Eigen::Vector3d(-1.0, 2.0, 3.0));  // already diagonal: no rotation, exact
    EXPECT_EQ(symmetric_eigenvalues(Eigen::Matrix3d::Zero()), Eigen::Vector3d::Zero());
    Eigen::Matrix3d with_nan = Eigen::Matrix3d::Identity();
    with_nan(0, 1) = with_nan(1, 0) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(symmetric_eigenvalues(with_nan).hasNaN());
}

}  // namespace
