// The first paper's formula kernels (Erhart & Hirche 2016; docs/model.md, docs/dynamics.md,
// docs/coordination.md, docs/analysis.md) on numpy arrays: the grasp matrix (24), the constraint
// matrix and bias (13)-(14), the weighted grasp inverse (25), Udwadia-Kalaba (18), the structured
// interaction wrenches (18), the internal wrenches (53), the apparent impedance (31)-(32) and the
// impedance synthesis (per-arm gains for a target object stiffness or damping, classical damping).
#include "common.hpp"

#include <coopdyn/analysis/apparent_impedance.hpp>
#include <coopdyn/analysis/impedance_synthesis.hpp>
#include <coopdyn/analysis/internal_wrenches.hpp>
#include <coopdyn/coordination/grasp_squeeze.hpp>
#include <coopdyn/coordination/load_distribution.hpp>
#include <coopdyn/dynamics/interaction_wrenches.hpp>
#include <coopdyn/dynamics/udwadia_kalaba.hpp>
#include <coopdyn/model/grasp.hpp>

#include <Eigen/Cholesky>

namespace coopdyn::python {

namespace {

using Offsets = Eigen::Matrix<double, 3, Eigen::Dynamic>;

std::string stack_shape(const char* symbol, Index value)
{
    return std::string(symbol) + " = (" + std::to_string(value) + ",)";
}

Offsets offsets(py::handle value, const char* function, Index minimum_arms = 1)
{
    const Offsets r = to_matrix(value, function, "r", 3, any_size, "(3, N)");
    if (r.cols() < minimum_arms) {
        fail_argument(function, "r", "must have N >= " + std::to_string(minimum_arms) + " columns, got " +
                                         std::to_string(r.cols()));
    }
    return r;
}

/// A (6, 6 cols) stack of symmetric positive definite (or, with semidefinite, semi-definite) blocks.
Matrix symmetric_stack(py::handle value, const char* function, const char* name, Index blocks, bool semidefinite)
{
    const std::string expected = blocks == 1 ? std::string("(6, 6)") : "(6, 6N) = (6, " + std::to_string(6 * blocks) + ")";
    const Matrix stack = to_matrix(value, function, name, 6, 6 * blocks, expected.c_str());
    for (Index i = 0; i < blocks; ++i) {
        const Matrix6<double> block = stack.middleCols<6>(6 * i);
        const double scale = block.cwiseAbs().maxCoeff();
        if (!block.allFinite() || (block - block.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
            fail_argument(function, name, "block " + std::to_string(i) + " must be finite and symmetric");
        }
        if (!semidefinite && Eigen::LLT<Matrix6<double>>(block).info() != Eigen::Success) {
            fail_argument(function, name, "block " + std::to_string(i) + " must be positive definite");
        }
    }
    return stack;
}

/// The load weights of the dense form, checked: mass_weights (N,), inertia_weights (3, 3N).
struct LoadWeights {
    Vector mass;
    Matrix inertia;
};

LoadWeights load_weights(ArrayLike mass_in, ArrayLike inertia_in, const char* function, Index arms)
{
    LoadWeights weights;
    weights.mass = to_vector(mass_in, function, "mass_weights", arms, stack_shape("(N,)", arms).c_str());
    weights.inertia = to_matrix(inertia_in, function, "inertia_weights", 3, 3 * arms,
                                ("(3, 3N) = (3, " + std::to_string(3 * arms) + ")").c_str());
    return weights;
}

py::array udwadia_kalaba_checked(ArrayLike m_in, ArrayLike a_in, ArrayLike b_in, ArrayLike sigma_in)
{
    constexpr const char* name = "udwadia_kalaba";
    const Matrix inertia = to_matrix(m_in, name, "M", any_size, any_size, "(n, n)");
    const Index n = inertia.rows();
    if (inertia.cols() != n || n == 0) {
        fail_argument(name, "M", "must be a non-empty square array of shape (n, n)");
    }
    const Matrix constraints = to_matrix(a_in, name, "A", any_size, n, ("(m, n) = (m, " + std::to_string(n) + ")").c_str());
    const Vector bias = to_vector(b_in, name, "b", constraints.rows(), stack_shape("(m,)", constraints.rows()).c_str());
    const Vector sigma = to_vector(sigma_in, name, "h_sigma", n, stack_shape("(n,)", n).c_str());
    if ((inertia - inertia.transpose()).cwiseAbs().maxCoeff() > 1e-12 * inertia.cwiseAbs().maxCoeff() ||
        Eigen::LLT<Matrix>(inertia).info() != Eigen::Success) {
        fail_argument(name, "M", "must be symmetric positive definite");
    }
    return vector_copy(udwadia_kalaba(inertia, constraints, bias, sigma));
}

}  // namespace

void bind_synthesis(py::module_& module)
{
    using Result = SynthesisResult<double>;
    py::class_<Result>(module, "SynthesisResult",
                       "Per-arm gains whose apparent object matrix (E3) is closest to a target (docs/analysis.md, "
                       "\"Impedance synthesis\"); read-only copies.")
        .def_readonly("achievable", &Result::achievable)
        .def_property_readonly("translational", [](const Result& self) { return vector_copy(self.translational, true); },
                               "k_i (or d_i) per arm (N,), >= 0")
        .def_property_readonly("rotational", [](const Result& self) { return vector_copy(self.rotational, true); },
                               "kappa_i (or delta_i) per arm (N,): total_rotational split equally")
        .def_readonly("total_rotational", &Result::total_rotational)
        .def_property_readonly("achieved", [](const Result& self) { return matrix_copy(self.achieved, true); },
                               "the object matrix these gains give (6, 6)")
        .def_readonly("relative_residual", &Result::relative_residual)
        .def_readonly("tolerance", &Result::tolerance);
    module.def(
        "synthesize_gains",
        [](ArrayLike r_in, ArrayLike target_in, double tolerance) {
            const Matrix r = to_matrix(r_in, "synthesize_gains", "r", 3, any_size, "(3, N)");
            const Matrix6<double> target = to_matrix(target_in, "synthesize_gains", "target", 6, 6, "(6, 6)");
            return synthesize_gains(r, target, tolerance);
        },
        py::arg("r"), py::arg("target"), py::arg("tolerance") = 1e-9,
        "synthesize_gains(r, target, tolerance=1e-9) -> SynthesisResult: non-negative translational gains per arm "
        "and a total rotational gain whose apparent object stiffness (or damping) sum_i k_i T(r_i) + sum kappa R (E3) "
        "is closest to target (6, 6) (non-negative least squares; docs/analysis.md). r (3, N).");
    module.def(
        "classical_damping",
        [](const ApparentImpedance<double>& impedance, double damping_ratio) {
            return matrix_copy(classical_damping(impedance, damping_ratio));
        },
        py::arg("impedance"), py::arg("damping_ratio"),
        "classical_damping(impedance, damping_ratio) -> (6, 6): D = 2 zeta M^1/2 (M^-1/2 K M^-1/2)^1/2 M^1/2, the "
        "damping that gives every mode of (52) the ratio zeta and commutes classically (Theorem 4; docs/analysis.md).");
}

void bind_kernels(py::module_& module)
{
    module.def(
        "grasp_matrix", [](ArrayLike r) { return matrix_copy(grasp_matrix(offsets(r, "grasp_matrix"))); }, py::arg("r"),
        "grasp_matrix(r) -> (6, 6N): G = [G_1 ... G_N] of (24), G_i = [[I, 0], [S(r_i), I]], with h_o = G hbar "
        "(23). r (3, N): grasp offsets from the object's centre of mass, {w} (docs/model.md).");
    module.def(
        "constraint_matrix", [](ArrayLike r) { return matrix_copy(constraint_matrix(offsets(r, "constraint_matrix"))); },
        py::arg("r"),
        "constraint_matrix(r) -> (6N, 6(N+1)): A of (14) for the rigid grasp A xdd = b; block row i is "
        "[[-I, S(r_i)], [0, -I]] in the object's columns and I in end-effector i's (docs/model.md).");
    module.def(
        "constraint_bias",
        [](ArrayLike r_in, ArrayLike omega_in) {
            const Offsets r = offsets(r_in, "constraint_bias");
            const Vector3<double> omega = to_vector(omega_in, "constraint_bias", "omega_o", 3, "(3,)");
            return vector_copy(constraint_bias(r, omega));
        },
        py::arg("r"), py::arg("omega_o"),
        "constraint_bias(r, omega_o) -> (6N,): b of (13), b_i = [S(w_o)^2 r_i; 0] (docs/model.md).");
    module.def(
        "weighted_grasp_inverse",
        [](ArrayLike r_in, ArrayLike mass_in, ArrayLike inertia_in) {
            constexpr const char* name = "weighted_grasp_inverse";
            const Offsets r = offsets(r_in, name);
            const LoadWeights weights = load_weights(mass_in, inertia_in, name, r.cols());
            return matrix_copy(weighted_grasp_inverse(r, weights.mass, weights.inertia));
        },
        py::arg("r"), py::arg("mass_weights"), py::arg("inertia_weights"),
        "weighted_grasp_inverse(r, mass_weights, inertia_weights) -> (6N, 6): G+_M of (25) with errata E2 "
        "(docs/coordination.md), G G+_M = I. mass_weights (N,) > 0, inertia_weights (3, 3N): the J*_i side by side, "
        "symmetric positive semi-definite. Raises InvalidModel for refused weights.");
    module.def(
        "load_distribution",
        [](ArrayLike r_in, ArrayLike mass_in, ArrayLike inertia_in, ArrayLike wrench_in) {
            constexpr const char* name = "load_distribution";
            const Offsets r = offsets(r_in, name);
            const LoadWeights weights = load_weights(mass_in, inertia_in, name, r.cols());
            const Vector6<double> wrench = to_vector(wrench_in, name, "object_wrench", 6, "(6,)");
            return vector_copy(load_distribution(r, weights.mass, weights.inertia, wrench));
        },
        py::arg("r"), py::arg("mass_weights"), py::arg("inertia_weights"), py::arg("object_wrench"),
        "load_distribution(r, mass_weights, inertia_weights, object_wrench) -> (6N,): the desired end-effector "
        "wrenches h_i^d = -(G+_M h_o^d)_i of (26) for the object wrench h_o^d (6,) (docs/coordination.md). Weights "
        "as in weighted_grasp_inverse; with the end-effectors' own inertias it squeezes nothing. Raises InvalidModel "
        "for refused weights.");
    module.def(
        "squeeze_wrenches",
        [](ArrayLike r_in, ArrayLike mass_in, ArrayLike inertia_in, ArrayLike wrenches_in) {
            constexpr const char* name = "squeeze_wrenches";
            const Offsets r = offsets(r_in, name);
            const Index arms = r.cols();
            const LoadWeights weights = load_weights(mass_in, inertia_in, name, arms);
            const Vector wrenches = to_vector(wrenches_in, name, "wrenches_on_object", 6 * arms,
                                              stack_shape("(6N,)", 6 * arms).c_str());
            std::vector<CentralInertia<double>> list;
            for (Index i = 0; i < arms; ++i) {
                const Matrix3<double> rotational = weights.inertia.middleCols<3>(3 * i);
                list.emplace_back(weights.mass(i), rotational);
            }
            return vector_copy(squeeze_wrenches(list, r, wrenches));
        },
        py::arg("r"), py::arg("mass_weights"), py::arg("inertia_weights"), py::arg("wrenches_on_object"),
        "squeeze_wrenches(r, mass_weights, inertia_weights, wrenches_on_object) -> (6N,): the squeeze "
        "hbar - G+_M G hbar of the wrenches hbar (6N,) the arms apply to the object at the grasp points, relative to "
        "the weights' non-squeezing distribution (ref. [23] of the first paper; docs/coordination.md). C++ takes the "
        "weights as a list of CentralInertia first; here they are the dense arrays of weighted_grasp_inverse.");
    module.def("udwadia_kalaba", &udwadia_kalaba_checked, py::arg("M"), py::arg("A"), py::arg("b"), py::arg("h_sigma"),
               "udwadia_kalaba(M, A, b, h_sigma) -> (n,): the constraint wrench h of (18) for M xdd = h_sigma + h "
               "subject to A xdd = b (Gauss's principle (19); docs/dynamics.md). M (n, n) symmetric positive definite, "
               "A (m, n) of any rank, b (m,) consistent, h_sigma (n,).");
    module.def(
        "interaction_wrenches",
        [](ArrayLike object_in, ArrayLike ee_in, ArrayLike r_in, ArrayLike omega_in, ArrayLike sigma_in) {
            constexpr const char* name = "interaction_wrenches";
            const Offsets r = offsets(r_in, name);
            const Index arms = r.cols();
            const Matrix6<double> object_inertia = symmetric_stack(object_in, name, "object_inertia", 1, false);
            const Matrix ee_inertias = symmetric_stack(ee_in, name, "ee_inertias", arms, false);
            const Vector3<double> omega = to_vector(omega_in, name, "omega_o", 3, "(3,)");
            const Vector sigma = to_vector(sigma_in, name, "h_sigma", 6 * (arms + 1),
                                           stack_shape("(6(N+1),)", 6 * (arms + 1)).c_str());
            return vector_copy(interaction_wrenches(object_inertia, ee_inertias, r, omega, sigma));
        },
        py::arg("object_inertia"), py::arg("ee_inertias"), py::arg("r"), py::arg("omega_o"), py::arg("h_sigma"),
        "interaction_wrenches(object_inertia, ee_inertias, r, omega_o, h_sigma) -> (6(N+1),): the interaction "
        "wrenches h = [h_o; h_1; ...; h_N] of the rigid grasp, (18) in its structured O(N) form "
        "(docs/dynamics.md). object_inertia (6, 6) and ee_inertias (6, 6N) symmetric positive definite, {w}; "
        "r (3, N); omega_o (3,); h_sigma (6(N+1),) = [hSigma_o; hSigma_1; ...] of (15)-(16).");
    module.def(
        "internal_wrenches",
        [](ArrayLike ee_in, ArrayLike r_in, ArrayLike omega_in, ArrayLike motion_in) {
            constexpr const char* name = "internal_wrenches";
            const Offsets r = offsets(r_in, name);
            const Index arms = r.cols();
            const Matrix ee_inertias = symmetric_stack(ee_in, name, "ee_inertias", arms, false);
            const Vector3<double> omega = to_vector(omega_in, name, "omega_o", 3, "(3,)");
            const Vector motion = to_vector(motion_in, name, "h_motion", 6 * arms, stack_shape("(6N,)", 6 * arms).c_str());
            return vector_copy(internal_wrenches(ee_inertias, r, omega, motion));
        },
        py::arg("ee_inertias"), py::arg("r"), py::arg("omega_o"), py::arg("h_motion"),
        "internal_wrenches(ee_inertias, r, omega_o, h_motion) -> (6N,): the internal end-effector wrenches h'_int of "
        "(53) (errata E5; docs/analysis.md), block i acting ON end-effector i. ee_inertias (6, 6N), r (3, N), "
        "omega_o (3,), h_motion (6N,): the motion wrenches h_i^x of (6) stacked.");

    using Impedance = ApparentImpedance<double>;
    py::class_<Impedance>(module, "ApparentImpedance",
                          "Apparent object impedance of Theorem 2 (docs/analysis.md), 6 x 6 each, in {w} about the "
                          "object's centre of mass; fields are read-only copies.")
        .def(py::init([](ArrayLike inertia, ArrayLike damping, ArrayLike stiffness) {
                 Impedance result;
                 result.inertia = symmetric_stack(inertia, "ApparentImpedance", "inertia", 1, false);
                 result.damping = symmetric_stack(damping, "ApparentImpedance", "damping", 1, true);
                 result.stiffness = symmetric_stack(stiffness, "ApparentImpedance", "stiffness", 1, true);
                 return result;
             }),
             py::arg("inertia"), py::arg("damping"), py::arg("stiffness"),
             "M (6, 6) symmetric positive definite, D and K (6, 6) symmetric")
        .def_property_readonly("inertia", [](const Impedance& self) { return matrix_copy(self.inertia, true); },
                               "M (31)")
        .def_property_readonly("damping", [](const Impedance& self) { return matrix_copy(self.damping, true); },
                               "D (32)")
        .def_property_readonly("stiffness", [](const Impedance& self) { return matrix_copy(self.stiffness, true); },
                               "K, the exact linearisation (errata E3)");
    module.def(
        "apparent_impedance",
        [](ArrayLike object_in, ArrayLike inertia_in, ArrayLike damping_in, ArrayLike stiffness_in, ArrayLike r_in) {
            constexpr const char* name = "apparent_impedance";
            const Offsets r = offsets(r_in, name);
            const Index arms = r.cols();
            const Matrix6<double> object_inertia = symmetric_stack(object_in, name, "object_inertia", 1, false);
            const Matrix inertia = symmetric_stack(inertia_in, name, "ee_inertia", arms, false);
            const Matrix damping = symmetric_stack(damping_in, name, "ee_damping", arms, true);
            const Matrix stiffness = symmetric_stack(stiffness_in, name, "ee_stiffness", arms, true);
            return apparent_impedance(object_inertia, inertia, damping, stiffness, r);
        },
        py::arg("object_inertia"), py::arg("ee_inertia"), py::arg("ee_damping"), py::arg("ee_stiffness"), py::arg("r"),
        "apparent_impedance(object_inertia, ee_inertia, ee_damping, ee_stiffness, r) -> ApparentImpedance: M = M_o + "
        "sum G_i M_i G_i^T (31), D = sum G_i D_i G_i^T (32) and the exact K (E3) of Theorem 2 (docs/analysis.md). "
        "object_inertia (6, 6); ee_inertia, ee_damping, ee_stiffness (6, 6N), symmetric blocks; r (3, N).");
    bind_synthesis(module);  // after ApparentImpedance
}

}  // namespace coopdyn::python
