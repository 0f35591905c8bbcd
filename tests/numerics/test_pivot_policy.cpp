// Tests of coopdyn/numerics/pivot_policy.hpp, the one rank policy (docs/numerics.md, "Pivot
// policy"): a squared pivot d_j of A counts as zero when d_j <= 1000 eps max_i A_ii. References
// the policy was not derived from: the condition number from Eigen's symmetric eigensolver, and
// matrices whose rank is known by construction.
// - regular: every random SPD matrix with cond(A) < 1 / tau passes, through every route (Eigen's
//   LLT, FixedLlt, FixedLdlt's pivots, the R of a Householder QR of a square root X of A), at
//   several sizes and units; and every refused matrix has cond(A) >= 1 / tau;
// - rank-deficient to rounding: Gram matrices X^T X of rank n - k (X's last k columns
//   combinations of the others), formed in floating point (positive "pivots" of rounding size),
//   are refused by every route, in every unit;
// - NaN: a NaN pivot, a NaN scale, a NaN anywhere in the factorised matrix are refused; so are
//   zero and negative pivots and the zero matrix.
#include "coopdyn/numerics/pivot_policy.hpp"

#include "coopdyn/numerics/fixed_ldlt.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/householder_qr.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace {

using Eigen::Index;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double eps = std::numeric_limits<double>::epsilon();

template <int Size> using Matrix = Eigen::Matrix<double, Size, Size>;

/// A random orthogonal n x n matrix (Q of a random matrix's QR).
template <int Size> Matrix<Size> random_orthogonal(std::mt19937& rng)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Matrix<Size> a;
    for (Index i = 0; i < a.size(); ++i) {
        a(i) = uniform(rng);
    }
    return Eigen::HouseholderQR<Matrix<Size>>(a).householderQ();
}

/// The verdicts of the four routes on A = X^T X, given X (n x n).
struct Verdicts {
    bool llt, fixed_llt, fixed_ldlt, qr;
};

template <int Size> Verdicts verdicts(const Matrix<Size>& x)
{
    const Matrix<Size> a = x.transpose() * x;
    Verdicts v{};
    v.llt = coopdyn::regular_llt(Eigen::LLT<Matrix<Size>>(a));
    coopdyn::FixedLlt<double, Size> fixed_llt;
    fixed_llt.compute(a);
    v.fixed_llt = coopdyn::regular_llt(fixed_llt);
    coopdyn::FixedLdlt<double, Size> fixed_ldlt;
    v.fixed_ldlt = fixed_ldlt.compute(a) && coopdyn::regular_pivots(fixed_ldlt.pivots(), a.diagonal().maxCoeff());
    Matrix<Size> r = x;
    Matrix<Size> reflectors = Matrix<Size>::Zero();
    Eigen::Matrix<double, Size, 1> tau = Eigen::Matrix<double, Size, 1>::Zero();
    coopdyn::householder_qr_in_place(r, reflectors, tau);
    v.qr = coopdyn::regular_triangular_factor(r);
    return v;
}

template <int Size> double condition(const Matrix<Size>& a)
{
    // lambda_min carries an absolute error of about eps lambda_max: beyond cond ~ 1 / eps it may
    // come out zero or negative, which is an infinite condition number here.
    const Eigen::SelfAdjointEigenSolver<Matrix<Size>> eigen(a, Eigen::EigenvaluesOnly);
    const double smallest = eigen.eigenvalues()(0);
    return smallest > 0.0 ? eigen.eigenvalues()(Size - 1) / smallest : std::numeric_limits<double>::infinity();
}

TEST(PivotPolicy, ToleranceIsAThousandUnitsOfRoundoff)
{
    EXPECT_EQ(coopdyn::pivot_tolerance_ulps, 1000);
    EXPECT_EQ(coopdyn::pivot_tolerance<double>(), 1000.0 * eps);
    EXPECT_EQ(coopdyn::pivot_tolerance<float>(), 1000.0f * std::numeric_limits<float>::epsilon());
    EXPECT_TRUE(coopdyn::regular_pivot(1.0, 1.0));
    EXPECT_TRUE(coopdyn::regular_pivot(1.01 * 1000.0 * eps, 1.0));
    EXPECT_FALSE(coopdyn::regular_pivot(1000.0 * eps, 1.0));  // at the tolerance: zero
    EXPECT_TRUE(coopdyn::regular_pivot(1.01e6 * 1000.0 * eps, 1e6));
    EXPECT_FALSE(coopdyn::regular_pivot(0.99e6 * 1000.0 * eps, 1e6));
}

template <int Size> void check_regular_and_refused_by_condition()
{
    std::mt19937 rng(300 + Size);
    const double limit = 1.0 / coopdyn::pivot_tolerance<double>();
    int passed = 0, refused = 0;
    for (int trial = 0; trial < 200; ++trial) {
        // Singular values of X from 1 to 10^-e, e up to 9: cond(A) = cond(X)^2 up to 1e18.
        const double exponent = 9.0 * trial / 199.0;
        Eigen::Matrix<double, Size, 1> singular_values;
        for (Index i = 0; i < Size; ++i) {
            singular_values(i) = std::pow(10.0, -exponent * static_cast<double>(i) / (Size - 1));
        }
        const double unit = std::pow(10.0, static_cast<double>(trial % 7) * 3.0 - 9.0);  // 1e-9 .. 1e9
        const Matrix<Size> x =
            unit * random_orthogonal<Size>(rng) * singular_values.asDiagonal() * random_orthogonal<Size>(rng);
        const Matrix<Size> a = x.transpose() * x;
        const double cond = condition<Size>(a);
        const Verdicts v = verdicts<Size>(x);
        for (const bool verdict : {v.llt, v.fixed_llt, v.fixed_ldlt, v.qr}) {
            if (cond < 0.5 * limit) {
                EXPECT_TRUE(verdict) << Size << " x " << Size << ", cond " << cond << ", unit " << unit;
            }
            if (!verdict) {
                // Refused: cond(A) >= 1 / tau, up to the eigensolver's own rounding of lambda_min.
                EXPECT_GT(cond, 0.5 * limit) << Size << " x " << Size << ", unit " << unit;
            }
            (verdict ? passed : refused) += 1;
        }
    }
    std::printf("[ measured ] %d x %d, cond(A) 1 .. 1e18, units 1e-9 .. 1e9: %d verdicts regular, %d singular\n",
                Size, Size, passed, refused);
    EXPECT_GT(passed, 0);
    EXPECT_GT(refused, 0);
}

TEST(PivotPolicy, PassesEveryMatrixBelowTheConditionLimitAndRefusesOnlyAboveIt)
{
    check_regular_and_refused_by_condition<3>();
    check_regular_and_refused_by_condition<6>();
    check_regular_and_refused_by_condition<12>();
}

template <int Size> void check_rank_deficient(int deficiency)
{
    std::mt19937 rng(static_cast<std::mt19937::result_type>(900 + Size + deficiency));
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int trial = 0; trial < 100; ++trial) {
        // X = [X1, X1 C]: its last k columns are combinations of the others (as a repeated or
        // redundant constraint), so A = X^T X has rank n - k exactly and null vectors [C; -I],
        // and an unpivoted factorisation meets the deficiency in its last k pivots. (A null
        // vector with tiny trailing entries hides it from an unpivoted factorisation, which is
        // not rank revealing: that is what pivoting is for; docs/numerics.md.)
        Eigen::MatrixXd x1(Size, Size - deficiency), c(Size - deficiency, deficiency);
        for (Index i = 0; i < x1.size(); ++i) {
            x1(i) = uniform(rng);
        }
        for (Index i = 0; i < c.size(); ++i) {
            c(i) = uniform(rng);
        }
        const double unit = std::pow(10.0, static_cast<double>(trial % 5) * 4.0 - 8.0);  // 1e-8 .. 1e8
        Matrix<Size> x;
        x << x1, x1 * c;
        x *= unit;
        const Verdicts v = verdicts<Size>(x);
        EXPECT_FALSE(v.llt) << Size << ", rank " << Size - deficiency << ", trial " << trial;
        EXPECT_FALSE(v.fixed_llt) << Size << ", rank " << Size - deficiency << ", trial " << trial;
        EXPECT_FALSE(v.fixed_ldlt) << Size << ", rank " << Size - deficiency << ", trial " << trial;
        EXPECT_FALSE(v.qr) << Size << ", rank " << Size - deficiency << ", trial " << trial;
    }
}

TEST(PivotPolicy, RefusesMatricesThatAreRankDeficientToRounding)
{
    check_rank_deficient<3>(1);
    check_rank_deficient<6>(1);
    check_rank_deficient<6>(3);
    check_rank_deficient<12>(1);
    check_rank_deficient<12>(6);
}

TEST(PivotPolicy, RefusesNanZeroAndNegativePivots)
{
    const Eigen::Vector3d regular(4.0, 2.0, 1.0);
    EXPECT_TRUE(coopdyn::regular_pivots(regular, 4.0));
    EXPECT_FALSE(coopdyn::regular_pivots(Eigen::Vector3d(4.0, nan, 1.0), 4.0));
    EXPECT_FALSE(coopdyn::regular_pivots(Eigen::Vector3d(nan, nan, nan), 4.0));
    EXPECT_FALSE(coopdyn::regular_pivots(regular, nan));
    EXPECT_FALSE(coopdyn::regular_pivots(Eigen::Vector3d(4.0, 0.0, 1.0), 4.0));
    EXPECT_FALSE(coopdyn::regular_pivots(Eigen::Vector3d(4.0, -1.0, 1.0), 4.0));
    EXPECT_FALSE(coopdyn::regular_pivots(Eigen::Vector3d::Zero(), 0.0));
    EXPECT_FALSE(coopdyn::regular_pivot(nan, 1.0));
    EXPECT_FALSE(coopdyn::regular_pivot(1.0, nan));

    std::mt19937 rng(5);
    const Matrix<6> q = random_orthogonal<6>(rng);
    const Matrix<6> a = q * Eigen::Matrix<double, 6, 1>::LinSpaced(1.0, 6.0).asDiagonal() * q.transpose();
    const Matrix<6> x = a.llt().matrixU();  // a square root: X^T X = A
    ASSERT_TRUE(coopdyn::regular_llt(Eigen::LLT<Matrix<6>>(a)));
    for (const Index at : {Index(0), Index(14), Index(35)}) {  // (0, 0), (2, 2), (5, 5)
        Matrix<6> bad = a;
        bad(at) = nan;
        EXPECT_FALSE(coopdyn::regular_llt(Eigen::LLT<Matrix<6>>(bad))) << at;
        coopdyn::FixedLlt<double, 6> fixed;
        EXPECT_FALSE(coopdyn::regular_llt(fixed.compute(bad))) << at;
        coopdyn::FixedLdlt<double, 6> ldlt;
        EXPECT_FALSE(ldlt.compute(bad) && coopdyn::regular_pivots(ldlt.pivots(), bad.diagonal().maxCoeff())) << at;
    }
    // A NaN below the diagonal (only the lower triangle is read) reaches the later pivots.
    Matrix<6> below = a;
    below(4, 1) = nan;
    EXPECT_FALSE(coopdyn::regular_llt(Eigen::LLT<Matrix<6>>(below)));
    // A NaN in R above the diagonal (a NaN in X's column) reaches the scale.
    Matrix<6> r = x;
    ASSERT_TRUE(coopdyn::regular_triangular_factor(r));
    r(1, 4) = nan;
    EXPECT_FALSE(coopdyn::regular_triangular_factor(r));
    EXPECT_FALSE(coopdyn::regular_triangular_factor(Matrix<6>::Zero()));
    EXPECT_FALSE(coopdyn::regular_llt(Eigen::LLT<Matrix<6>>(Matrix<6>::Zero())));
}

TEST(PivotPolicy, FloatUsesFloatRoundoff)
{
    // cond 1e2 passes, a rank-deficient Gram matrix in float is refused.
    std::mt19937 rng(8);
    const Matrix<6> q = random_orthogonal<6>(rng);
    Eigen::Matrix<double, 6, 1> spectrum;
    spectrum << 1.0, 3.0, 10.0, 30.0, 60.0, 100.0;
    const Eigen::Matrix<float, 6, 6> a = (q * spectrum.asDiagonal() * q.transpose()).cast<float>();
    EXPECT_TRUE(coopdyn::regular_llt(Eigen::LLT<Eigen::Matrix<float, 6, 6>>(a)));
    const Eigen::Matrix<float, 6, 5> u = q.leftCols<5>().cast<float>();
    const Eigen::Matrix<float, 6, 6> rank5 = u * u.transpose();
    coopdyn::FixedLdlt<float, 6> ldlt;
    EXPECT_FALSE(ldlt.compute(rank5) && coopdyn::regular_pivots(ldlt.pivots(), rank5.diagonal().maxCoeff()));
}

}  // namespace
