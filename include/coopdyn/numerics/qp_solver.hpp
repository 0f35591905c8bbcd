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
/// Numerics: H is factorised once per solve (L L^T: FixedLlt for fixed sizes, Eigen::LLT
/// otherwise); J = L^-T Q (Q orthogonal) and the upper-triangular R with J^T [active rows as
/// columns] = [R; 0] are updated by Givens rotations when a row enters or leaves, never
/// refactorised, never inverted (numerics/qp_active_set.hpp). C is kept between solves, as C and
/// C^T with its rows' norms, so a constant C is given once (set_constraints).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"
#include "coopdyn/numerics/qp_active_set.hpp"

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
/// once and nothing else does. Solves are noexcept; their size and finiteness preconditions are
/// debug assertions, except that a problem of another size than the workspace stops the program
/// in Release too (COOPDYN_REQUIRE_SHAPE), instead of writing past a buffer.
///
/// Constant constraints (a controller's friction rows): give C once (constructor or
/// set_constraints()) and solve each tick with H, g and d only. solve(H, g, C, d) is
/// set_constraints(C) followed by solve(H, g, d): the same answer.
template <typename Scalar, int Variables, int Rows> class QpSolver {
    static_assert(Variables == Eigen::Dynamic || Variables > 0, "QpSolver: at least one variable");
    static_assert(Rows == Eigen::Dynamic || Rows > 0,
                  "QpSolver: a fixed number of rows must be positive (use Dynamic for a problem without rows)");

public:
    using Result = QpResult<Scalar, Variables, Rows>;
    /// C, m x n.
    using ConstraintMatrix = Eigen::Matrix<Scalar, Rows, Variables>;

    /// Workspace for fixed sizes (a template so that an explicit instantiation for dynamic sizes
    /// does not instantiate it). C is zero until set_constraints().
    template <int V = Variables, int R = Rows,
              std::enable_if_t<V != Eigen::Dynamic && R != Eigen::Dynamic, int> = 0>
    QpSolver() : QpSolver(Variables, Rows)
    {
    }

    /// Workspace for n = `variables` unknowns and m = `rows` inequality rows (must equal the
    /// compile-time sizes when those are fixed). Allocates all dynamic storage. C is zero until
    /// set_constraints().
    QpSolver(Index variables, Index rows)
        : variables_(variables),
          rows_(rows),
          iteration_limit_(default_iteration_limit(variables, rows)),
          llt_(variables),
          gradient_(variables),
          constraints_(ConstraintMatrix::Zero(rows, variables)),
          normals_(NormalMatrix::Zero(variables, rows)),
          bounds_(rows),
          row_norms_(RowVector::Zero(rows)),
          inverse_row_norms_(RowVector::Zero(rows)),
          violations_(rows),
          is_active_(rows),
          warm_rows_(variables),
          active_(variables),
          result_(variables, rows)
    {
        COOPDYN_REQUIRE_SHAPE(variables > 0 && rows >= 0, "QpSolver: needs n > 0 variables and m >= 0 rows");
        COOPDYN_REQUIRE_SHAPE(Variables == Eigen::Dynamic || variables == Variables,
                              "QpSolver: number of variables differs from the compile-time size");
        COOPDYN_REQUIRE_SHAPE(Rows == Eigen::Dynamic || rows == Rows,
                              "QpSolver: number of rows differs from the compile-time size");
    }

    /// Workspace sized by C (n = its columns, m = its rows), with C set (set_constraints): for a
    /// problem whose constraint matrix is constant.
    template <typename C>
    explicit QpSolver(const Eigen::MatrixBase<C>& constraints) : QpSolver(constraints.cols(), constraints.rows())
    {
        set_constraints(constraints);
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

    /// \brief Sets C (m x n) for the solves that follow: kept as C (for C x, all rows at once) and
    /// as C^T (each row's normal a contiguous column), with the rows' norms and their inverses.
    /// Allocates nothing (the workspace was sized at construction). The previous solve's active
    /// set stays the warm start of the next solve_warm().
    template <typename C> void set_constraints(const Eigen::MatrixBase<C>& constraints) noexcept
    {
        static_assert(detail::sizes_agree(C::ColsAtCompileTime, Variables) &&
                          detail::sizes_agree(C::RowsAtCompileTime, Rows),
                      "QpSolver: C's sizes disagree with the solver's sizes");
        COOPDYN_REQUIRE_SHAPE(constraints.rows() == rows_ && constraints.cols() == variables_,
                              "QpSolver: C sized for another problem");
        COOPDYN_ASSERT(constraints.allFinite(), "QpSolver: C not finite");
        constraints_ = constraints;
        normals_ = constraints_.transpose();
        // Square roots of the whole vector at once (they vectorise; one per row would not).
        row_norms_ = constraints_.rowwise().squaredNorm();
        row_norms_ = row_norms_.cwiseSqrt();
        // 1 / |c_i| for the most-violated scan (multiplied, not divided, on every scan), all at
        // once (vectorised divisions); a zero row's +inf is never read (most_violated_row
        // returns such a row before using its inverse).
        inverse_row_norms_ = row_norms_.cwiseInverse();
    }

    /// The C of the last set_constraints() (zero before it).
    const ConstraintMatrix& constraints() const noexcept { return constraints_; }

    /// \brief Cold solve of min 1/2 x^T H x + g^T x s.t. C x <= d, C the one set last
    /// (constructor or set_constraints()).
    /// \param hessian H, n x n symmetric positive definite (only its lower triangle is read).
    /// \param gradient g, n.
    /// \param bounds d, m.
    /// \return result(): x, multipliers, status, active set (valid until the next solve).
    template <typename H, typename G, typename D>
    const Result& solve(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
                        const Eigen::MatrixBase<D>& bounds) noexcept
    {
        load(hessian, gradient, bounds);
        run(false);
        return result_;
    }

    /// \brief Warm solve: as solve(H, g, d), starting from the active set of the previous solve.
    /// The rows active last time are added first, each by the same Goldfarb-Idnani steps as any
    /// other row (a row that no longer fits is dropped again by those steps), then the ordinary
    /// iteration finishes. The answer is the same as solve()'s (the minimiser is unique); when
    /// consecutive problems share their active set it usually takes fewer steps.
    template <typename H, typename G, typename D>
    const Result& solve_warm(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
                             const Eigen::MatrixBase<D>& bounds) noexcept
    {
        load(hessian, gradient, bounds);
        run(true);
        return result_;
    }

    /// \brief Cold solve with C given too: set_constraints(C), then solve(H, g, d).
    template <typename H, typename G, typename C, typename D>
    const Result& solve(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
                        const Eigen::MatrixBase<C>& constraints, const Eigen::MatrixBase<D>& bounds) noexcept
    {
        set_constraints(constraints);
        return solve(hessian, gradient, bounds);
    }

    /// \brief Warm solve with C given too: set_constraints(C), then solve_warm(H, g, d).
    template <typename H, typename G, typename C, typename D>
    const Result& solve_warm(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
                             const Eigen::MatrixBase<C>& constraints, const Eigen::MatrixBase<D>& bounds) noexcept
    {
        set_constraints(constraints);
        return solve_warm(hessian, gradient, bounds);
    }

private:
    using Matrix = Eigen::Matrix<Scalar, Variables, Variables>;
    using Vector = Eigen::Matrix<Scalar, Variables, 1>;
    using NormalMatrix = Eigen::Matrix<Scalar, Variables, Rows>;
    using RowVector = Eigen::Matrix<Scalar, Rows, 1>;
    using RowFlags = Eigen::Matrix<int, Rows, 1>;
    using ActiveList = Eigen::Matrix<int, Variables, 1>;

    /// What one step did to the row being added.
    enum class Step { added, dropped, infeasible };

    /// Checks the shapes, factorises H and copies g and d into the workspace.
    template <typename H, typename G, typename D>
    void load(const Eigen::MatrixBase<H>& hessian, const Eigen::MatrixBase<G>& gradient,
              const Eigen::MatrixBase<D>& bounds) noexcept
    {
        static_assert(detail::sizes_agree(H::RowsAtCompileTime, Variables) &&
                          detail::sizes_agree(H::ColsAtCompileTime, Variables) &&
                          detail::sizes_agree(G::RowsAtCompileTime, Variables) &&
                          detail::sizes_agree(D::RowsAtCompileTime, Rows),
                      "QpSolver: argument sizes disagree with the solver's sizes");
        // One comparison each (none survive for fixed sizes): a wrong size would read or write
        // past the workspace.
        COOPDYN_REQUIRE_SHAPE(hessian.rows() == variables_ && hessian.cols() == variables_ &&
                                  gradient.rows() == variables_ && gradient.cols() == 1 &&
                                  bounds.rows() == rows_ && bounds.cols() == 1,
                              "QpSolver: H, g or d sized for another problem");
        COOPDYN_ASSERT(hessian.allFinite() && gradient.allFinite(), "QpSolver: H or g not finite");
        COOPDYN_ASSERT(bounds.allFinite(), "QpSolver: d not finite");
        llt_.compute(hessian);
        gradient_ = gradient;
        bounds_ = bounds;
    }

    /// The whole iteration; writes result_. A warm start first re-adds the previous solve's
    /// active rows (those violated at the current iterate), in their order of entry.
    void run(bool warm) noexcept
    {
        const int warm_count = warm ? result_.active_count : 0;
        for (int k = 0; k < warm_count; ++k) {
            warm_rows_(k) = result_.active(k);
        }
        reset_result();
        // H = L L^T; refused when not numerically positive definite by the pivot policy
        // (numerics/pivot_policy.hpp: a pivot L_jj^2 at or below 1000 eps max_i H_ii counts as
        // zero): J = L^-T would amplify the rounding noise such a pivot holds.
        if (!regular_llt(llt_)) {
            result_.status = QpStatus::not_positive_definite;
            return;
        }
        active_.start(llt_.matrixLLT());
        active_.unconstrained_minimum(gradient_, result_.x);
        is_active_.setZero();
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

    /// c_i^T x - d_i when it exceeds the rounding level of evaluating it, else 0.
    Scalar violation_of(Index row) const noexcept
    {
        using std::abs;
        const Scalar residual = normals_.col(row).dot(result_.x) - bounds_(row);
        const Scalar noise = feasibility_tolerance() * (row_norms_(row) * result_.x.norm() + abs(bounds_(row)));
        return residual > noise ? residual : Scalar(0);
    }

    /// The inactive row with the largest violation per unit row norm, or -1 when none is violated.
    /// A zero row is violated only when d_i < 0, and then no step can help: it is returned first
    /// and add_row reports infeasibility.
    Index most_violated_row() noexcept
    {
        using std::abs;
        // C x for all rows at once: C is column-major m x n, so this is n vectorised column
        // updates (coefficient-based: no GEMV dispatch at these sizes).
        violations_.noalias() = constraints_.lazyProduct(result_.x);
        const Scalar x_norm = result_.x.norm();
        Index worst = -1;
        Scalar worst_distance = 0;
        for (Index i = 0; i < rows_; ++i) {
            const Scalar residual = violations_(i) - bounds_(i);
            const Scalar noise = feasibility_tolerance() * (row_norms_(i) * x_norm + abs(bounds_(i)));
            if (is_active_(i) || !(residual > noise)) {
                continue;
            }
            if (!(row_norms_(i) > 0)) {
                return i;
            }
            const Scalar distance = residual * inverse_row_norms_(i);
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
        const Scalar complement_squared = active_.compute_directions(normals_.col(row));
        const Index blocking = active_.blocking_position();
        const Scalar partial_length = active_.partial_length(blocking);
        if (!active_.primal_step_possible(complement_squared, row_norms_(row))) {
            if (blocking < 0) {
                return Step::infeasible;  // no multiplier can give way: the rows contradict
            }
            active_.move_multipliers(partial_length, entering_multiplier);
            is_active_(active_.drop(blocking)) = 0;
            return Step::dropped;
        }
        // Along z, c_p^T x decreases by |d2|^2 per unit step (z^T c_p = -|J2^T c_p|^2).
        using std::max;
        const Scalar residual = normals_.col(row).dot(result_.x) - bounds_(row);
        const Scalar full_length = max(residual, Scalar(0)) / complement_squared;
        if (full_length <= partial_length) {
            result_.x += full_length * active_.direction();
            active_.move_multipliers(full_length, entering_multiplier);
            active_.append(static_cast<int>(row), entering_multiplier);
            is_active_(row) = 1;
            return Step::added;
        }
        result_.x += partial_length * active_.direction();
        active_.move_multipliers(partial_length, entering_multiplier);
        is_active_(active_.drop(blocking)) = 0;
        return Step::dropped;
    }

    /// Multipliers per row, the active set and the objective 1/2 |L^T x|^2 + g^T x.
    void finish(QpStatus status) noexcept
    {
        result_.status = status;
        for (Index j = 0; j < active_.size(); ++j) {
            result_.multipliers(active_.row(j)) = active_.multiplier(j);
            result_.active(j) = active_.row(j);
        }
        result_.active_count = static_cast<int>(active_.size());
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
    ConstraintMatrix constraints_;     ///< C (set_constraints): C x for every row at once
    NormalMatrix normals_;             ///< C^T: row i's normal c_i is column i
    RowVector bounds_;                 ///< d
    RowVector row_norms_;              ///< |c_i|
    RowVector inverse_row_norms_;      ///< 1 / |c_i| (+inf for a zero row, never read)
    RowVector violations_;             ///< C x (scratch)
    RowFlags is_active_;               ///< 1 for rows in the active set
    ActiveList warm_rows_;             ///< the previous active set, for solve_warm
    detail::QpActiveSet<Scalar, Variables> active_;  ///< J, R, the active rows and multipliers
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
