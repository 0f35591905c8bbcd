/// \file
/// \brief Dense strictly convex quadratic programs, min 1/2 x^T H x + g^T x subject to C x <= d,
/// by the dual active-set method of Goldfarb and Idnani, "A numerically stable dual method for
/// solving strictly convex quadratic programs", Mathematical Programming 27, 1983
/// (docs/qp_solver.md).
///
/// Written for a controller's per-tick contact-wrench QP (6 variables and 30 rows for two arms, 12 x
/// 60 for four): fixed sizes allocate nothing, a QpSolver built for dynamic sizes allocates only in
/// its constructor, and the solve path is noexcept.
///
/// The method in brief (H = L L^T, n variables, m rows, A the active set of q rows):
/// - start at the unconstrained minimum x = -H^-1 g, with A empty and every multiplier zero: the
///   dual problem is feasible from the start, and stays so;
/// - pick the most violated row p (violation divided by the row norm, so that the choice does not
///   depend on how rows are scaled) and move towards making it active: the primal direction z is
///   the part of H^-1 c_p orthogonal (in the metric of H) to the active rows, the dual direction
///   moves the active multipliers so that stationarity keeps holding;
/// - a full step makes p active; a partial step stops where an active multiplier reaches zero and
///   drops that row; when z = 0 (c_p depends linearly on the active rows) only the multipliers
///   move, and one active row is dropped. When z = 0 and no multiplier decreases, no point
///   satisfies p together with the active rows: the problem is infeasible;
/// - when no row is violated, x is optimal (all KKT conditions hold).
///
/// Numerics: H is factorised once (L L^T: FixedLlt for fixed sizes, Eigen::LLT
/// otherwise); the solver keeps J = L^-T Q (Q orthogonal) and the upper-triangular R with
/// J^T [active rows as columns] = [R; 0], updated by Givens rotations when a row enters or leaves
/// (never refactorised, never inverted).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace coopdyn {

/// \brief Outcome of a QP solve (QpResult::status).
enum class QpStatus {
    /// Every KKT condition holds: x is the minimiser, multipliers its Lagrange multipliers.
    solved,
    /// A violated row cannot be satisfied together with the active rows (its normal depends on
    /// theirs with no multiplier that may decrease): no x satisfies C x <= d. x and multipliers
    /// are the last iterate (x satisfies the rows active at that point, not all of C x <= d).
    infeasible,
    /// The iteration cap (QpSolver::set_iteration_limit) was reached first: x and multipliers are
    /// the last iterate (multipliers >= 0, x not necessarily feasible).
    iteration_limit,
    /// H is not (numerically) positive definite: its Cholesky factorisation failed, or a pivot
    /// L_jj^2 fell below n eps max_i H_ii (a semidefinite or indefinite H). x, multipliers and
    /// the objective are zero.
    not_positive_definite,
};

/// The enumerator's name ("solved", "infeasible", "iteration_limit", "not_positive_definite").
inline const char* to_string(QpStatus status) noexcept
{
    switch (status) {
    case QpStatus::solved: return "solved";
    case QpStatus::infeasible: return "infeasible";
    case QpStatus::iteration_limit: return "iteration_limit";
    case QpStatus::not_positive_definite: return "not_positive_definite";
    }
    return "unknown";
}

/// \brief Solution of min 1/2 x^T H x + g^T x s.t. C x <= d. Every field is finite whatever the
/// status (see QpStatus for what x holds when the status is not `solved`).
template <typename Scalar, int Variables, int Rows> struct QpResult {
    using VariableVector = Eigen::Matrix<Scalar, Variables, 1>;
    using RowVector = Eigen::Matrix<Scalar, Rows, 1>;
    using IndexVector = Eigen::Matrix<int, Rows, 1>;

    QpResult() : QpResult(Variables == Eigen::Dynamic ? 0 : Variables, Rows == Eigen::Dynamic ? 0 : Rows) {}

    /// Sized for n variables and m rows, all zero (dynamic sizes allocate here).
    QpResult(Index variables, Index rows)
        : x(VariableVector::Zero(variables)),
          multipliers(RowVector::Zero(rows)),
          active(IndexVector::Constant(rows, -1))
    {
    }

    VariableVector x;         ///< the minimiser (n)
    RowVector multipliers;    ///< lambda (m), one per row of C: >= 0, zero for inactive rows
    /// Rows of C active at x (held with equality, in the order they entered), in
    /// active.head(active_count); the other entries are -1. Warm starts begin from this set.
    IndexVector active;
    int active_count = 0;
    QpStatus status = QpStatus::solved;
    int iterations = 0;       ///< primal/dual steps taken (full, partial and dual-only)
    Scalar objective = 0;     ///< 1/2 x^T H x + g^T x at x
};

/// \brief Reusable workspace for min 1/2 x^T H x + g^T x s.t. C x <= d, H symmetric positive
/// definite n x n, C m x n (Goldfarb-Idnani, see the file comment).
///
/// `Variables` (n) and `Rows` (m) are compile-time sizes or Eigen::Dynamic. For fixed sizes the
/// object holds everything inline (no heap at all); for dynamic sizes the constructor allocates
/// once and solve() / solve_warm() allocate nothing. Solves are noexcept; their size and
/// finiteness preconditions are debug assertions, except that a problem of another size than the
/// workspace stops the program in Release too (COOPDYN_REQUIRE_SHAPE), instead of writing past a
/// buffer.
template <typename Scalar, int Variables, int Rows> class QpSolver {
    static_assert(Variables == Eigen::Dynamic || Variables > 0, "QpSolver: at least one variable");
    static_assert(Rows == Eigen::Dynamic || Rows > 0,
                  "QpSolver: a fixed number of rows must be positive (use Dynamic for a problem without rows)");

public:
    using Result = QpResult<Scalar, Variables, Rows>;

    /// Workspace for fixed sizes (a template so that an explicit instantiation for dynamic sizes
    /// does not instantiate it).
    template <int V = Variables, int R = Rows,
              std::enable_if_t<V != Eigen::Dynamic && R != Eigen::Dynamic, int> = 0>
    QpSolver() : QpSolver(Variables, Rows)
    {
    }

    /// Workspace for n = `variables` unknowns and m = `rows` inequality rows (must equal the
    /// compile-time sizes when those are fixed). Allocates all dynamic storage.
    QpSolver(Index variables, Index rows)
        : variables_(variables),
          rows_(rows),
          iteration_limit_(default_iteration_limit(variables, rows)),
          llt_(variables),
          gradient_(variables),
          constraints_(variables, rows),
          bounds_(rows),
          row_norms_(rows),
          violations_(rows),
          is_active_(rows),
          basis_(variables, variables),
          triangle_(variables, variables),
          step_(variables),
          direction_(variables),
          dual_direction_(variables),
          active_multipliers_(variables),
          active_rows_(variables),
          warm_rows_(variables),
          result_(variables, rows)
    {
        COOPDYN_REQUIRE_SHAPE(variables > 0 && rows >= 0, "QpSolver: needs n > 0 variables and m >= 0 rows");
        COOPDYN_REQUIRE_SHAPE(Variables == Eigen::Dynamic || variables == Variables,
                              "QpSolver: number of variables differs from the compile-time size");
        COOPDYN_REQUIRE_SHAPE(Rows == Eigen::Dynamic || rows == Rows,
                              "QpSolver: number of rows differs from the compile-time size");
    }

    /// n, the number of variables.
    Index variables() const noexcept { return variables_; }
    /// m, the number of inequality rows.
    Index rows() const noexcept { return rows_; }

    /// The default cap on steps, 10 (n + m): Goldfarb-Idnani adds each row at most a few times in
    /// practice; the cap only guards against rounding cycles.
    static int default_iteration_limit(Index variables, Index rows) noexcept
    {
        return static_cast<int>(10 * (variables + rows));
    }
    /// Cap on steps per solve (>= 0); reaching it returns QpStatus::iteration_limit.
    void set_iteration_limit(int limit) noexcept
    {
        COOPDYN_ASSERT(limit >= 0, "QpSolver::set_iteration_limit: negative limit");
        iteration_limit_ = limit;
    }
    /// The current cap on steps per solve (default_iteration_limit(n, m) unless set).
    int iteration_limit() const noexcept { return iteration_limit_; }

    /// Relative tolerance of the feasibility test: row i counts as violated when
    /// c_i^T x - d_i > tolerance (|c_i| |x| + |d_i|), the rounding level of evaluating the row
    /// (100 eps: 2.2e-14 in double, 1.2e-5 in float).
    static Scalar feasibility_tolerance() noexcept { return Scalar(100) * std::numeric_limits<Scalar>::epsilon(); }

    /// The result of the last solve (all zero before the first one).
    const Result& result() const noexcept { return result_; }

    /// \brief Cold solve of min 1/2 x^T H x + g^T x s.t. C x <= d.
    /// \param hessian H, n x n symmetric positive definite (only its lower triangle is read).
    /// \param gradient g, n.
    /// \param constraints C, m x n.
    /// \param bounds d, m.
    /// \return result(): x, multipliers, status, active set (valid until the next solve).
    template <typename H, typename G, typename C, typename D>
    const Result& solve(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
                        const Eigen::MatrixBase<C>& constraints, const Eigen::MatrixBase<D>& bounds) noexcept
    {
        load(hessian, gradient, constraints, bounds);
        run(false);
        return result_;
    }

    /// \brief Warm solve: as solve(), starting from the active set of the previous solve. The rows
    /// active last time are added first, each by the same Goldfarb-Idnani steps as any other row
    /// (a row that no longer fits is dropped again by those steps), then the ordinary iteration
    /// finishes. The answer is the same as solve()'s (the minimiser is unique); when consecutive
    /// problems share their active set it usually takes fewer steps.
    template <typename H, typename G, typename C, typename D>
    const Result& solve_warm(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
                             const Eigen::MatrixBase<C>& constraints, const Eigen::MatrixBase<D>& bounds) noexcept
    {
        load(hessian, gradient, constraints, bounds);
        run(true);
        return result_;
    }

private:
    using Matrix = Eigen::Matrix<Scalar, Variables, Variables>;
    using Vector = Eigen::Matrix<Scalar, Variables, 1>;
    using ConstraintMatrix = Eigen::Matrix<Scalar, Variables, Rows>;
    using RowVector = Eigen::Matrix<Scalar, Rows, 1>;
    using RowFlags = Eigen::Matrix<int, Rows, 1>;
    using ActiveList = Eigen::Matrix<int, Variables, 1>;

    /// What one step did to the row being added.
    enum class Step { added, dropped, infeasible };

    /// Checks the shapes and copies the problem into the workspace: C transposed, so that each
    /// row's normal is a contiguous column.
    template <typename H, typename G, typename C, typename D>
    void load(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
              const Eigen::MatrixBase<C>& constraints, const Eigen::MatrixBase<D>& bounds) noexcept
    {
        static_assert(detail::sizes_agree(H::RowsAtCompileTime, Variables) &&
                          detail::sizes_agree(H::ColsAtCompileTime, Variables) &&
                          detail::sizes_agree(G::RowsAtCompileTime, Variables) &&
                          detail::sizes_agree(C::ColsAtCompileTime, Variables) &&
                          detail::sizes_agree(C::RowsAtCompileTime, Rows) &&
                          detail::sizes_agree(D::RowsAtCompileTime, Rows),
                      "QpSolver: argument sizes disagree with the solver's sizes");
        // One comparison each (none survive for fixed sizes): a wrong size would read or write
        // past the workspace.
        COOPDYN_REQUIRE_SHAPE(hessian.rows() == variables_ && hessian.cols() == variables_ &&
                                  gradient.rows() == variables_ && gradient.cols() == 1 &&
                                  constraints.rows() == rows_ && constraints.cols() == variables_ &&
                                  bounds.rows() == rows_ && bounds.cols() == 1,
                              "QpSolver: H, g, C or d sized for another problem");
        COOPDYN_ASSERT(hessian.allFinite() && gradient.allFinite(), "QpSolver: H or g not finite");
        COOPDYN_ASSERT(constraints.allFinite() && bounds.allFinite(), "QpSolver: C or d not finite");
        llt_.compute(hessian);
        gradient_ = gradient;
        constraints_ = constraints.transpose();
        bounds_ = bounds;
    }

    /// The whole iteration; writes result_.
    void run(bool warm) noexcept
    {
        const int warm_count = warm ? result_.active_count : 0;
        for (int k = 0; k < warm_count; ++k) {
            warm_rows_(k) = result_.active(k);
        }
        reset_result();
        if (!factorise()) {
            result_.status = QpStatus::not_positive_definite;
            return;
        }
        start_unconstrained();
        QpStatus status = QpStatus::solved;
        for (int k = 0; k < warm_count && status == QpStatus::solved; ++k) {
            const Index row = warm_rows_(k);
            if (!is_active_(row) && violation_of(row) > 0) {
                status = add_row(row);
            }
        }
        while (status == QpStatus::solved) {
            const Index row = most_violated_row();
            if (row < 0) {
                break;
            }
            status = add_row(row);
        }
        finish(status);
    }

    void reset_result() noexcept
    {
        result_.x.setZero();
        result_.multipliers.setZero();
        result_.active.setConstant(-1);
        result_.active_count = 0;
        result_.iterations = 0;
        result_.objective = 0;
    }

    /// H = L L^T and J = L^-T (Q = I, no row active). False when H is not numerically positive
    /// definite by the pivot policy (numerics/pivot_policy.hpp: a pivot L_jj^2 at or below
    /// 1000 eps max_i H_ii counts as zero): J would amplify the rounding noise such a pivot holds.
    bool factorise() noexcept
    {
        if (!regular_llt(llt_)) {
            return false;
        }
        invert_transposed_factor();
        return true;
    }

    /// basis_ = L^-T (upper triangular), by back substitution on L^T J = I, column by column; also
    /// |L^-1|_F, the scale of the rounding in J^T c (used by the dependence test).
    void invert_transposed_factor() noexcept
    {
        const auto& factor = llt_.matrixLLT();
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
    }

    /// x = -H^-1 g = -J J^T g; no row active.
    void start_unconstrained() noexcept
    {
        step_.noalias() = basis_.transpose() * gradient_;
        x().noalias() = basis_ * step_;
        x() = -x();  // negated apart: -(product) would evaluate into a heap temporary for dynamic sizes
        // Square roots of the whole vector at once (they vectorise; one per row would not).
        row_norms_ = constraints_.colwise().squaredNorm().transpose();
        row_norms_ = row_norms_.cwiseSqrt();
        is_active_.setZero();
        active_count_ = 0;
    }

    Vector& x() noexcept { return result_.x; }

    /// c_i^T x - d_i when it exceeds the rounding level of evaluating it, else 0.
    Scalar violation_of(Index row) const noexcept
    {
        using std::abs;
        const Scalar residual = constraints_.col(row).dot(result_.x) - bounds_(row);
        const Scalar noise = feasibility_tolerance() * (row_norms_(row) * result_.x.norm() + abs(bounds_(row)));
        return residual > noise ? residual : Scalar(0);
    }

    /// The inactive row with the largest violation per unit row norm, or -1 when none is violated.
    /// A zero row is violated only when d_i < 0, and then no step can help: it is returned first
    /// and add_row reports infeasibility.
    Index most_violated_row() noexcept
    {
        using std::abs;
        violations_.noalias() = constraints_.transpose() * result_.x;
        const Scalar x_norm = result_.x.norm();
        Index worst = -1;
        Scalar worst_distance = 0;
        for (Index i = 0; i < rows_; ++i) {
            if (is_active_(i)) {
                continue;
            }
            const Scalar residual = violations_(i) - bounds_(i);
            const Scalar noise = feasibility_tolerance() * (row_norms_(i) * x_norm + abs(bounds_(i)));
            if (!(residual > noise)) {
                continue;
            }
            if (!(row_norms_(i) > 0)) {
                return i;
            }
            const Scalar distance = residual / row_norms_(i);
            if (distance > worst_distance) {
                worst_distance = distance;
                worst = i;
            }
        }
        return worst;
    }

    /// Goldfarb-Idnani's step 2 for row p: partial steps and dual-only steps (each dropping one
    /// active row) until a full step adds p, the problem proves infeasible or the cap is reached.
    QpStatus add_row(Index row) noexcept
    {
        Scalar entering_multiplier = 0;
        for (;;) {
            if (result_.iterations >= iteration_limit_) {
                return QpStatus::iteration_limit;
            }
            ++result_.iterations;
            const Step step = take_step(row, entering_multiplier);
            if (step == Step::added) {
                return QpStatus::solved;
            }
            if (step == Step::infeasible) {
                return QpStatus::infeasible;
            }
        }
    }

    /// One primal/dual step towards activating `row` (see the file comment).
    Step take_step(Index row, Scalar& entering_multiplier) noexcept
    {
        const Scalar complement_squared = compute_directions(row);
        const Index blocking = blocking_position();
        const Scalar partial_length = blocking >= 0 ? active_multipliers_(blocking) / dual_direction_(blocking)
                                                    : std::numeric_limits<Scalar>::infinity();
        if (!primal_step_possible(row, complement_squared)) {
            if (blocking < 0) {
                return Step::infeasible;  // no multiplier can give way: the rows contradict
            }
            move_multipliers(partial_length, entering_multiplier);
            drop_active(blocking);
            return Step::dropped;
        }
        // Along z, c_p^T x decreases by |d2|^2 per unit step (z^T c_p = -|J2^T c_p|^2).
        using std::max;
        const Scalar residual = constraints_.col(row).dot(result_.x) - bounds_(row);
        const Scalar full_length = max(residual, Scalar(0)) / complement_squared;
        if (full_length <= partial_length) {
            x() += full_length * direction_;
            move_multipliers(full_length, entering_multiplier);
            append_active(row, entering_multiplier);
            return Step::added;
        }
        x() += partial_length * direction_;
        move_multipliers(partial_length, entering_multiplier);
        drop_active(blocking);
        return Step::dropped;
    }

    /// For the row p being added, with n_p = -c_p (Goldfarb and Idnani write rows as n^T x >= b):
    /// step_ = J^T n_p; direction_ = z = J2 J2^T n_p (the primal direction, J2 the last n - q
    /// columns of J); dual_direction_ = r = R^-1 (J1^T n_p) (how fast the active multipliers
    /// decrease). Returns |J2^T n_p|^2 = z^T n_p.
    Scalar compute_directions(Index row) noexcept
    {
        const Index q = active_count_;
        step_.noalias() = basis_.transpose() * constraints_.col(row);
        step_ = -step_;  // n_p = -c_p; negated apart, see start_unconstrained
        direction_.setZero();
        Scalar complement_squared = 0;
        for (Index j = q; j < variables_; ++j) {
            direction_ += step_(j) * basis_.col(j);
            complement_squared += step_(j) * step_(j);
        }
        solve_triangle(q);
        return complement_squared;
    }

    /// r = R^-1 step_.head(q) by back substitution. An entry within the rounding of its own
    /// computation is set to zero: its sign is noise, and a noise-positive r_j would drop a row
    /// (or hide an infeasibility) for no reason.
    void solve_triangle(Index q) noexcept
    {
        using std::abs;
        const Scalar noise = Scalar(8) * static_cast<Scalar>(variables_) * std::numeric_limits<Scalar>::epsilon();
        for (Index i = q - 1; i >= 0; --i) {
            Scalar sum = step_(i);
            Scalar magnitude = abs(step_(i));
            for (Index k = i + 1; k < q; ++k) {
                sum -= triangle_(i, k) * dual_direction_(k);
                magnitude += abs(triangle_(i, k) * dual_direction_(k));
            }
            dual_direction_(i) = abs(sum) > noise * magnitude ? sum / triangle_(i, i) : Scalar(0);
        }
    }

    /// z counts as zero when |J2^T c_p| is within the rounding of J^T c_p (about eps |L^-1|_F |c_p|,
    /// amplified by the rotations applied to J): c_p then depends linearly on the active rows.
    bool primal_step_possible(Index row, Scalar complement_squared) const noexcept
    {
        const Scalar floor = Scalar(64) * static_cast<Scalar>(variables_) * std::numeric_limits<Scalar>::epsilon() *
                             basis_norm_ * row_norms_(row);
        return complement_squared > floor * floor;
    }

    /// Position in the active set of the row whose multiplier reaches zero first along the dual
    /// direction (smallest u_j / r_j over r_j > 0), or -1 when no multiplier decreases.
    Index blocking_position() const noexcept
    {
        Index blocking = -1;
        Scalar shortest = 0;
        for (Index j = 0; j < active_count_; ++j) {
            if (dual_direction_(j) > 0) {
                const Scalar length = active_multipliers_(j) / dual_direction_(j);
                if (blocking < 0 || length < shortest) {
                    shortest = length;
                    blocking = j;
                }
            }
        }
        return blocking;
    }

    /// u_active -= t r, u_p += t (clamped at zero: the blocking multiplier lands there up to
    /// rounding).
    void move_multipliers(Scalar length, Scalar& entering_multiplier) noexcept
    {
        using std::max;
        for (Index j = 0; j < active_count_; ++j) {
            active_multipliers_(j) = max(active_multipliers_(j) - length * dual_direction_(j), Scalar(0));
        }
        entering_multiplier += length;
    }

    /// Rotates J^T c_p (step_) so that its entries q+1.. vanish, applying the same rotations to
    /// J's columns, and appends the result as R's new column q.
    void append_active(Index row, Scalar multiplier) noexcept
    {
        const Index q = active_count_;
        for (Index j = variables_ - 1; j > q; --j) {
            rotate_basis(j - 1, j, step_(j - 1), step_(j));
        }
        for (Index i = 0; i <= q; ++i) {
            triangle_(i, q) = step_(i);
        }
        active_rows_(q) = static_cast<int>(row);
        active_multipliers_(q) = multiplier;
        is_active_(row) = 1;
        ++active_count_;
    }

    /// Removes the active row at `position`: R loses that column, and the rotations that restore
    /// its triangular shape are applied to J's columns as well.
    void drop_active(Index position) noexcept
    {
        const Index q = active_count_;
        is_active_(active_rows_(position)) = 0;
        for (Index j = position; j + 1 < q; ++j) {
            active_rows_(j) = active_rows_(j + 1);
            active_multipliers_(j) = active_multipliers_(j + 1);
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
        --active_count_;
    }

    /// A plane rotation [c s; -s c] with c a + s b = |(a, b)| and -s a + c b = 0.
    struct Givens {
        Scalar c = 1;
        Scalar s = 0;
        Scalar norm = 0;

        static Givens zeroing(Scalar a, Scalar b) noexcept
        {
            using std::sqrt;
            Givens rotation;
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
        /// The same rotation on J's columns (J^T's rows), keeping J^T [rows] = [R; 0]. Through
        /// plain pointers to the two (contiguous, distinct) columns so that the loop vectorises:
        /// these rotations are the largest part of a step.
        void apply_to_columns(Matrix& matrix, Index first, Index second) const noexcept
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

    /// Zeroes step_(second) against step_(first), rotating J's columns alike.
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

    /// Multipliers per row, the active set and the objective 1/2 |L^T x|^2 + g^T x.
    void finish(QpStatus status) noexcept
    {
        result_.status = status;
        for (Index j = 0; j < active_count_; ++j) {
            result_.multipliers(active_rows_(j)) = active_multipliers_(j);
            result_.active(j) = active_rows_(j);
        }
        result_.active_count = static_cast<int>(active_count_);
        const auto& factor = llt_.matrixLLT();
        Scalar curvature = 0;
        for (Index i = 0; i < variables_; ++i) {
            Scalar entry = 0;  // (L^T x)_i
            for (Index k = i; k < variables_; ++k) {
                entry += factor(k, i) * result_.x(k);
            }
            curvature += entry * entry;
        }
        result_.objective = Scalar(0.5) * curvature + gradient_.dot(result_.x);
    }

    Index variables_;
    Index rows_;
    int iteration_limit_;
    Llt<Matrix> llt_;                  ///< H = L L^T (unrolled for fixed sizes)
    Vector gradient_;                  ///< g
    ConstraintMatrix constraints_;     ///< C^T: row i's normal c_i is column i
    RowVector bounds_;                 ///< d
    RowVector row_norms_;              ///< |c_i|
    RowVector violations_;             ///< C x (scratch)
    RowFlags is_active_;               ///< 1 for rows in the active set
    Matrix basis_;                     ///< J = L^-T Q
    Matrix triangle_;                  ///< R (q x q upper triangle in use)
    Scalar basis_norm_ = 0;            ///< |L^-1|_F = |J|_F
    Vector step_;                      ///< J^T n_p
    Vector direction_;                 ///< z
    Vector dual_direction_;            ///< r (first q entries)
    Vector active_multipliers_;        ///< u (first q entries)
    ActiveList active_rows_;           ///< active rows in order of entry (first q entries)
    ActiveList warm_rows_;             ///< the previous active set, for solve_warm
    Index active_count_ = 0;           ///< q
    Result result_;
};

/// \brief One-shot min 1/2 x^T H x + g^T x s.t. C x <= d (Goldfarb-Idnani; a thin wrapper around a
/// QpSolver built for this call). Sizes come from the arguments' compile-time sizes: n from H or g,
/// m from C or d; Eigen::Dynamic when none is fixed. With fixed sizes nothing is allocated (and
/// nothing throws); dynamic sizes allocate the workspace and the returned result.
/// \param hessian H, n x n symmetric positive definite (lower triangle read).
/// \param gradient g, n.
/// \param constraints C, m x n.
/// \param bounds d, m.
/// \return x (n), multipliers (m), status, iterations, objective and active set.
template <typename H, typename G, typename C, typename D>
auto solve_qp(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
              const Eigen::MatrixBase<C>& constraints, const Eigen::MatrixBase<D>& bounds)
{
    using Scalar = typename H::Scalar;
    constexpr int variables = detail::first_fixed(
        detail::first_fixed(H::RowsAtCompileTime, H::ColsAtCompileTime),
        detail::first_fixed(G::RowsAtCompileTime, C::ColsAtCompileTime));
    constexpr int rows = detail::first_fixed(C::RowsAtCompileTime, D::RowsAtCompileTime);
    QpSolver<Scalar, variables, rows> solver(hessian.rows(), constraints.rows());
    return QpResult<Scalar, variables, rows>(solver.solve(hessian, gradient, constraints, bounds));
}

}  // namespace coopdyn
