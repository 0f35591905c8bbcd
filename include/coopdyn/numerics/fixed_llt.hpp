/// \file
/// \brief FixedLlt: the Cholesky factorisation A = L L^T of a small fixed-size SPD matrix (the
/// controller's joint, contact and task matrices, the QP's Hessian, whose factor L they also use),
/// every loop with a compile-time trip count; DynamicLlt, Eigen::LLT with the same triangular-solve
/// names for run-time sizes; and Llt<MatrixType>, which picks one of the two; docs/numerics.md.
/// Its square-root-free sibling is FixedLdlt (numerics/fixed_ldlt.hpp).
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <type_traits>

// Ask for complete unrolling of the fixed-trip-count loops below (the inner bounds depend on the
// outer index, which compilers do not always unroll on their own).
#if defined(__clang__)
#define COOPDYN_LLT_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define COOPDYN_LLT_UNROLL _Pragma("GCC unroll 8")
#else
#define COOPDYN_LLT_UNROLL
#endif

namespace coopdyn {

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
        // Left-looking, as FixedLdlt: column j needs only the finished columns k < j,
        // l_jj = sqrt(a_jj - sum_k l_jk^2), l_ij = (a_ij - sum_k l_ik l_jk) / l_jj, so every entry
        // is one dot product kept in registers (a right-looking update rewrites the trailing
        // triangle through memory once per column: 400 ns against 250 ns at 14 x 14).
        factor_ = matrix;
        bool positive_definite = true;
        COOPDYN_LLT_UNROLL
        for (int column = 0; column < Size; ++column) {
            Scalar pivot = factor_(column, column);
            COOPDYN_LLT_UNROLL
            for (int k = 0; k < column; ++k) {
                pivot -= factor_(column, k) * factor_(column, k);
            }
            positive_definite = positive_definite && pivot > Scalar(0);
            using std::sqrt;
            const Scalar diagonal = sqrt(pivot);
            factor_(column, column) = diagonal;
            inverse_diagonal_(column) = Scalar(1) / diagonal;
            COOPDYN_LLT_UNROLL
            for (int row = column + 1; row < Size; ++row) {
                Scalar value = factor_(row, column);
                COOPDYN_LLT_UNROLL
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
///
/// The solves are plain substitution loops, not Eigen's triangular solver: called one column at a
/// time (its many-column solver packs like a GEMM) on the few joints of an arm, Eigen's dispatch
/// per column cost more than the arithmetic (15 % of a rigid scene plant's step in a profile,
/// docs/performance.md, "Scenes of any arms"). A row-major X is substituted a whole row at a time,
/// vectorised across its right-hand sides (JointSpaceGrasp's [J^T, u] side by side); a
/// column-major X column by column.
template <typename MatrixType> class DynamicLlt : public Eigen::LLT<MatrixType> {
public:
    using Scalar = typename MatrixType::Scalar;
    using Eigen::LLT<MatrixType>::LLT;
    template <typename Derived> DynamicLlt& compute(const Eigen::MatrixBase<Derived>& matrix)
    {
        Eigen::LLT<MatrixType>::compute(matrix);
        return *this;
    }
    /// X <- L^-1 X (forward substitution).
    template <typename Derived> void solve_lower_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        const MatrixType& L = this->matrixLLT();
        const Index n = L.rows();
        COOPDYN_ASSERT(X.rows() == n, "DynamicLlt: X must have the factor's rows");
        if constexpr (Derived::IsRowMajor) {
            for (Index k = 0; k < n; ++k) {
                X.row(k) /= L(k, k);
                for (Index row = k + 1; row < n; ++row) {
                    X.row(row) -= L(row, k) * X.row(k);
                }
            }
        } else {
            for (Index j = 0; j < X.cols(); ++j) {
                for (Index k = 0; k < n; ++k) {
                    const Scalar value = X(k, j) / L(k, k);
                    X(k, j) = value;
                    for (Index row = k + 1; row < n; ++row) {
                        X(row, j) -= L(row, k) * value;
                    }
                }
            }
        }
    }
    /// X <- L^-T X (back substitution; row k of L^T is column k of L).
    template <typename Derived> void solve_upper_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        const MatrixType& L = this->matrixLLT();
        const Index n = L.rows();
        COOPDYN_ASSERT(X.rows() == n, "DynamicLlt: X must have the factor's rows");
        if constexpr (Derived::IsRowMajor) {
            for (Index k = n - 1; k >= 0; --k) {
                for (Index row = k + 1; row < n; ++row) {
                    X.row(k) -= L(row, k) * X.row(row);
                }
                X.row(k) /= L(k, k);
            }
        } else {
            for (Index j = 0; j < X.cols(); ++j) {
                for (Index k = n - 1; k >= 0; --k) {
                    Scalar value = X(k, j);
                    for (Index row = k + 1; row < n; ++row) {
                        value -= L(row, k) * X(row, j);
                    }
                    X(k, j) = value / L(k, k);
                }
            }
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

}  // namespace coopdyn

#undef COOPDYN_LLT_UNROLL
