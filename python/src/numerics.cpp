// coopdyn/numerics: the Goldfarb-Idnani QP solver (docs/qp_solver.md) as solve_qp(H, g, C, d).
#include "common.hpp"

#include <coopdyn/numerics/qp_solver.hpp>

namespace coopdyn::python {

namespace {

using QpResultX = QpResult<double, Eigen::Dynamic, Eigen::Dynamic>;

/// The one-shot solve of min 1/2 x^T H x + g^T x s.t. C x <= d, every argument checked first.
QpResultX solve(ArrayLike hessian_in, ArrayLike gradient_in, ArrayLike constraints_in, ArrayLike bounds_in)
{
    constexpr const char* name = "solve_qp";
    const Matrix hessian = to_matrix(hessian_in, name, "H", any_size, any_size, "(n, n)");
    const Index n = hessian.rows();
    if (hessian.cols() != n || n == 0) {
        fail_argument(name, "H", "must be a non-empty square array of shape (n, n), got (" + std::to_string(n) + ", " +
                                     std::to_string(hessian.cols()) + ")");
    }
    const std::string n_text = std::to_string(n);
    const Vector gradient = to_vector(gradient_in, name, "g", n, ("(n,) = (" + n_text + ",)").c_str());
    const Matrix constraints = to_matrix(constraints_in, name, "C", any_size, n, ("(m, n) = (m, " + n_text + ")").c_str());
    const std::string m_text = std::to_string(constraints.rows());
    const Vector bounds = to_vector(bounds_in, name, "d", constraints.rows(), ("(m,) = (" + m_text + ",)").c_str());
    if (!hessian.allFinite() || !gradient.allFinite() || !constraints.allFinite() || !bounds.allFinite()) {
        fail_argument(name, "H, g, C, d", "must be finite");
    }
    py::gil_scoped_release unlocked;
    QpSolver<double, Eigen::Dynamic, Eigen::Dynamic> solver(n, constraints.rows());
    return solver.solve(hessian, gradient, constraints, bounds);
}

}  // namespace

void bind_numerics(py::module_& module)
{
    py::enum_<QpStatus>(module, "QpStatus", "Outcome of a QP solve (docs/qp_solver.md).")
        .value("solved", QpStatus::solved, "every KKT condition holds: x is the minimiser")
        .value("infeasible", QpStatus::infeasible, "no x satisfies C x <= d; x is the last iterate")
        .value("iteration_limit", QpStatus::iteration_limit, "the step cap was reached; x is the last iterate")
        .value("not_positive_definite", QpStatus::not_positive_definite,
               "H is not (numerically) positive definite; x and the multipliers are zero");

    py::class_<QpResultX>(module, "QpResult",
                          "Solution of min 1/2 x^T H x + g^T x s.t. C x <= d (docs/qp_solver.md). Every array "
                          "is a copy owned by the caller.")
        .def_property_readonly("x", [](const QpResultX& r) { return vector_copy(r.x); }, "the minimiser, (n,)")
        .def_property_readonly(
            "multipliers", [](const QpResultX& r) { return vector_copy(r.multipliers); },
            "the Lagrange multipliers, (m,): >= 0, zero for inactive rows")
        .def_property_readonly(
            "active",
            [](const QpResultX& r) {
                py::list rows;
                for (int k = 0; k < r.active_count; ++k) {
                    rows.append(r.active(k));
                }
                return rows;
            },
            "the rows of C active at x (held with equality), in the order they entered")
        .def_readonly("status", &QpResultX::status, "QpStatus")
        .def_readonly("iterations", &QpResultX::iterations, "primal/dual steps taken")
        .def_readonly("objective", &QpResultX::objective, "1/2 x^T H x + g^T x at x")
        .def("__repr__", [](const QpResultX& r) {
            return "QpResult(status=QpStatus." + std::string(to_string(r.status)) +
                   ", iterations=" + std::to_string(r.iterations) + ", objective=" + std::to_string(r.objective) + ")";
        });

    module.def("solve_qp", &solve, py::arg("H"), py::arg("g"), py::arg("C"), py::arg("d"),
               R"doc(solve_qp(H, g, C, d) -> QpResult

Minimises 1/2 x^T H x + g^T x subject to C x <= d by the dual active-set method of Goldfarb and
Idnani (docs/qp_solver.md), cold (no warm start).

H: (n, n) symmetric positive definite (only its lower triangle is read); g: (n,); C: (m, n), m >= 0;
d: (m,). All finite. Returns a QpResult with .x, .status (QpStatus), .multipliers, .iterations,
.objective, .active. Check .status: for infeasible and iteration_limit, x is the last iterate.
Releases the GIL while it solves.)doc");
}

}  // namespace coopdyn::python
