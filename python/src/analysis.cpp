// The first paper's stability analysis of the linearised object dynamics (52) (Theorems 3-4,
// Corollary 1, errata E4; docs/analysis.md) on an ApparentImpedance. Its own translation unit:
// Eigen's eigen-solvers (12 x 12 general, 6 x 6 generalized symmetric) are the most expensive
// templates of the module to compile.
#include "common.hpp"

#include <coopdyn/analysis/stability.hpp>

#include <cmath>
#include <complex>

namespace coopdyn::python {

void bind_analysis(py::module_& module)
{
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

}  // namespace coopdyn::python
