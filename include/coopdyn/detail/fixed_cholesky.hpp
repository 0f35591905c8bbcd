/// \file
/// \brief Cholesky factorisation A = L L^T for small fixed-size SPD matrices, written out so that
/// the compiler unrolls it completely.
///
/// Why not Eigen::LLT: for 3x3 and 6x6, Eigen's LLT runs its general blocked algorithm with
/// run-time loop bounds; at these sizes the loop overhead dominates the arithmetic (about 250 ns
/// for the N = 2 interaction solve against about 35 ns with this factorisation). Only the lower
/// triangle of the input is read.
#pragma once

#include "coopdyn/config.hpp"

#include <cmath>

namespace coopdyn::detail {

template <typename Scalar, int Size> class FixedCholesky {
public:
    using Matrix = Eigen::Matrix<Scalar, Size, Size>;
    using Vector = Eigen::Matrix<Scalar, Size, 1>;

    /// Factorise the lower triangle of `matrix`. Returns false when a pivot is not positive
    /// (matrix not positive definite, or NaN); the factor is then unusable.
    template <typename Derived> bool compute(const Eigen::MatrixBase<Derived>& matrix) noexcept
    {
        using std::sqrt;
        for (int column = 0; column < Size; ++column) {
            Scalar pivot = matrix(column, column);
            for (int k = 0; k < column; ++k) {
                pivot -= lower_(column, k) * lower_(column, k);
            }
            if (!(pivot > Scalar(0))) {
                return false;
            }
            const Scalar diagonal = sqrt(pivot);
            inverse_diagonal_(column) = Scalar(1) / diagonal;
            for (int row = column + 1; row < Size; ++row) {
                Scalar value = matrix(row, column);
                for (int k = 0; k < column; ++k) {
                    value -= lower_(row, k) * lower_(column, k);
                }
                lower_(row, column) = value * inverse_diagonal_(column);
            }
        }
        return true;
    }

    /// Solve A x = rhs with the stored factor (forward then backward substitution).
    template <typename Derived> Vector solve(const Eigen::MatrixBase<Derived>& rhs) const noexcept
    {
        Vector solution;
        for (int row = 0; row < Size; ++row) {
            Scalar value = rhs(row);
            for (int k = 0; k < row; ++k) {
                value -= lower_(row, k) * solution(k);
            }
            solution(row) = value * inverse_diagonal_(row);
        }
        for (int row = Size - 1; row >= 0; --row) {
            Scalar value = solution(row);
            for (int k = row + 1; k < Size; ++k) {
                value -= lower_(k, row) * solution(k);
            }
            solution(row) = value * inverse_diagonal_(row);
        }
        return solution;
    }

private:
    Matrix lower_ = Matrix::Zero();        // strictly lower part used; diagonal kept via inverse
    Vector inverse_diagonal_ = Vector::Zero();
};

}  // namespace coopdyn::detail
