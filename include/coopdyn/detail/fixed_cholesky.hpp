/// \file
/// \brief Cholesky factorisations for small fixed-size SPD matrices, written out so that every loop
/// has a compile-time trip count: FixedCholesky, the square-root-free form A = L D L^T (L unit
/// lower triangular, D diagonal positive; the spatial layer's 3x3 and 6x6 solves), and FixedLlt,
/// A = L L^T (the controller's joint, contact and task matrices, whose factor L it also uses).
///
/// Why not Eigen::LLT / Eigen::LDLT: for 3x3 and 6x6 they run general blocked (LDLT: pivoting)
/// algorithms with run-time loop bounds; at these sizes the loop overhead dominates the arithmetic.
///
/// Why L D L^T rather than L L^T: the factorisation is a serial chain, each column waiting for
/// the previous column's pivot. L L^T puts a square root and a division on that chain per column,
/// L D L^T only a division (about half the latency), and needs no sqrt at all (no errno call-out,
/// and friendlier to autodiff scalars). Only the lower triangle of the input is read.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <type_traits>

// Ask for complete unrolling of the fixed-trip-count loops below (the inner bounds depend on the
// outer index, which compilers do not always unroll on their own).
#if defined(__clang__)
#define COOPDYN_DETAIL_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define COOPDYN_DETAIL_UNROLL _Pragma("GCC unroll 8")
#else
#define COOPDYN_DETAIL_UNROLL
#endif

namespace coopdyn::detail {

template <typename Scalar, int Size> class FixedCholesky {
public:
    using Matrix = Eigen::Matrix<Scalar, Size, Size>;
    using Vector = Eigen::Matrix<Scalar, Size, 1>;

    /// Factorise the lower triangle of `matrix`. Returns false when a pivot is not positive
    /// (matrix not positive definite, or NaN); the factor is then unusable.
    ///
    /// Always inlined, like solve_in_place(): a caller that factorises several independent
    /// matrices in turn (the rigid plant's two arms) gets their serial pivot chains interleaved
    /// only when both calls are inlined into it, and an out-of-line call would also have to
    /// store and reload the factor through memory.
    template <typename Derived> COOPDYN_INLINE bool compute(const Eigen::MatrixBase<Derived>& matrix) noexcept
    {
        // Column by column: d_j = a_jj - sum_k l_jk^2 d_k, l_ij = (a_ij - sum_k l_ik l_jk d_k) / d_j.
        // scaled_(i, k) = l_ik d_k is kept alongside l_ik so that each update is one product.
        bool positive_definite = true;
        COOPDYN_DETAIL_UNROLL
        for (int column = 0; column < Size; ++column) {
            Scalar pivot = matrix(column, column);
            COOPDYN_DETAIL_UNROLL
            for (int k = 0; k < column; ++k) {
                pivot -= lower_(column, k) * scaled_(column, k);
            }
            // No early return: every entry is written on every path (so nothing needs zeroing),
            // and the result of an indefinite matrix is reported, not used.
            positive_definite = positive_definite && pivot > Scalar(0);
            pivots_(column) = pivot;
            inverse_diagonal_(column) = Scalar(1) / pivot;
            COOPDYN_DETAIL_UNROLL
            for (int row = column + 1; row < Size; ++row) {
                Scalar value = matrix(row, column);
                COOPDYN_DETAIL_UNROLL
                for (int k = 0; k < column; ++k) {
                    value -= lower_(row, k) * scaled_(column, k);
                }
                scaled_(row, column) = value;  // l_ij d_j
                lower_(row, column) = value * inverse_diagonal_(column);
            }
        }
        return positive_definite;
    }

    /// The pivots d_j of the last compute() (D's diagonal; the squares of L L^T's diagonal). Their
    /// smallest, relative to the matrix's diagonal, tells how close to singular the matrix is.
    const Vector& pivots() const noexcept { return pivots_; }

    /// Solve A x = rhs with the stored factor (solve_in_place on a copy of rhs).
    template <typename Derived> Vector solve(const Eigen::MatrixBase<Derived>& rhs) const noexcept
    {
        Vector solution = rhs;
        solve_in_place(solution);
        return solution;
    }

    /// X <- A^-1 X for Size-row X with any number of columns: L Y = X, then L^T X = D^-1 Y, a
    /// whole row of X per step. With a row-major X each step is then one multiply-add across
    /// all right-hand sides, which vectorises; a vector X gets the scalar substitution.
    template <typename Derived> COOPDYN_INLINE void solve_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        static_assert(Derived::RowsAtCompileTime == Size || Derived::RowsAtCompileTime == Eigen::Dynamic,
                      "FixedCholesky::solve_in_place: X must have Size rows");
        // Eigen's idiom for writing through an expression argument (a block, a map).
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        COOPDYN_ASSERT(X.rows() == Size, "FixedCholesky::solve_in_place: X must have Size rows");
        COOPDYN_DETAIL_UNROLL
        for (int row = 1; row < Size; ++row) {
            COOPDYN_DETAIL_UNROLL
            for (int k = 0; k < row; ++k) {
                X.row(row) -= lower_(row, k) * X.row(k);
            }
        }
        COOPDYN_DETAIL_UNROLL
        for (int row = Size - 1; row >= 0; --row) {
            X.row(row) *= inverse_diagonal_(row);
            COOPDYN_DETAIL_UNROLL
            for (int k = row + 1; k < Size; ++k) {
                X.row(row) -= lower_(k, row) * X.row(k);
            }
        }
    }

private:
    // Only the strictly lower parts are written and read; left uninitialised on purpose (zeroing
    // them costs stores on every tick and buys nothing).
    Matrix lower_;             // l_ij, i > j (unit diagonal implied)
    Matrix scaled_;            // l_ij d_j, i > j
    Vector pivots_;            // d_j
    Vector inverse_diagonal_;  // 1 / d_j
};

/// L L^T of a small fixed-size SPD matrix (the controller's joint, contact and task matrices,
/// 6 to 24 rows), with the interface of Eigen::LLT that the controller uses plus explicit
/// triangular solves. Why not Eigen::LLT: it factorises with run-time loop bounds over dynamic
/// blocks and solves vectors longer than 8 through GEMV panels, which at these sizes costs several
/// times the arithmetic. Here every loop has a compile-time trip count (left-looking; see
/// compute()).
template <typename Scalar, int Size> class FixedLlt {
public:
    using Matrix = Eigen::Matrix<Scalar, Size, Size>;

    FixedLlt() = default;
    explicit FixedLlt(Index size) noexcept
    {
        COOPDYN_ASSERT(size == Size, "FixedLlt: size must equal the compile-time size");
        (void)size;
    }

    /// Factorise the lower triangle of `matrix`; info() says whether every pivot was positive
    /// (NaN is not). On failure the factor is unusable (not NaN-free).
    template <typename Derived> FixedLlt& compute(const Eigen::MatrixBase<Derived>& matrix) noexcept
    {
        // Left-looking, as FixedCholesky: column j needs only the finished columns k < j,
        // l_jj = sqrt(a_jj - sum_k l_jk^2), l_ij = (a_ij - sum_k l_ik l_jk) / l_jj, so every entry
        // is one dot product kept in registers (a right-looking update rewrites the trailing
        // triangle through memory once per column: 400 ns against 250 ns at 14 x 14).
        factor_ = matrix;
        bool positive_definite = true;
        COOPDYN_DETAIL_UNROLL
        for (int column = 0; column < Size; ++column) {
            Scalar pivot = factor_(column, column);
            COOPDYN_DETAIL_UNROLL
            for (int k = 0; k < column; ++k) {
                pivot -= factor_(column, k) * factor_(column, k);
            }
            positive_definite = positive_definite && pivot > Scalar(0);
            using std::sqrt;
            const Scalar diagonal = sqrt(pivot);
            factor_(column, column) = diagonal;
            inverse_diagonal_(column) = Scalar(1) / diagonal;
            COOPDYN_DETAIL_UNROLL
            for (int row = column + 1; row < Size; ++row) {
                Scalar value = factor_(row, column);
                COOPDYN_DETAIL_UNROLL
                for (int k = 0; k < column; ++k) {
                    value -= factor_(row, k) * factor_(column, k);
                }
                factor_(row, column) = value * inverse_diagonal_(column);
            }
        }
        info_ = positive_definite ? Eigen::Success : Eigen::NumericalIssue;
        return *this;
    }

    Eigen::ComputationInfo info() const noexcept { return info_; }
    /// L in the lower triangle (the strict upper triangle holds the input's, as Eigen::LLT's).
    const Matrix& matrixLLT() const noexcept { return factor_; }

    /// X <- L^-1 X, column by column (forward substitution, column-oriented: each step is one
    /// multiply and an axpy below it).
    template <typename Derived> void solve_lower_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        for (Index j = 0; j < X.cols(); ++j) {
            for (int k = 0; k < Size; ++k) {
                const Scalar value = X(k, j) * inverse_diagonal_(k);
                X(k, j) = value;
                for (int row = k + 1; row < Size; ++row) {
                    X(row, j) -= factor_(row, k) * value;
                }
            }
        }
    }

    /// X <- L^-T X, column by column (back substitution; row k of L^T is column k of L).
    template <typename Derived> void solve_upper_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        for (Index j = 0; j < X.cols(); ++j) {
            for (int k = Size - 1; k >= 0; --k) {
                Scalar value = X(k, j);
                for (int row = k + 1; row < Size; ++row) {
                    value -= factor_(row, k) * X(row, j);
                }
                X(k, j) = value * inverse_diagonal_(k);
            }
        }
    }

    /// X <- A^-1 X.
    template <typename Derived> void solveInPlace(const Eigen::MatrixBase<Derived>& X) const noexcept
    {
        solve_lower_in_place(X);
        solve_upper_in_place(X);
    }

private:
    Matrix factor_ = Matrix::Zero();
    Eigen::Matrix<Scalar, Size, 1> inverse_diagonal_ = Eigen::Matrix<Scalar, Size, 1>::Ones();
    Eigen::ComputationInfo info_ = Eigen::Success;
};

/// Eigen::LLT with FixedLlt's triangular-solve names, for sizes chosen at run time.
template <typename MatrixType> class DynamicLlt : public Eigen::LLT<MatrixType> {
public:
    using Eigen::LLT<MatrixType>::LLT;
    template <typename Derived> DynamicLlt& compute(const Eigen::MatrixBase<Derived>& matrix)
    {
        Eigen::LLT<MatrixType>::compute(matrix);
        return *this;
    }
    /// X <- L^-1 X, one column at a time (Eigen's many-column solver packs like a GEMM).
    template <typename Derived> void solve_lower_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        for (Index j = 0; j < X.cols(); ++j) {
            this->matrixL().solveInPlace(X.col(j));
        }
    }
    /// X <- L^-T X, one column at a time.
    template <typename Derived> void solve_upper_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        for (Index j = 0; j < X.cols(); ++j) {
            this->matrixU().solveInPlace(X.col(j));
        }
    }
};

/// The L L^T factorisation for a square matrix type: FixedLlt up to 24 rows known at compile
/// time, Eigen::LLT (as DynamicLlt) otherwise.
template <typename MatrixType>
using Llt = std::conditional_t<MatrixType::RowsAtCompileTime != Eigen::Dynamic && MatrixType::RowsAtCompileTime <= 24,
                               FixedLlt<typename MatrixType::Scalar,
                                        MatrixType::RowsAtCompileTime == Eigen::Dynamic ? 1 : MatrixType::RowsAtCompileTime>,
                               DynamicLlt<MatrixType>>;

}  // namespace coopdyn::detail

#undef COOPDYN_DETAIL_UNROLL
