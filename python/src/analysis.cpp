// The first paper's stability analysis of the linearised object dynamics (52) (Theorems 3-4,
// Corollary 1, errata E4; docs/analysis.md) on an ApparentImpedance, and the impedance synthesis
// (per-arm gains for a target object stiffness or damping, classical damping). Its own translation unit:
// Eigen's eigen-solvers (12 x 12 general, 6 x 6 generalized symmetric) are the most expensive
// templates of the module to compile.
#include "common.hpp"

#include <coopdyn/analysis/impedance_synthesis.hpp>
#include <coopdyn/analysis/stability.hpp>

#include <cmath>
#include <complex>

namespace coopdyn::python {

void bind_synthesis(py::module_& module);

void bind_analysis(py::module_& module)
{
    bind_synthesis(module);
    using Impedance = ApparentImpedance<double>;
    module.def(
        "state_matrix", [](const Impedance& impedance) { return matrix_copy(state_matrix(impedance)); },
        py::arg("impedance"),
        "state_matrix(impedance) -> (12, 12): [[0, I], [-M^-1 K, -M^-1 D]], the first-order form of the linearised "
        "object dynamics (52) for x = [dx; dxd] (docs/analysis.md).");
    module.def(
        "linearised_eigenvalues",
        [](const Impedance& impedance) {
            const Eigen::Matrix<std::complex<double>, 12, 1> values = linearised_eigenvalues(impedance);
            py::array_t<std::complex<double>> result(12);
            auto view = result.mutable_unchecked<1>();
            for (Index k = 0; k < 12; ++k) {
                view(k) = values(k);
            }
            return result;
        },
        py::arg("impedance"),
        "linearised_eigenvalues(impedance) -> complex (12,): the eigenvalues of (52); all with negative real part "
        "when M, D, K are positive definite (Theorem 3).");
    py::class_<Modes<double>>(module, "Modes", "Undamped modes of (52) (Theorem 4, errata E4); read-only copies.")
        .def_property_readonly("natural_frequencies",
                               [](const Modes<double>& self) { return vector_copy(self.natural_frequencies, true); },
                               "omega_k (6,), rad/s, ascending")
        .def_property_readonly("damping_ratios",
                               [](const Modes<double>& self) { return vector_copy(self.damping_ratios, true); },
                               "zeta_k (6,)")
        .def_property_readonly("shapes", [](const Modes<double>& self) { return matrix_copy(self.shapes, true); },
                               "(6, 6): column k is v_k, v_k^T M v_k = 1");
    module.def("modes", &modes<double>, py::arg("impedance"),
               "modes(impedance) -> Modes: K v = omega^2 M v with zeta_k = v_k^T D v_k / (2 omega_k); exact damping "
               "ratios only when the damping is classical (classical_damping_commutator = 0; errata E4). M and K "
               "must be positive definite.");
    module.def("classical_damping_commutator", &classical_damping_commutator<double>, py::arg("impedance"),
               "classical_damping_commutator(impedance) -> float: |D M^-1 K - K M^-1 D|_F, zero exactly for classical "
               "damping (Theorem 4's claim; errata E4).");
    module.def(
        "is_decoupled", [](const Impedance& impedance, double tolerance) { return is_decoupled(impedance, tolerance); },
        py::arg("impedance"), py::arg("tolerance") = 1e-12,
        "is_decoupled(impedance, tolerance=1e-12) -> bool: Corollary 1, the off-diagonal 3 x 3 blocks of M, D, K "
        "vanish (relative to each matrix's largest entry).");
    module.def(
        "centre_of_stiffness",
        [](ArrayLike stiffness_in) {
            const Matrix6<double> stiffness = to_matrix(stiffness_in, "centre_of_stiffness", "stiffness", 6, 6, "(6, 6)");
            if (std::abs(stiffness.topLeftCorner<3, 3>().determinant()) <= 0.0) {
                fail_argument("centre_of_stiffness", "stiffness", "needs an invertible translational block K_tt");
            }
            return vector_copy(centre_of_stiffness(stiffness));
        },
        py::arg("stiffness"),
        "centre_of_stiffness(stiffness) -> (3,): the point (from the object's centre of mass, {w}) about which a force "
        "is resisted by a pure translation; sum k_i r_i / sum k_i for the cooperative K (docs/analysis.md).");
}

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

}  // namespace coopdyn::python
