// Tests of coopdyn/numerics/triangular_solve.hpp against references they were not derived from.
//
// solve_upper_in_place (x <- R^-1 x) and solve_upper_transpose_in_place (x <- R^-T x), the
// projection's back and forward substitutions with the R of its Householder QR:
// - the result satisfies R x = b (R^T x = b) to rounding, measured as a residual, and agrees with a
//   full-pivoting LU solve of the dense triangular matrix;
// - the strict lower triangle is not read (it is filled with NaN);
// - they work on the expression types the projection passes: a fixed-size block of a larger
//   matrix for R and a segment of a vector for x, and dynamic sizes.
//
// R is random upper triangular with diagonal entries of both signs, 0.5 to 2 in magnitude (a
// triangular matrix with random off-diagonal entries is far worse conditioned than its diagonal
// suggests at larger n; the tolerances are relative to cond(R) via the LU reference). Seeded.
#include "coopdyn/numerics/triangular_solve.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

MatrixXd random_upper(Index n, std::mt19937_64& rng)
{
    std::uniform_real_distribution<double> entry(-1.0, 1.0), magnitude(0.5, 2.0);
    MatrixXd R = MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());  // never read below
    for (Index j = 0; j < n; ++j) {
        for (Index i = 0; i < j; ++i) {
            R(i, j) = entry(rng);
        }
        R(j, j) = (entry(rng) < 0.0 ? -1.0 : 1.0) * magnitude(rng);
    }
    return R;
}

MatrixXd dense_upper(const MatrixXd& R)
{
    MatrixXd dense = MatrixXd::Zero(R.rows(), R.cols());
    for (Index j = 0; j < R.cols(); ++j) {
        dense.col(j).head(j + 1) = R.col(j).head(j + 1);
    }
    return dense;
}

TEST(TriangularSolve, BackAndForwardSubstitutionSolveTheSystemsForSizesOneToTwentyFour)
{
    std::mt19937_64 rng(31);
    std::normal_distribution<double> normal;
    for (Index n = 1; n <= 24; ++n) {
        for (int trial = 0; trial < 5; ++trial) {
            const MatrixXd R = random_upper(n, rng);
            const MatrixXd U = dense_upper(R);
            const VectorXd b = VectorXd::NullaryExpr(n, [&] { return normal(rng); });
            const Eigen::FullPivLU<MatrixXd> lu(U), lu_transpose(U.transpose());

            VectorXd x = b;
            coopdyn::solve_upper_in_place(R, x);
            ASSERT_TRUE(x.allFinite()) << "n " << n;  // a NaN below the diagonal was read
            const VectorXd reference = lu.solve(b);
            EXPECT_LT((U * x - b).norm(), 1e-12 * (1.0 + U.norm() * x.norm())) << "n " << n;
            EXPECT_LT((x - reference).norm(), 1e-10 * (1.0 + reference.norm())) << "n " << n;

            VectorXd y = b;
            coopdyn::solve_upper_transpose_in_place(R, y);
            ASSERT_TRUE(y.allFinite()) << "n " << n;
            const VectorXd reference_transpose = lu_transpose.solve(b);
            EXPECT_LT((U.transpose() * y - b).norm(), 1e-12 * (1.0 + U.norm() * y.norm())) << "n " << n;
            EXPECT_LT((y - reference_transpose).norm(), 1e-10 * (1.0 + reference_transpose.norm())) << "n " << n;
        }
    }
}

TEST(TriangularSolve, WorksOnFixedSizeBlocksAndSegmentsAsTheProjectionPassesThem)
{
    // R the top-left 6 x 6 of a 12 x 6 fixed-size matrix (the projection's QR of a 6(K-1) x 6
    // block), x a segment of a longer vector; the rest of x must not change.
    std::mt19937_64 rng(32);
    std::normal_distribution<double> normal;
    Eigen::Matrix<double, 12, 6> stacked;
    stacked.setConstant(std::numeric_limits<double>::quiet_NaN());
    stacked.topRows<6>() = random_upper(6, rng);
    const Eigen::Matrix<double, 6, 6> U = dense_upper(stacked.topRows<6>());
    Eigen::Matrix<double, 10, 1> vector = Eigen::Matrix<double, 10, 1>::NullaryExpr([&] { return normal(rng); });
    const Eigen::Matrix<double, 10, 1> before = vector;

    coopdyn::solve_upper_in_place(stacked.topLeftCorner<6, 6>(), vector.segment<6>(2));
    EXPECT_LT((U * vector.segment<6>(2) - before.segment<6>(2)).norm(), 1e-13 * (1.0 + before.norm()));
    EXPECT_EQ(vector.head<2>(), before.head<2>());
    EXPECT_EQ(vector.tail<2>(), before.tail<2>());

    vector = before;
    coopdyn::solve_upper_transpose_in_place(stacked.topLeftCorner<6, 6>(), vector.segment<6>(2));
    EXPECT_LT((U.transpose() * vector.segment<6>(2) - before.segment<6>(2)).norm(), 1e-13 * (1.0 + before.norm()));
    EXPECT_EQ(vector.head<2>(), before.head<2>());
    EXPECT_EQ(vector.tail<2>(), before.tail<2>());
}

TEST(TriangularSolve, ADiagonalRDividesAndAnIdentityLeavesXAlone)
{
    // Exact cases: the substitutions reduce to divisions (no rounding for powers of two).
    Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
    R.diagonal() << 2.0, -4.0, 0.5;
    Eigen::Vector3d x(1.0, 1.0, 1.0);
    coopdyn::solve_upper_in_place(R, x);
    EXPECT_EQ(x, Eigen::Vector3d(0.5, -0.25, 2.0));
    x << 3.0, -1.0, 7.0;
    coopdyn::solve_upper_transpose_in_place(Eigen::Matrix3d::Identity(), x);
    EXPECT_EQ(x, Eigen::Vector3d(3.0, -1.0, 7.0));
}

}  // namespace
