// Tests of coopdyn/numerics/fixed_llt.hpp against references they were not derived from.
//
// FixedLlt, the unrolled L L^T the controller factorises its joint, contact and task matrices
// with:
// - the product L L^T reproduces the matrix (and L is lower triangular with a positive diagonal);
// - its solves agree with a full-pivoting LU solve of the same system and with Eigen's LLT
//   factor, at the sizes the controller uses (6, 8, 12, 14, 15, 18, 21);
// - an indefinite, a singular-by-rounding-free negative pivot and a NaN matrix are reported;
// - DynamicLlt's own substitution loops (run-time sizes 1 to 21), on column-major and row-major
//   right-hand sides and on a strided block of a wider row-major matrix (JointSpaceGrasp's
//   layout), agree with a full-pivoting LU solve and with the explicit factor's products;
// - Llt picks FixedLlt for fixed sizes up to 24 and DynamicLlt (Eigen's LLT) otherwise, and the
//   deprecated header coopdyn/detail/fixed_cholesky.hpp still names them in detail::.
//
// Matrices are random SPD with condition numbers up to about 1e6 (seeded).
#include "coopdyn/numerics/fixed_llt.hpp"

#include "coopdyn/detail/fixed_cholesky.hpp"  // the deprecated names, checked below


#include <Eigen/LU>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <type_traits>

namespace {

using Eigen::Index;

static_assert(std::is_same_v<coopdyn::Llt<Eigen::Matrix<double, 14, 14>>, coopdyn::FixedLlt<double, 14>>);
static_assert(std::is_same_v<coopdyn::Llt<Eigen::Matrix<double, 25, 25>>,
                             coopdyn::DynamicLlt<Eigen::Matrix<double, 25, 25>>>);
static_assert(std::is_same_v<coopdyn::Llt<Eigen::MatrixXd>, coopdyn::DynamicLlt<Eigen::MatrixXd>>);
static_assert(std::is_same_v<coopdyn::detail::FixedLlt<double, 6>, coopdyn::FixedLlt<double, 6>>,
              "the deprecated name is the same type");
static_assert(std::is_same_v<coopdyn::detail::Llt<Eigen::MatrixXd>, coopdyn::Llt<Eigen::MatrixXd>>,
              "the deprecated name is the same type");

template <int Size> Eigen::Matrix<double, Size, Size> random_spd(std::mt19937& rng, double condition)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::Matrix<double, Size, Size> a;
    for (Index i = 0; i < Size; ++i) {
        for (Index j = 0; j < Size; ++j) {
            a(i, j) = uniform(rng);
        }
    }
    const Eigen::HouseholderQR<Eigen::Matrix<double, Size, Size>> qr(a);
    const Eigen::Matrix<double, Size, Size> q = qr.householderQ();
    Eigen::Matrix<double, Size, 1> spectrum;
    for (Index i = 0; i < Size; ++i) {
        spectrum(i) = std::pow(condition, static_cast<double>(i) / (Size - 1));
    }
    return q * spectrum.asDiagonal() * q.transpose();
}

template <int Size> void check_size()
{
    using Matrix = Eigen::Matrix<double, Size, Size>;
    std::mt19937 rng(1000 + Size);
    double worst_product = 0.0, worst_solve = 0.0, worst_factor = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
        const double condition = std::pow(10.0, 6.0 * trial / 19.0);
        const Matrix a = random_spd<Size>(rng, condition);
        coopdyn::FixedLlt<double, Size> factor(Size);
        ASSERT_EQ(factor.compute(a).info(), Eigen::Success);
        const Matrix lower = factor.matrixLLT().template triangularView<Eigen::Lower>();
        EXPECT_GT(lower.diagonal().minCoeff(), 0.0);
        worst_product = std::max(worst_product, (lower * lower.transpose() - a).norm() / a.norm());
        const Eigen::LLT<Matrix> reference(a);
        worst_factor = std::max(worst_factor, (lower - Matrix(reference.matrixL())).norm() / lower.norm());

        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        Eigen::Matrix<double, Size, 3> rhs;
        for (Index i = 0; i < rhs.size(); ++i) {
            rhs(i) = uniform(rng);
        }
        const Eigen::Matrix<double, Size, 3> expected = a.fullPivLu().solve(rhs);
        Eigen::Matrix<double, Size, 3> solved = rhs;
        factor.solveInPlace(solved);
        worst_solve = std::max(worst_solve, (solved - expected).norm() / expected.norm() / condition);
        // The two halves separately: L^-1 and L^-T against the explicit factor.
        Eigen::Matrix<double, Size, 3> half = rhs;
        factor.solve_lower_in_place(half);
        EXPECT_LT((lower * half - rhs).norm(), 1e-13 * condition * rhs.norm());
        half = rhs;
        factor.solve_upper_in_place(half);
        EXPECT_LT((lower.transpose() * half - rhs).norm(), 1e-13 * condition * rhs.norm());
    }
    std::printf("FixedLlt<%d>: |L L^T - A|/|A| %.1e, |L - Eigen's L|/|L| %.1e, solve error / condition %.1e\n", Size,
                worst_product, worst_factor, worst_solve);
    EXPECT_LT(worst_product, 1e-15);
    EXPECT_LT(worst_factor, 1e-12);
    EXPECT_LT(worst_solve, 2e-15);
}

TEST(FixedLlt, FactorsAndSolvesAtTheControllersSizes)
{
    check_size<6>();
    check_size<8>();
    check_size<12>();
    check_size<14>();
    check_size<15>();
    check_size<18>();
    check_size<21>();
}

Eigen::MatrixXd random_spd_dynamic(std::mt19937& rng, Index size, double condition)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    const Eigen::MatrixXd a = Eigen::MatrixXd::NullaryExpr(size, size, [&] { return uniform(rng); });
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
    const Eigen::MatrixXd q = qr.householderQ();
    Eigen::VectorXd spectrum(size);
    for (Index i = 0; i < size; ++i) {
        spectrum(i) = size == 1 ? condition : std::pow(condition, static_cast<double>(i) / static_cast<double>(size - 1));
    }
    return q * spectrum.asDiagonal() * q.transpose();
}

TEST(DynamicLlt, SolvesRowAndColumnMajorRightHandSidesAtRunTimeSizes)
{
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    double worst = 0.0;
    for (Index size = 1; size <= 21; ++size) {
        for (int trial = 0; trial < 4; ++trial) {
            const double condition = std::pow(10.0, 2.0 * trial);
            const Eigen::MatrixXd a = random_spd_dynamic(rng, size, condition);
            coopdyn::DynamicLlt<Eigen::MatrixXd> factor(size);
            ASSERT_EQ(factor.compute(a).info(), Eigen::Success);
            const Eigen::MatrixXd lower = factor.matrixLLT().triangularView<Eigen::Lower>();
            // The right-hand sides: columns 1-6 of an n x 8 row-major matrix (a strided block, as
            // JointSpaceGrasp's [J^T, u, 0] is solved), and the same values column-major.
            RowMajor wide = RowMajor::NullaryExpr(size, 8, [&] { return uniform(rng); });
            const Eigen::MatrixXd rhs = wide.middleCols(1, 6);
            const Eigen::MatrixXd expected = a.fullPivLu().solve(rhs);

            auto row_major = wide.middleCols(1, 6);
            const RowMajor untouched_left = wide.col(0), untouched_right = wide.col(7);
            factor.solve_lower_in_place(row_major);
            EXPECT_LT((lower * Eigen::MatrixXd(row_major) - rhs).norm(), 1e-13 * condition * rhs.norm());
            factor.solve_upper_in_place(row_major);
            EXPECT_EQ(RowMajor(wide.col(0)), untouched_left) << "a column outside the block was written";
            EXPECT_EQ(RowMajor(wide.col(7)), untouched_right) << "a column outside the block was written";
            worst = std::max(worst, (Eigen::MatrixXd(row_major) - expected).norm() / expected.norm() / condition);

            Eigen::MatrixXd column_major = rhs;
            factor.solve_lower_in_place(column_major);
            EXPECT_LT((lower * column_major - rhs).norm(), 1e-13 * condition * rhs.norm());
            Eigen::MatrixXd upper_only = rhs;
            factor.solve_upper_in_place(upper_only);
            EXPECT_LT((lower.transpose() * upper_only - rhs).norm(), 1e-13 * condition * rhs.norm());
            factor.solve_upper_in_place(column_major);
            worst = std::max(worst, (column_major - expected).norm() / expected.norm() / condition);
        }
    }
    std::printf("DynamicLlt, sizes 1-21: solve error / condition %.1e\n", worst);
    EXPECT_LT(worst, 2e-15);
}

TEST(FixedLlt, ReportsMatricesThatAreNotPositiveDefinite)
{
    using Matrix = Eigen::Matrix<double, 7, 7>;
    std::mt19937 rng(7);
    Matrix indefinite = random_spd<7>(rng, 10.0);
    indefinite(4, 4) = -1.0;
    coopdyn::FixedLlt<double, 7> factor;
    EXPECT_EQ(factor.compute(indefinite).info(), Eigen::NumericalIssue);
    Matrix singular = Matrix::Zero();
    singular.topLeftCorner<3, 3>().setIdentity();  // pivot 4 is exactly zero
    EXPECT_EQ(factor.compute(singular).info(), Eigen::NumericalIssue);
    Matrix not_a_number = random_spd<7>(rng, 10.0);
    not_a_number(6, 6) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(factor.compute(not_a_number).info(), Eigen::NumericalIssue);
    EXPECT_EQ(factor.compute(random_spd<7>(rng, 10.0)).info(), Eigen::Success);  // usable again
}

}  // namespace
