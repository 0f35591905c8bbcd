// The second paper's kernels (Lin et al.; docs/control.md): the projected dynamics, the grasp
// Jacobians, the internal-wrench basis, the friction rows and margins. The controller that uses
// them is in controller.cpp, which binds ContactFriction before calling bind_control_kernels.
// Sizes K (contacts), Q (joints) and the pyramids' edges are chosen at run time (Eigen::Dynamic).
#include "common.hpp"

#include <coopdyn/control.hpp>

#include <string>

namespace coopdyn::python {

namespace {

constexpr int X = Eigen::Dynamic;
using Friction = ContactFriction<double>;
using Projection = ProjectedDynamics<double, X, X>;

void bind_projection(py::module_& module)
{
    py::enum_<ProjectionStatus>(module, "ProjectionStatus", "Outcome of the projected dynamics.")
        .value("ok", ProjectionStatus::ok)
        .value("singular_constraint", ProjectionStatus::singular_constraint, "J lost rank")
        .value("singular_task", ProjectionStatus::singular_task, "the object cannot be moved in some direction");

    py::class_<Projection> projection(module, "ProjectedDynamics",
                                      "Projected inverse dynamics L(4), (13), (15), (26) at one configuration "
                                      "(docs/control.md). Every field is a read-only copy.");
    projection.def_property_readonly("status", [](const Projection& self) { return self.status; }, "ProjectionStatus (a copy)");
    def_output(projection, "contact_offsets", &Projection::contact_offsets, "r (3, K), {w}");
    def_output(projection, "grasp", &Projection::grasp, "G (6, 6K), (24)");
    def_output(projection, "object_jacobian", &Projection::object_jacobian, "Jx (6, Q)");
    def_output(projection, "constraint_jacobian", &Projection::constraint_jacobian, "Jc (6K, Q), L(13)");
    def_output(projection, "internal_basis", &Projection::internal_basis, "B (6K, 6K - 6), orthonormal, G B = 0");
    def_output(projection, "reduced_jacobian_transpose", &Projection::reduced_jacobian_transpose, "J^T B (Q, 6K - 6)");
    def_output(projection, "projector", &Projection::projector, "P (Q, Q), L(4)");
    def_output(projection, "constrained_inertia", &Projection::constrained_inertia, "Mc (Q, Q), L(26)");
    def_output(projection, "task_inertia", &Projection::task_inertia, "Lambda_c (6, 6), L(15)");
    def_output(projection, "task_bias", &Projection::task_bias, "hc (6,), L(15)");
    def_output(projection, "object_twist", &Projection::object_twist, "Jx qdot (6,)");
    def_output(projection, "object_jacobian_rate_qdot", &Projection::object_jacobian_rate_qdot, "Jxdot qdot (6,)");
    def_output(projection, "constraint_jacobian_rate_qdot", &Projection::constraint_jacobian_rate_qdot,
               "Jcdot qdot (6K,)");
    def_output(projection, "projector_rate_qdot", &Projection::projector_rate_qdot, "Pdot qdot (Q,)");

    module.def(
        "projected_dynamics",
        [](ArrayLike m_in, ArrayLike h_in, ArrayLike j_in, ArrayLike jdot_in, ArrayLike qdot_in, ArrayLike r_in) {
            constexpr const char* name = "projected_dynamics";
            const Matrix r = to_matrix(r_in, name, "r", 3, any_size, "(3, K)");
            const Index arms = r.cols();
            if (arms < 2) {
                fail_argument(name, "r", "must have K >= 2 columns, got " + std::to_string(arms));
            }
            const Matrix jacobian = to_matrix(j_in, name, "J", 6 * arms, any_size, ("(6K, Q) = (" + std::to_string(6 * arms) + ", Q)").c_str());
            const Index joints = jacobian.cols();
            if (joints < 6 * arms) {
                fail_argument(name, "J", "must have Q >= 6K = " + std::to_string(6 * arms) + " columns, got " +
                                             std::to_string(joints));
            }
            const Matrix inertia = to_matrix(m_in, name, "M", joints, joints, ("(Q, Q) = " + dims(joints, joints)).c_str());
            const Vector bias = to_vector(h_in, name, "h", joints, ("(Q,) = " + dims(joints)).c_str());
            const Vector rate = to_vector(jdot_in, name, "Jdot_qdot", 6 * arms, ("(6K,) = " + dims(6 * arms)).c_str());
            const Vector velocities = to_vector(qdot_in, name, "qdot", joints, ("(Q,) = " + dims(joints)).c_str());
            py::gil_scoped_release unlocked;
            Projection result(arms, joints);
            result.compute(inertia, bias, jacobian, rate, velocities, r);
            return result;
        },
        py::arg("M"), py::arg("h"), py::arg("J"), py::arg("Jdot_qdot"), py::arg("qdot"), py::arg("r"),
        R"doc(projected_dynamics(M, h, J, Jdot_qdot, qdot, r) -> ProjectedDynamics

Projected inverse dynamics L(4), (13), (15), (26) of K arms holding an object (docs/control.md):
M (Q, Q) joint inertia, SPD; h (Q,) bias; J (6K, Q) stacked contact Jacobians; Jdot_qdot (6K,);
qdot (Q,) satisfying the grasp (Jc qdot = 0); r (3, K) contact points from the object's centre, {w}.
K >= 2, Q >= 6K. Check .status. Releases the GIL.)doc");

    module.def(
        "object_jacobian",
        [](ArrayLike r_in, ArrayLike j_in) {
            const Matrix r = to_matrix(r_in, "object_jacobian", "r", 3, any_size, "(3, K)");
            const Matrix jacobian = to_matrix(j_in, "object_jacobian", "J", 6 * r.cols(), any_size,
                                              ("(6K, Q) = (" + std::to_string(6 * r.cols()) + ", Q)").c_str());
            if (r.cols() < 1) {
                fail_argument("object_jacobian", "r", "must have K >= 1 columns");
            }
            return matrix_copy(coopdyn::object_jacobian(r, jacobian));
        },
        py::arg("r"), py::arg("J"),
        "object_jacobian(r, J) -> (6, Q): Jx = (G G^T)^-1 G J, the object's twist Jx qdot while the grasp holds "
        "(docs/model.md, \"Grasp Jacobians\"). r (3, K), J (6K, Q).");
    module.def(
        "constraint_jacobian",
        [](ArrayLike r_in, ArrayLike j_in) {
            const Matrix r = to_matrix(r_in, "constraint_jacobian", "r", 3, any_size, "(3, K)");
            const Matrix jacobian = to_matrix(j_in, "constraint_jacobian", "J", 6 * r.cols(), any_size,
                                              ("(6K, Q) = (" + std::to_string(6 * r.cols()) + ", Q)").c_str());
            if (r.cols() < 1) {
                fail_argument("constraint_jacobian", "r", "must have K >= 1 columns");
            }
            return matrix_copy(coopdyn::constraint_jacobian(r, jacobian));
        },
        py::arg("r"), py::arg("J"),
        "constraint_jacobian(r, J) -> (6K, Q): Jc = (I - G^+ G) J = J - G^T Jx, Lin et al. L(13), rank 6K - 6 "
        "(errata E10). r (3, K), J (6K, Q).");
    module.def(
        "internal_wrench_basis",
        [](ArrayLike r_in) {
            const Matrix r = to_matrix(r_in, "internal_wrench_basis", "r", 3, any_size, "(3, K)");
            if (r.cols() < 2) {
                fail_argument("internal_wrench_basis", "r", "must have K >= 2 columns, got " + std::to_string(r.cols()));
            }
            return matrix_copy(coopdyn::internal_wrench_basis(r));
        },
        py::arg("r"),
        "internal_wrench_basis(r) -> (6K, 6K - 6): an orthonormal basis B of the internal wrenches, the null space "
        "of the grasp matrix G (24): G B = 0, B^T B = I (docs/control.md). r (3, K), K >= 2.");
}

Friction checked_friction(const Friction& friction)
{
    if (friction.pyramid_edges < 3 || friction.pyramid_edges > max_pyramid_edges) {
        friction.validate(no_arm);  // raises InvalidModel naming pyramid_edges
    }
    return friction;
}

void bind_friction(py::module_& module)
{
    module.def(
        "friction_margin",
        [](const Friction& friction, ArrayLike wrench_in) {
            const Vector wrench = to_vector(wrench_in, "friction_margin", "wrench", 6, "(6,)");
            const Vector6<double> w = wrench;
            return coopdyn::friction_margin(checked_friction(friction), w);
        },
        py::arg("friction"), py::arg("wrench"),
        "friction_margin(friction, wrench) -> float: min_k (b_k - a_k^T w) / |a_k| over the contact's friction rows "
        "L(17)-(19) (errata E9) for the wrench w = [f; t] (6,) in the contact frame: > 0 inside, < 0 violated "
        "(N for force rows, N m for moment rows; docs/control.md).");
    module.def(
        "friction_margins",
        [](const Friction& friction, ArrayLike wrench_in) {
            const Vector wrench = to_vector(wrench_in, "friction_margins", "wrench", 6, "(6,)");
            const Vector6<double> w = wrench;
            const FrictionMargins<double> margins = coopdyn::friction_margins(checked_friction(friction), w);
            return py::make_tuple(margins.force, margins.moment);
        },
        py::arg("friction"), py::arg("wrench"),
        "friction_margins(friction, wrench) -> (force, moment): friction_margin split into the force rows' margin "
        "(unilateral and pyramid, N) and the moment rows' (torsion and centre of pressure, N m).");
    module.def(
        "contact_frame_friction_rows",
        [](const Friction& friction) {
            const Friction checked = checked_friction(friction);
            const Index count = friction_rows(checked.pyramid_edges);
            Eigen::Matrix<double, Eigen::Dynamic, 6> rows = Eigen::Matrix<double, Eigen::Dynamic, 6>::Zero(count, 6);
            Vector bounds = Vector::Zero(count);
            contact_frame_friction_rows(checked, rows, bounds);
            return py::make_tuple(matrix_copy(rows), vector_copy(bounds));
        },
        py::arg("friction"),
        "contact_frame_friction_rows(friction) -> (A (n + 7, 6), b (n + 7,)): the rows A [f; t] <= b of L(17)-(19) "
        "with errata E9, in the order unilateral, the n pyramid facets, torsion (+, -), t_x (+, -), t_y (+, -).");
}

}  // namespace

void bind_control_kernels(py::module_& module)
{
    bind_projection(module);
    bind_friction(module);
}

}  // namespace coopdyn::python
