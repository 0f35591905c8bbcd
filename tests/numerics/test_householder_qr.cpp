// Tests of coopdyn/numerics/householder_qr.hpp against Eigen's HouseholderQR, which it was not
// derived from (the same convention, so the same R and Q to rounding), and against the defining
// identities:
// - R equals Eigen's R (same signs: both use makeHouseholder's R_kk = -sign(a_kk) |a_k|) and is
//   upper triangular with exact zeros below the diagonal;
// - the thin Q1 (m x n) and the full Q (m x m) equal Eigen's householderQ(), are orthonormal
//   (Q^T Q = I), and Q [R; 0] = A;
// - at the projected dynamics' shapes 6K x 6(K-1) (the internal-wrench basis, K = 2..5) and
//   Q x 6(K-1) (Jr^T, Q = 14 joints), square and thin shapes, fixed and dynamic sizes, float;
// - columns already triangular (tau = 0, H = I) and rank-deficient A (R_kk of rounding size,
//   Q still orthonormal and Q R = A).
// Seeded random matrices with entries in [-1, 1].
#include "coopdyn/numerics/householder_qr.hpp"

#include <Eigen/QR>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <random>

namespace {

using Eigen::Index;

template <typename Matrix> Matrix random_matrix(Index rows, Index cols, std::mt19937& rng)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Matrix m(rows, cols);
    for (Index i = 0; i < m.size(); ++i) {
        m(i) = static_cast<typename Matrix::Scalar>(uniform(rng));
    }
    return m;
}

struct Errors {
    double r = 0, q = 0, orthonormal = 0, product = 0;
    void include(const Errors& other)
    {
        r = std::max(r, other.r);
        q = std::max(q, other.q);
        orthonormal = std::max(orthonormal, other.orthonormal);
        product = std::max(product, other.product);
    }
};

/// Factor a (m x n, fixed or dynamic sizes as the Matrix type says) in place and compare with
/// Eigen's HouseholderQR in double. All errors relative to |A| (Frobenius).
template <int Rows, int Cols, typename Scalar = double> Errors check(const Eigen::MatrixXd& a_double)
{
    using Matrix = Eigen::Matrix<Scalar, Rows, Cols>;
    using Square = Eigen::Matrix<Scalar, Rows, Rows>;
    const Index m = a_double.rows(), n = a_double.cols();
    const Matrix a = a_double.cast<Scalar>();
    Matrix r = a;
    Matrix reflectors = Matrix::Constant(m, n, Scalar(7));  // overwritten entirely
    Eigen::Matrix<Scalar, Cols, 1> tau = Eigen::Matrix<Scalar, Cols, 1>::Zero(n);
    coopdyn::householder_qr_in_place(r, reflectors, tau);

    Matrix thin = Matrix::Zero(m, n);  // (zeroed only to quiet -Wmaybe-uninitialized: overwritten)
    Eigen::Matrix<Scalar, 1, Cols> thin_workspace = Eigen::Matrix<Scalar, 1, Cols>::Zero(1, n);
    coopdyn::householder_q(reflectors, tau, thin, thin_workspace);
    Square full = Square::Zero(m, m);
    Eigen::Matrix<Scalar, 1, Rows> full_workspace = Eigen::Matrix<Scalar, 1, Rows>::Zero(1, m);
    coopdyn::householder_q(reflectors, tau, full, full_workspace);

    const Eigen::MatrixXd a_reference = a.template cast<double>();
    const Eigen::HouseholderQR<Eigen::MatrixXd> reference(a_reference);
    const Eigen::MatrixXd reference_r = reference.matrixQR().triangularView<Eigen::Upper>();
    const Eigen::MatrixXd reference_q = reference.householderQ();
    const Eigen::MatrixXd r_double = r.template cast<double>();
    const Eigen::MatrixXd thin_double = thin.template cast<double>();
    const Eigen::MatrixXd full_double = full.template cast<double>();
    const double scale = a.template cast<double>().norm();

    // Below the diagonal R holds exact zeros.
    for (Index j = 0; j < n; ++j) {
        for (Index i = j + 1; i < m; ++i) {
            EXPECT_EQ(r(i, j), Scalar(0)) << m << " x " << n << " at (" << i << ", " << j << ")";
        }
    }
    Errors e;
    e.r = (r_double - reference_r.topRows(m)).norm() / scale;
    e.q = std::max((thin_double - reference_q.leftCols(n)).norm(), (full_double - reference_q).norm()) /
          std::sqrt(static_cast<double>(m));
    EXPECT_EQ(full_double.leftCols(n), thin_double) << "the thin Q is the full Q's leading columns";
    e.orthonormal = (full_double.transpose() * full_double - Eigen::MatrixXd::Identity(m, m)).norm();
    e.product = std::max((thin_double * r_double.topRows(n) - a.template cast<double>()).norm(),
                         (full_double * r_double - a.template cast<double>()).norm()) /
                scale;
    return e;
}

template <int Rows, int Cols, typename Scalar = double>
Errors check_random(Index m, Index n, int trials, std::mt19937& rng)
{
    Errors worst;
    for (int trial = 0; trial < trials; ++trial) {
        worst.include(check<Rows, Cols, Scalar>(random_matrix<Eigen::MatrixXd>(m, n, rng)));
        if (testing::Test::HasFailure()) {
            break;
        }
    }
    return worst;
}

void expect_small(const Errors& e, double tolerance, const char* label)
{
    std::printf("[ measured ] %s: R vs Eigen %.1e, Q vs Eigen %.1e, |Q^T Q - I| %.1e, |Q R - A|/|A| %.1e\n", label,
                e.r, e.q, e.orthonormal, e.product);
    EXPECT_LT(e.r, tolerance) << label;
    EXPECT_LT(e.q, tolerance) << label;
    EXPECT_LT(e.orthonormal, tolerance) << label;
    EXPECT_LT(e.product, tolerance) << label;
}

TEST(HouseholderQr, MatchesEigenAtTheProjectedDynamicsShapes)
{
    std::mt19937 rng(20261125);
    constexpr double tolerance = 1e-14;  // a few hundred eps at these sizes; measured ~1e-15
    // The internal-wrench basis: 6K x 6(K-1), fixed and dynamic.
    expect_small(check_random<12, 6>(12, 6, 50, rng), tolerance, "12 x 6 (K = 2) fixed");
    expect_small(check_random<18, 12>(18, 12, 50, rng), tolerance, "18 x 12 (K = 3) fixed");
    expect_small(check_random<24, 18>(24, 18, 20, rng), tolerance, "24 x 18 (K = 4) fixed");
    expect_small(check_random<Eigen::Dynamic, Eigen::Dynamic>(30, 24, 20, rng), tolerance, "30 x 24 (K = 5) dynamic");
    // Jr^T, Q x 6(K-1): two 7-joint arms, and with a shared 1-joint torso.
    expect_small(check_random<14, 6>(14, 6, 50, rng), tolerance, "14 x 6 (Jr^T, K = 2) fixed");
    expect_small(check_random<Eigen::Dynamic, Eigen::Dynamic>(15, 6, 50, rng), tolerance, "15 x 6 dynamic");
    expect_small(check_random<Eigen::Dynamic, 12>(22, 12, 20, rng), tolerance, "22 x 12 (K = 3) rows dynamic");
}

TEST(HouseholderQr, MatchesEigenOnSquareThinAndTinyShapes)
{
    std::mt19937 rng(7);
    constexpr double tolerance = 1e-14;
    expect_small(check_random<Eigen::Dynamic, Eigen::Dynamic>(1, 1, 10, rng), tolerance, "1 x 1");
    expect_small(check_random<5, 1>(5, 1, 10, rng), tolerance, "5 x 1");
    expect_small(check_random<6, 6>(6, 6, 50, rng), tolerance, "6 x 6 square");
    expect_small(check_random<Eigen::Dynamic, Eigen::Dynamic>(9, 9, 50, rng), tolerance, "9 x 9 square dynamic");
    expect_small(check_random<Eigen::Dynamic, Eigen::Dynamic>(40, 3, 20, rng), tolerance, "40 x 3 dynamic");
}

TEST(HouseholderQr, FloatMatchesEigenToFloatRounding)
{
    std::mt19937 rng(11);
    // Compared with Eigen's double factorisation of the same (float-rounded) matrix: the error is
    // float rounding, a few hundred float eps at these sizes.
    const double tolerance = 300.0 * std::numeric_limits<float>::epsilon();
    expect_small(check_random<12, 6, float>(12, 6, 20, rng), tolerance, "12 x 6 float");
    expect_small(check_random<14, 6, float>(14, 6, 20, rng), tolerance, "14 x 6 float");
}

TEST(HouseholderQr, TriangularColumnsAndRankDeficientMatrices)
{
    std::mt19937 rng(3);
    constexpr double tolerance = 1e-14;
    // Already upper triangular (every tau is 0, H_k = I): R = A exactly and Q = I exactly.
    Eigen::MatrixXd triangular = random_matrix<Eigen::MatrixXd>(8, 5, rng);
    triangular.triangularView<Eigen::StrictlyLower>().setZero();
    Eigen::MatrixXd r = triangular, reflectors(8, 5), q(8, 8);
    Eigen::VectorXd tau(5);
    Eigen::RowVectorXd workspace(8);
    coopdyn::householder_qr_in_place(r, reflectors, tau);
    coopdyn::householder_q(reflectors, tau, q, workspace);
    EXPECT_EQ(tau, Eigen::VectorXd::Zero(5));
    EXPECT_EQ(r, triangular);
    EXPECT_EQ(q, Eigen::MatrixXd::Identity(8, 8));
    expect_small(check<Eigen::Dynamic, Eigen::Dynamic>(triangular), tolerance, "8 x 5 upper triangular");

    // A zero column in the middle, and a matrix of rank 3 (12 x 6, as a degenerate grasp's Jr^T):
    // Q stays orthonormal and Q R = A; R's trailing diagonal is rounding.
    Eigen::MatrixXd zero_column = random_matrix<Eigen::MatrixXd>(12, 6, rng);
    zero_column.col(2).setZero();
    expect_small(check<Eigen::Dynamic, Eigen::Dynamic>(zero_column), tolerance, "12 x 6, zero column");
    const Eigen::MatrixXd rank3 = random_matrix<Eigen::MatrixXd>(12, 3, rng) * random_matrix<Eigen::MatrixXd>(3, 6, rng);
    Errors e;
    e.include(check<12, 6>(rank3));
    std::printf("[ measured ] 12 x 6 of rank 3: |Q^T Q - I| %.1e, |Q R - A|/|A| %.1e\n", e.orthonormal, e.product);
    EXPECT_LT(e.orthonormal, tolerance);
    EXPECT_LT(e.product, tolerance);
    Eigen::MatrixXd rank3_r = rank3, rank3_reflectors(12, 6);
    Eigen::VectorXd rank3_tau(6);
    coopdyn::householder_qr_in_place(rank3_r, rank3_reflectors, rank3_tau);
    EXPECT_LT(rank3_r.diagonal().tail(3).cwiseAbs().maxCoeff(), 1e-14 * rank3.norm());
}

}  // namespace
