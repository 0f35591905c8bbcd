/// \file
/// \brief The active-set core of the Goldfarb-Idnani QP solver (coopdyn/numerics/qp_solver.hpp,
/// docs/qp_solver.md, "Method"): the matrices J = L^-T Q and R with J^T [active rows] = [R; 0],
/// the primal and dual directions of one step, and the Givens updates when a row enters or leaves.
/// It knows nothing of the rows that are not active, of x or of the bounds; QpSolver drives it.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace coopdyn::detail {

/// A plane rotation [c s; -s c] with c a + s b = |(a, b)| and -s a + c b = 0.
template <typename Scalar> struct QpGivens {
    Scalar c = 1;
    Scalar s = 0;
    Scalar norm = 0;

    static QpGivens zeroing(Scalar a, Scalar b) noexcept
    {
        using std::sqrt;
        QpGivens rotation;
        rotation.norm = sqrt(a * a + b * b);
        if (rotation.norm > 0) {
            const Scalar inverse = Scalar(1) / rotation.norm;
            rotation.c = a * inverse;
            rotation.s = b * inverse;
        }
        return rotation;
    }
    void apply(Scalar& a, Scalar& b) const noexcept
    {
        const Scalar first = c * a + s * b;
        b = -s * a + c * b;
        a = first;
    }
    /// The same rotation on two columns of a matrix (J's columns, J^T's rows, keeping
    /// J^T [rows] = [R; 0]). Through plain pointers to the two (contiguous, distinct) columns so
    /// that the loop vectorises: these rotations are the largest part of a step.
    template <typename Matrix> void apply_to_columns(Matrix& matrix, Index first, Index second) const noexcept
    {
        Scalar* x = matrix.col(first).data();
        Scalar* y = matrix.col(second).data();
        for (Index i = 0; i < matrix.rows(); ++i) {
            const Scalar xi = x[i];
            const Scalar yi = y[i];
            x[i] = c * xi + s * yi;
            y[i] = -s * xi + c * yi;
        }
    }
};

/// \brief J, R, the active rows and their multipliers u of a Goldfarb-Idnani iteration over n =
/// `Variables` unknowns (q <= n rows active). Fixed sizes hold everything inline; dynamic sizes
/// allocate in the constructor only.
template <typename Scalar, int Variables> class QpActiveSet {
public:
    using Matrix = Eigen::Matrix<Scalar, Variables, Variables>;
    using Vector = Eigen::Matrix<Scalar, Variables, 1>;
    using ActiveList = Eigen::Matrix<int, Variables, 1>;

    explicit QpActiveSet(Index variables)
        : variables_(variables),
          basis_(Matrix::Zero(variables, variables)),
          triangle_(Matrix::Zero(variables, variables)),
          step_(Vector::Zero(variables)),
          direction_(Vector::Zero(variables)),
          dual_direction_(Vector::Zero(variables)),
          dual_scale_(Vector::Zero(variables)),
          multipliers_(Vector::Zero(variables)),
          rows_(ActiveList::Constant(variables, -1))
    {
    }

    /// q, the number of active rows.
    Index size() const noexcept { return count_; }
    /// The row of C active at `position` (positions in order of entry).
    int row(Index position) const noexcept { return rows_(position); }
    /// Its multiplier u (>= 0).
    Scalar multiplier(Index position) const noexcept { return multipliers_(position); }
    /// z of the last compute_directions().
    const Vector& direction() const noexcept { return direction_; }

    /// J = L^-T (upper triangular, Q = I) by back substitution on L^T J = I, column by column,
    /// and |L^-1|_F, the scale of the rounding in J^T c (used by the dependence test); no row
    /// active. `factor` is the lower-triangular L (only its lower triangle is read).
    template <typename Factor> void start(const Factor& factor) noexcept
    {
        // 1 / L_ii, kept in step_ (free until the first step): n divisions instead of n^2 / 2.
        for (Index i = 0; i < variables_; ++i) {
            step_(i) = Scalar(1) / factor(i, i);
        }
        basis_.setZero();
        for (Index column = 0; column < variables_; ++column) {
            basis_(column, column) = step_(column);
            for (Index i = column - 1; i >= 0; --i) {
                Scalar sum = 0;
                for (Index k = i + 1; k <= column; ++k) {
                    sum += factor(k, i) * basis_(k, column);
                }
                basis_(i, column) = -sum * step_(i);
            }
        }
        basis_norm_ = basis_.norm();
        count_ = 0;
    }

    /// x = -H^-1 g = -J J^T g (right after start()).
    template <typename Gradient, typename X> void unconstrained_minimum(const Gradient& gradient, X& x) noexcept
    {
        // Coefficient-based products: at these sizes a dynamic GEMV's dispatch costs more than
        // its arithmetic.
        step_.noalias() = basis_.transpose().lazyProduct(gradient);
        x.noalias() = basis_.lazyProduct(step_);
        x = -x;  // negated apart: -(product) would evaluate into a heap temporary for dynamic sizes
    }

    /// For the row p being added, with n_p = -c_p (Goldfarb and Idnani write rows as n^T x >= b):
    /// step_ = J^T n_p; direction_ = z = J2 J2^T n_p (the primal direction, J2 the last n - q
    /// columns of J); dual_direction_ = r = R^-1 (J1^T n_p) (how fast the active multipliers
    /// decrease). Returns |J2^T n_p|^2 = z^T n_p.
    template <typename Normal> Scalar compute_directions(const Normal& normal) noexcept
    {
        const Index q = count_;
        step_.noalias() = basis_.transpose().lazyProduct(normal);
        step_ = -step_;  // n_p = -c_p; negated apart, see unconstrained_minimum
        direction_.setZero();
        Scalar complement_squared = 0;
        for (Index j = q; j < variables_; ++j) {
            direction_ += step_(j) * basis_.col(j);
            complement_squared += step_(j) * step_(j);
        }
        solve_triangle(q);
        return complement_squared;
    }

    /// z counts as zero when |J2^T c_p| is within the rounding of J^T c_p (about eps |L^-1|_F |c_p|,
    /// amplified by the rotations applied to J): c_p then depends linearly on the active rows.
    bool primal_step_possible(Scalar complement_squared, Scalar row_norm) const noexcept
    {
        const Scalar floor = Scalar(64) * static_cast<Scalar>(variables_) * std::numeric_limits<Scalar>::epsilon() *
                             basis_norm_ * row_norm;
        return complement_squared > floor * floor;
    }

    /// Position of the active row whose multiplier reaches zero first along the dual direction
    /// (smallest u_j / r_j over r_j > 0), or -1 when no multiplier decreases.
    Index blocking_position() const noexcept
    {
        Index blocking = -1;
        Scalar shortest = 0;
        for (Index j = 0; j < count_; ++j) {
            if (dual_direction_(j) > 0) {
                const Scalar length = multipliers_(j) / dual_direction_(j);
                if (blocking < 0 || length < shortest) {
                    shortest = length;
                    blocking = j;
                }
            }
        }
        return blocking;
    }

    /// The step length at which the multiplier at `blocking` reaches zero (infinity for -1).
    Scalar partial_length(Index blocking) const noexcept
    {
        return blocking >= 0 ? multipliers_(blocking) / dual_direction_(blocking) : std::numeric_limits<Scalar>::infinity();
    }

    /// u_active -= t r, u_p += t (clamped at zero: the blocking multiplier lands there up to
    /// rounding).
    void move_multipliers(Scalar length, Scalar& entering_multiplier) noexcept
    {
        using std::max;
        for (Index j = 0; j < count_; ++j) {
            multipliers_(j) = max(multipliers_(j) - length * dual_direction_(j), Scalar(0));
        }
        entering_multiplier += length;
    }

    /// Rotates J^T n_p (step_ of the last compute_directions) so that its entries q+1.. vanish,
    /// applying the same rotations to J's columns, and appends the result as R's new column q.
    void append(int row, Scalar multiplier) noexcept
    {
        const Index q = count_;
        for (Index j = variables_ - 1; j > q; --j) {
            rotate_basis(j - 1, j, step_(j - 1), step_(j));
        }
        for (Index i = 0; i <= q; ++i) {
            triangle_(i, q) = step_(i);
        }
        rows_(q) = row;
        multipliers_(q) = multiplier;
        ++count_;
    }

    /// Removes the active row at `position` and returns it: R loses that column, and the rotations
    /// that restore its triangular shape are applied to J's columns as well.
    int drop(Index position) noexcept
    {
        const Index q = count_;
        const int dropped = rows_(position);
        for (Index j = position; j + 1 < q; ++j) {
            rows_(j) = rows_(j + 1);
            multipliers_(j) = multipliers_(j + 1);
            triangle_.col(j).head(j + 2) = triangle_.col(j + 1).head(j + 2);
        }
        // Column j now has a subdiagonal entry R(j + 1, j); rotating rows j, j + 1 zeroes it.
        for (Index j = position; j + 1 < q; ++j) {
            Scalar& top = triangle_(j, j);
            Scalar& bottom = triangle_(j + 1, j);
            const Givens rotation = Givens::zeroing(top, bottom);
            top = rotation.norm;
            bottom = 0;
            for (Index k = j + 1; k + 1 < q; ++k) {
                rotation.apply(triangle_(j, k), triangle_(j + 1, k));
            }
            rotation.apply_to_columns(basis_, j, j + 1);
        }
        triangle_.col(q - 1).setZero();
        --count_;
        return dropped;
    }

private:
    using Givens = QpGivens<Scalar>;

    /// r = R^-1 step_.head(q) by back substitution, column by column: once r_k is known, its
    /// column of R times r_k is subtracted from the entries above it at once (a contiguous column
    /// of the column-major R, so the loop vectorises; a row-by-row sum would walk R across its
    /// storage in one dependent chain). Each entry's rounding scale, |w_i| + sum_k |R_ik r_k|, is
    /// accumulated alongside: an entry within the rounding of its own computation (8 n eps of that
    /// scale) is set to zero, because its sign is noise, and a noise-positive r_j would drop a row
    /// (or hide an infeasibility) for no reason.
    void solve_triangle(Index q) noexcept
    {
        using std::abs;
        const Scalar noise = Scalar(8) * static_cast<Scalar>(variables_) * std::numeric_limits<Scalar>::epsilon();
        Scalar* w = dual_direction_.data();  // J1^T n_p, becoming r from the bottom up
        Scalar* scale = dual_scale_.data();
        for (Index i = 0; i < q; ++i) {
            w[i] = step_(i);
            scale[i] = abs(step_(i));
        }
        for (Index k = q - 1; k >= 0; --k) {
            const Scalar r = abs(w[k]) > noise * scale[k] ? w[k] / triangle_(k, k) : Scalar(0);
            w[k] = r;
            const Scalar* column = triangle_.col(k).data();
            for (Index i = 0; i < k; ++i) {
                const Scalar term = column[i] * r;
                w[i] -= term;
                scale[i] += abs(term);
            }
        }
    }

    /// Zeroes b against a, rotating J's columns `first` and `second` alike.
    void rotate_basis(Index first, Index second, Scalar& a, Scalar& b) noexcept
    {
        const Givens rotation = Givens::zeroing(a, b);
        if (!(rotation.norm > 0)) {
            return;
        }
        a = rotation.norm;
        b = 0;
        rotation.apply_to_columns(basis_, first, second);
    }

    Index variables_;
    Matrix basis_;           ///< J = L^-T Q
    Matrix triangle_;        ///< R (q x q upper triangle in use)
    Scalar basis_norm_ = 0;  ///< |L^-1|_F = |J|_F
    Vector step_;            ///< J^T n_p
    Vector direction_;       ///< z
    Vector dual_direction_;  ///< r (first q entries)
    Vector dual_scale_;      ///< the rounding scale of each entry of r (scratch)
    Vector multipliers_;     ///< u (first q entries)
    ActiveList rows_;        ///< active rows in order of entry (first q entries)
    Index count_ = 0;        ///< q
};

}  // namespace coopdyn::detail
