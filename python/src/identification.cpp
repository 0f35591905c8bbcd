// The first paper's grey-box identification of the apparent impedance from logged motion and
// wrench (section V; docs/analysis.md, "Identification"): identify_impedance (one axis),
// identify_diagonal_impedance (six axes) and simulate_impedance. Its own translation unit: the
// Levenberg-Marquardt fit, the exact discretisation and the equation-error QR compile here only.
#include "common.hpp"

#include <coopdyn/analysis/identification.hpp>

#include <array>

namespace coopdyn::python {

namespace {

Vector samples(ArrayLike value, const char* function, const char* name)
{
    return to_vector(value, function, name, any_size, "(N,)");
}

}  // namespace

void bind_identification(py::module_& module)
{
    py::enum_<ForceInterpolation>(module, "ForceInterpolation",
                                  "How the force varies between samples in the identification's simulation.")
        .value("zero_order_hold", ForceInterpolation::zero_order_hold, "f(t) = f[n] on [nT, (n+1)T)")
        .value("linear", ForceInterpolation::linear, "a straight line between samples")
        .value("cubic", ForceInterpolation::cubic, "the cubic through the four nearest samples (default)");

    py::class_<IdentificationOptions>(module, "IdentificationOptions", "Options of identify_impedance.")
        .def(py::init<>())
        .def_readwrite("force_interpolation", &IdentificationOptions::force_interpolation)
        .def_readwrite("estimate_initial_state", &IdentificationOptions::estimate_initial_state,
                       "estimate p0, v0 too (False: the record starts at rest at p[0])")
        .def_readwrite("max_iterations", &IdentificationOptions::max_iterations)
        .def_readwrite("tolerance", &IdentificationOptions::tolerance);

    py::class_<ImpedanceParameters>(module, "ImpedanceParameters", "m, d, k of one axis.")
        .def(py::init([](double mass, double damping, double stiffness) {
                 return ImpedanceParameters{mass, damping, stiffness};
             }),
             py::arg("mass") = 0.0, py::arg("damping") = 0.0, py::arg("stiffness") = 0.0)
        .def_readwrite("mass", &ImpedanceParameters::mass)
        .def_readwrite("damping", &ImpedanceParameters::damping)
        .def_readwrite("stiffness", &ImpedanceParameters::stiffness);

    py::class_<ImpedanceFit>(module, "ImpedanceFit", "Result of identify_impedance (docs/analysis.md).")
        .def_readonly("mass", &ImpedanceFit::mass)
        .def_readonly("damping", &ImpedanceFit::damping)
        .def_readonly("stiffness", &ImpedanceFit::stiffness)
        .def_readonly("initial_position", &ImpedanceFit::initial_position)
        .def_readonly("initial_velocity", &ImpedanceFit::initial_velocity)
        .def_readonly("mean_squared_output_error", &ImpedanceFit::mean_squared_output_error)
        .def_readonly("iterations", &ImpedanceFit::iterations)
        .def_readonly("converged", &ImpedanceFit::converged)
        .def_readonly("equation_error", &ImpedanceFit::equation_error, "step 1's estimate (ImpedanceParameters)")
        .def_readonly("equation_error_start", &ImpedanceFit::equation_error_start)
        .def("parameters", &ImpedanceFit::parameters);

    py::class_<DiagonalImpedanceFit>(module, "DiagonalImpedanceFit",
                                     "Result of identify_diagonal_impedance: diagonal M, D, K over (x, y, z, rotation "
                                     "x, y, z); read-only copies.")
        .def_property_readonly("inertia", [](const DiagonalImpedanceFit& self) { return vector_copy(self.inertia, true); })
        .def_property_readonly("damping", [](const DiagonalImpedanceFit& self) { return vector_copy(self.damping, true); })
        .def_property_readonly("stiffness",
                               [](const DiagonalImpedanceFit& self) { return vector_copy(self.stiffness, true); })
        .def_property_readonly("identified",
                               [](const DiagonalImpedanceFit& self) {
                                   py::list result;
                                   for (const bool axis : self.identified) {
                                       result.append(axis);
                                   }
                                   return result;
                               })
        .def_property_readonly("axes",
                               [](const DiagonalImpedanceFit& self) {
                                   py::list result;
                                   for (const ImpedanceFit& axis : self.axes) {
                                       result.append(axis);
                                   }
                                   return result;
                               })
        .def("matrices", &DiagonalImpedanceFit::matrices, "ApparentImpedance with diagonal M, D, K (Theorem 2)");

    module.def(
        "identify_impedance",
        [](ArrayLike position_in, ArrayLike force_in, double sample_period, const IdentificationOptions& options) {
            const Vector position = samples(position_in, "identify_impedance", "position");
            const Vector force = to_vector(force_in, "identify_impedance", "force", position.size(),
                                           ("(N,) = " + dims(position.size())).c_str());
            py::gil_scoped_release unlocked;
            return identify_impedance(position, force, sample_period, options);
        },
        py::arg("position"), py::arg("force"), py::arg("sample_period"), py::arg("options") = IdentificationOptions(),
        "identify_impedance(position, force, sample_period, options=IdentificationOptions()) -> ImpedanceFit: fits "
        "m pdd + d pd + k p = f, the 1-DOF projection of (52), to uniformly sampled p[n], f[n] (N >= 10) by equation "
        "error then output-error Levenberg-Marquardt (docs/analysis.md, \"Identification\"). Raises InvalidArgument "
        "for unexcited or invalid data. Releases the GIL.");
    module.def(
        "identify_diagonal_impedance",
        [](ArrayLike displacement_in, ArrayLike wrench_in, double sample_period, const IdentificationOptions& options,
           const py::sequence& axes_in) {
            constexpr const char* name = "identify_diagonal_impedance";
            const Matrix displacement = to_matrix(displacement_in, name, "displacement", 6, any_size, "(6, N)");
            const Matrix wrench = to_matrix(wrench_in, name, "wrench", 6, displacement.cols(),
                                            ("(6, N) = " + dims(6, displacement.cols())).c_str());
            if (axes_in.size() != 6) {
                fail_argument(name, "axes", "must hold 6 booleans (x, y, z, rotation x, y, z)");
            }
            std::array<bool, 6> axes{};
            for (std::size_t k = 0; k < 6; ++k) {
                axes[k] = axes_in[k].cast<bool>();
            }
            py::gil_scoped_release unlocked;
            return identify_diagonal_impedance(displacement, wrench, sample_period, options, axes);
        },
        py::arg("displacement"), py::arg("wrench"), py::arg("sample_period"),
        py::arg("options") = IdentificationOptions(), py::arg("axes") = py::make_tuple(true, true, true, true, true, true),
        "identify_diagonal_impedance(displacement, wrench, sample_period, options, axes) -> DiagonalImpedanceFit: "
        "identify_impedance on each requested axis of (6, N) displacement and wrench logs (rows x, y, z, rotation x, "
        "y, z), for set-ups whose apparent impedance is diagonal in those axes (Corollary 1).");
    module.def(
        "simulate_impedance",
        [](const ImpedanceParameters& parameters, double initial_position, double initial_velocity, ArrayLike force_in,
           double sample_period, ForceInterpolation interpolation) {
            const Vector force = samples(force_in, "simulate_impedance", "force");
            return vector_copy(simulate_impedance(parameters, initial_position, initial_velocity, force, sample_period,
                                                  interpolation));
        },
        py::arg("parameters"), py::arg("initial_position"), py::arg("initial_velocity"), py::arg("force"),
        py::arg("sample_period"), py::arg("interpolation") = ForceInterpolation::cubic,
        "simulate_impedance(parameters, initial_position, initial_velocity, force, sample_period, "
        "interpolation=ForceInterpolation.cubic) -> (N,): p(nT) of m pdd + d pd + k p = f, exact for the chosen "
        "interpolation of the force samples.");
}

}  // namespace coopdyn::python
