// The first paper's Simulator (docs/dynamics.md, "Simulation") for both kinds of model: Simulator
// on a Model of impedance end-effectors (1) and ResolvedAccelerationSimulator on a
// ResolvedAccelerationModel (20)-(21), each driven by a Python callable
// inputs(time, state, setpoints, disturbances) with the stage's state for feedback. run() loops
// in C++ and logs into numpy arrays (the C++ run() with an observer); without inputs it releases
// the GIL.
#include "common.hpp"

#include <coopdyn/core.hpp>

namespace coopdyn::python {

namespace {

using SetpointsX = Setpoints<double, Dynamic>;
using DisturbancesX = Disturbances<double, Dynamic>;
using State = RigidBodyState<double>;

/// The log run() fills: one row per step taken, in new C-order numpy arrays made before the loop.
/// Their memory is resolved to row pointers once, here, with the GIL held: the loop writes through
/// plain pointers while the GIL is released (no pybind11 call, nothing that can throw).
struct RunLog {
    RunLog(Index steps, Index arms)
        : time(steps), position({steps, Index(3)}), orientation({steps, Index(4)}), twist({steps, Index(6)}),
          object_acceleration({steps, Index(6)}), wrenches({steps, 6 * (arms + 1)}), columns(6 * (arms + 1)),
          time_rows(time.mutable_data()), position_rows(position.mutable_data()),
          orientation_rows(orientation.mutable_data()), twist_rows(twist.mutable_data()),
          acceleration_rows(object_acceleration.mutable_data()), wrench_rows(wrenches.mutable_data())
    {
    }
    py::array_t<double> time, position, orientation, twist, object_acceleration, wrenches;
    Index columns;
    double* time_rows;
    double* position_rows;
    double* orientation_rows;
    double* twist_rows;
    double* acceleration_rows;
    double* wrench_rows;
    Index taken = 0;

    template <typename DataType> void write(double start_time, const State& state, const DataType& data) noexcept
    {
        const Index k = taken++;
        time_rows[k] = start_time;
        Eigen::Map<Vector3<double>>(position_rows + 3 * k) = state.pose.position;
        Eigen::Map<Vector4<double>>(orientation_rows + 4 * k) = state.pose.orientation.coeffs();
        Eigen::Map<Vector6<double>>(twist_rows + 6 * k) = state.twist;
        Eigen::Map<Vector6<double>>(acceleration_rows + 6 * k) = data.object_acceleration();
        Eigen::Map<Vector>(wrench_rows + columns * k, columns) = data.wrenches;
    }

    /// The arrays themselves when every step was taken; the rows taken, as new arrays, when the run
    /// stopped early.
    py::dict result() const
    {
        py::dict log;
        const bool complete = taken == static_cast<Index>(time.shape(0));
        const py::slice rows(0, static_cast<py::ssize_t>(taken), 1);
        const auto rows_of = [&](const py::array_t<double>& array) -> py::object {
            return complete ? py::object(array) : py::object(array[rows].attr("copy")());
        };
        log["time"] = rows_of(time);
        log["position"] = rows_of(position);
        log["orientation"] = rows_of(orientation);
        log["twist"] = rows_of(twist);
        log["object_acceleration"] = rows_of(object_acceleration);
        log["wrenches"] = rows_of(wrenches);
        return log;
    }
};

template <typename SimulatorT> auto python_inputs(py::object self, py::object inputs)
{
    return [self, inputs](double time, const State& state, SetpointsX& setpoints, DisturbancesX& disturbances) {
        inputs(time, state, py::cast(&setpoints, py::return_value_policy::reference_internal, self),
               py::cast(&disturbances, py::return_value_policy::reference_internal, self));
    };
}

template <typename SimulatorT> py::dict run(py::object self, Index steps, py::object inputs)
{
    if (steps < 0) {
        fail_argument("Simulator.run", "steps", "must be >= 0");
    }
    SimulatorT& simulator = self.cast<SimulatorT&>();
    RunLog log(steps, simulator.model().arms());
    auto observe = [&log](double time, const State& state, const typename SimulatorT::DataType& data) {
        log.write(time, state, data);
    };
    if (inputs.is_none()) {
        py::gil_scoped_release unlocked;
        simulator.run(steps, [](double, SetpointsX&, DisturbancesX&) noexcept {}, observe);
    } else {
        simulator.run(steps, python_inputs<SimulatorT>(self, inputs), observe);
    }
    return log.result();
}

template <typename ModelType>
void bind_simulator_of(py::module_& module, const char* name, const char* model_name)
{
    using SimulatorT = Simulator<ModelType>;
    const std::string doc = std::string("Fixed-step simulation of the cooperative system (Fig. 2; docs/dynamics.md) on a ") +
                            model_name +
                            ". Keeps the model alive. Inputs come from a Python callable inputs(time, state, "
                            "setpoints, disturbances) that writes into setpoints and disturbances (the simulator's own "
                            "buffers; state is the integrator stage's object state, for feedback).";
    py::class_<SimulatorT>(module, name, doc.c_str())
        .def(py::init<const ModelType&, double, const State&, Integrator, InputHold>(), py::arg("model"),
             py::arg("time_step"), py::arg("initial_state") = State(), py::arg("integrator") = Integrator::runge_kutta_4,
             py::arg("input_hold") = InputHold::per_stage, py::keep_alive<1, 2>())
        .def(
            "step",
            [](py::object self, py::object inputs) {
                SimulatorT& simulator = self.cast<SimulatorT&>();
                if (inputs.is_none()) {
                    py::gil_scoped_release unlocked;
                    return simulator.step();
                }
                return simulator.step(python_inputs<SimulatorT>(self, inputs));
            },
            py::arg("inputs") = py::none(),
            "step(inputs=None) -> SimulationStatus: one step; inputs(time, state, setpoints, disturbances) is called at "
            "every integrator stage (per_stage) or once (zero_order). An exception in it propagates (the step is not "
            "taken). Without inputs the setpoints and disturbances keep their values and the GIL is released.")
        .def("run", &run<SimulatorT>, py::arg("steps"), py::arg("inputs") = py::none(),
             "run(steps, inputs=None) -> dict of numpy arrays, one row per step taken: step(inputs) `steps` times in "
             "C++ (stopping at a failed step: check .status). Row k holds the step's start: \"time\" (steps,), the "
             "object's \"position\" (steps, 3), \"orientation\" (steps, 4) as [x, y, z, w], \"twist\" (steps, 6), and "
             "the evaluation there (.data): \"object_acceleration\" (steps, 6) and \"wrenches\" (steps, 6(N+1)) = "
             "[h_o; h_1; ...; h_N] of (18). New, writable arrays. Without inputs the GIL is released.")
        .def("reset", &SimulatorT::reset, py::arg("state"), py::arg("time") = 0.0)
        .def_property_readonly("state", &SimulatorT::state, py::return_value_policy::copy,
                               "a copy of the object's state (change it with reset(state, time))")
        .def_property_readonly("time", &SimulatorT::time)
        .def_property_readonly("steps", &SimulatorT::steps)
        .def_property_readonly("time_step", &SimulatorT::time_step)
        .def_property_readonly("status", &SimulatorT::status, py::return_value_policy::copy)
        .def_property_readonly("data", &SimulatorT::data, py::return_value_policy::reference_internal,
                               "the evaluation at the state the last step started from (a view)")
        .def_property_readonly("setpoints",
                               py::cpp_function([](SimulatorT& self) -> SetpointsX& { return self.setpoints(); },
                                                py::return_value_policy::reference_internal))
        .def_property_readonly("disturbances",
                               py::cpp_function([](SimulatorT& self) -> DisturbancesX& { return self.disturbances(); },
                                                py::return_value_policy::reference_internal));
}

}  // namespace

void bind_simulator(py::module_& module)
{
    py::enum_<Integrator>(module, "Integrator")
        .value("runge_kutta_4", Integrator::runge_kutta_4)
        .value("semi_implicit_euler", Integrator::semi_implicit_euler);
    py::enum_<InputHold>(module, "InputHold")
        .value("per_stage", InputHold::per_stage)
        .value("zero_order", InputHold::zero_order);
    py::class_<SimulationStatus<double>>(module, "SimulationStatus")
        .def_readonly("ok", &SimulationStatus<double>::ok)
        .def_readonly("failed_step", &SimulationStatus<double>::failed_step)
        .def_readonly("failed_time", &SimulationStatus<double>::failed_time)
        .def_readonly("input", &SimulationStatus<double>::input);
    bind_simulator_of<ImpedanceModelX>(module, "Simulator", "Model");
    bind_simulator_of<Model<double, Dynamic, ResolvedAccelerationEndEffector>>(module, "ResolvedAccelerationSimulator",
                                                                                "ResolvedAccelerationModel");
}

}  // namespace coopdyn::python
