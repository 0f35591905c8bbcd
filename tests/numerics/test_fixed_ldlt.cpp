// Tests of coopdyn/numerics/fixed_ldlt.hpp against references they were not derived from.
//
// FixedLdlt, the unrolled L D L^T (the spatial layer's 3x3 and 6x6 solves, the rigid plant's
// weld solve at 6 and 7):
// - its pivots are the squares of Eigen's LLT diagonal (LLT does not pivot, so its factor is
//   the same L D^1/2);
// - solve() and solve_in_place() (vectors, row- and column-major blocks of several columns,
//   blocks of a larger matrix) agree with a full-pivoting LU solve;
// - an indefinite, an exactly singular and a NaN matrix are reported;
// - the deprecated header coopdyn/detail/fixed_cholesky.hpp still names it detail::FixedCholesky.
//
// Matrices are random SPD with condition numbers up to about 1e6 (seeded).
#include "coopdyn/numerics/fixed_ldlt.hpp"

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

static_assert(std::is_same_v<coopdyn::detail::FixedCholesky<double, 6>, coopdyn::FixedLdlt<double, 6>>,
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

/// Random entries in [-1, 1].
template <typename Matrix> Matrix random_matrix(std::mt19937& rng)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Matrix m;
    for (Index i = 0; i < m.size(); ++i) {
        m(i) = uniform(rng);
    }
    return m;
}

template <int Size> void check_cholesky_size()
{
    using Matrix = Eigen::Matrix<double, Size, Size>;
    using Vector = Eigen::Matrix<double, Size, 1>;
    constexpr int columns = 5;
    using ColumnMajorBlock = Eigen::Matrix<double, Size, columns>;
    using RowMajorBlock = Eigen::Matrix<double, Size, columns, Eigen::RowMajor>;
    std::mt19937 rng(2000 + Size);
    double worst_pivot = 0.0, worst_solve = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
        const double condition = std::pow(10.0, 6.0 * trial / 19.0);
        const Matrix a = random_spd<Size>(rng, condition);
        // Only the lower triangle may be read: garbage in the strict upper one must not matter.
        Matrix lower_only = a;
        lower_only.template triangularView<Eigen::StrictlyUpper>().setConstant(1e30);
        coopdyn::FixedLdlt<double, Size> factor;
        ASSERT_TRUE(factor.compute(lower_only));

        const Eigen::LLT<Matrix> reference(a);
        ASSERT_EQ(reference.info(), Eigen::Success);
        const Vector reference_pivots = Matrix(reference.matrixL()).diagonal().array().square();
        EXPECT_GT(factor.pivots().minCoeff(), 0.0);
        worst_pivot = std::max(worst_pivot, ((factor.pivots() - reference_pivots).array() / reference_pivots.array())
                                                .abs()
                                                .maxCoeff());

        const Eigen::FullPivLU<Matrix> lu(a);
        const auto solve_error = [&](const auto& solved, const auto& rhs) {
            using Solution = std::decay_t<decltype(solved)>;
            const Solution expected = lu.solve(rhs);
            return (solved - expected).norm() / expected.norm() / condition;
        };
        const Vector rhs = random_matrix<Vector>(rng);
        const Vector solved = factor.solve(rhs);
        worst_solve = std::max(worst_solve, solve_error(solved, rhs));
        Vector in_place = rhs;
        factor.solve_in_place(in_place);
        EXPECT_EQ(in_place, solved);  // solve() is solve_in_place() on a copy

        const ColumnMajorBlock block_rhs = random_matrix<ColumnMajorBlock>(rng);
        ColumnMajorBlock column_major = block_rhs;
        factor.solve_in_place(column_major);
        worst_solve = std::max(worst_solve, solve_error(column_major, block_rhs));
        RowMajorBlock row_major = block_rhs;
        factor.solve_in_place(row_major);
        worst_solve = std::max(worst_solve, solve_error(ColumnMajorBlock(row_major), block_rhs));
        // Each column alone gives the same digits as the block: the columns do not mix.
        for (Index j = 0; j < columns; ++j) {
            EXPECT_EQ(factor.solve(block_rhs.col(j)), column_major.col(j));
        }
        // A block of a larger matrix (an expression, written through): only its columns change.
        Eigen::Matrix<double, Size, columns + 2> wider = Eigen::Matrix<double, Size, columns + 2>::Constant(7.0);
        wider.template middleCols<columns>(1) = block_rhs;
        factor.solve_in_place(wider.template middleCols<columns>(1));
        EXPECT_EQ(ColumnMajorBlock(wider.template middleCols<columns>(1)), column_major);
        EXPECT_TRUE((wider.col(0).array() == 7.0).all() && (wider.col(columns + 1).array() == 7.0).all());
    }
    std::printf("FixedLdlt<%d>: pivots vs Eigen's LLT (relative) %.1e, solve error / condition %.1e\n", Size,
                worst_pivot, worst_solve);
    EXPECT_LT(worst_pivot, 1e-9);
    EXPECT_LT(worst_solve, 2e-15);
}

TEST(FixedLdlt, FactorsAndSolvesAtTheLibrarysAndThePlantsSizes)
{
    check_cholesky_size<3>();
    check_cholesky_size<6>();
    check_cholesky_size<7>();
    check_cholesky_size<12>();
}

TEST(FixedLdlt, ReportsMatricesThatAreNotPositiveDefinite)
{
    using Matrix = Eigen::Matrix<double, 7, 7>;
    std::mt19937 rng(17);
    coopdyn::FixedLdlt<double, 7> factor;
    Matrix indefinite = random_spd<7>(rng, 10.0);
    indefinite(4, 4) = -1.0;
    EXPECT_FALSE(factor.compute(indefinite));
    Matrix singular = Matrix::Zero();
    singular.topLeftCorner<3, 3>().setIdentity();  // pivot 4 is exactly zero
    EXPECT_FALSE(factor.compute(singular));
    EXPECT_EQ(factor.pivots()(3), 0.0);
    Matrix not_a_number = random_spd<7>(rng, 10.0);
    not_a_number(6, 6) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(factor.compute(not_a_number));
    Matrix first_column_nan = random_spd<7>(rng, 10.0);
    first_column_nan(3, 0) = std::numeric_limits<double>::quiet_NaN();  // reaches later pivots only
    EXPECT_FALSE(factor.compute(first_column_nan));
    EXPECT_TRUE(factor.compute(random_spd<7>(rng, 10.0)));  // usable again
}

}  // namespace
