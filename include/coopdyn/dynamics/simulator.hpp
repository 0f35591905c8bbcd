/// \file
/// \brief Fixed-step simulation of the cooperative system in reduced coordinates (the block
/// scheme of paper Fig. 2): the state is the object's pose and twist; the end-effector states
/// follow from the rigid grasp, so the constraints hold exactly at every step.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/input_check.hpp"
#include "coopdyn/dynamics/integrator.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/spatial/quaternion.hpp"

#include <cmath>
#include <type_traits>
#include <utility>

namespace coopdyn {

/// When Simulator calls the input function within a step.
enum class InputHold {
    /// At every stage of the integrator (RK4: t, t + dt/2 twice, t + dt), with the stage's state:
    /// inputs that are smooth functions of time and state (a physical drag, a spring, a
    /// continuous-time controller) keep the integrator's order.
    per_stage,
    /// Once per step, at its start, held through the step: a digital controller that computes its
    /// output once per tick (zero-order hold). The step then integrates a piecewise-constant input
    /// exactly as a real sampled controller applies it.
    zero_order,
};

/// \brief What became of the steps taken since the last reset. A step that would produce a
/// non-finite state (a diverging simulation), or whose inputs check_setpoints/check_disturbances
/// refuse (a NaN, a non-unit setpoint quaternion), is not taken: the state stays at the last
/// finite one, `ok` turns false and stays false until reset(), and later steps do nothing. The
/// dynamics are never evaluated on such a state or input, so a debug build does not stop on its
/// input assertions either.
template <typename Scalar> struct SimulationStatus {
    bool ok = true;
    /// The step that failed, counted from 0 at the last reset (-1 while ok).
    Index failed_step = -1;
    /// The time the failed step started from.
    Scalar failed_time = Scalar(0);
    /// The refused input and its arm when the step failed on its inputs (ok() otherwise).
    InputCheck input{};
};

/// \brief Steps a cooperative Model at a fixed time step.
///
/// Inputs come from a caller-supplied function that writes the setpoints and disturbances into
/// the buffers it is given (they keep their previous values if it writes nothing), either
/// `inputs(time, state, setpoints, disturbances)` (state = the integrator stage's object state,
/// for feedback) or `inputs(time, setpoints, disturbances)`. With InputHold::per_stage (default)
/// RK4 calls it at t, t + dt/2 (twice) and t + dt; with InputHold::zero_order once per step.
/// After each step, data() holds the full evaluation (accelerations and every wrench) at the
/// state and time the step started from, for a logger; run() hands exactly that to an observer.
/// time() is start time + (steps since reset) dt, never an accumulated sum.
/// Nothing allocates after construction.
template <typename ModelType> class Simulator {
public:
    using Scalar = typename ModelType::Scalar;
    static constexpr int Arms = ModelType::arms_at_compile_time;
    using State = RigidBodyState<Scalar>;
    using SetpointsType = Setpoints<Scalar, Arms>;
    using DisturbancesType = Disturbances<Scalar, Arms>;
    using DataType = Data<ModelType>;

    using Status = SimulationStatus<Scalar>;

    /// \param model kept by reference: it must outlive the simulator (a temporary model does not
    ///        compile: that overload is deleted).
    /// \param time_step dt > 0, seconds.
    /// \param initial_state object pose (unit quaternion) and twist.
    /// Throws InvalidArgument on a non-positive or non-finite time step or an invalid initial state.
    Simulator(const ModelType& model, Scalar time_step, const State& initial_state,
              Integrator integrator = Integrator::runge_kutta_4, InputHold input_hold = InputHold::per_stage)
        : model_(model),
          time_step_(time_step),
          integrator_(integrator),
          input_hold_(input_hold),
          setpoints_(model.arms()),
          disturbances_(model.arms()),
          data_(model),
          stage_data_(model)
    {
        detail::require_positive(time_step, "simulator", "time_step");
        reset(initial_state);
    }
    /// A simulator keeps a reference to its model: a temporary would dangle.
    Simulator(const ModelType&& model, Scalar time_step, const State& initial_state,
              Integrator integrator = Integrator::runge_kutta_4, InputHold input_hold = InputHold::per_stage) = delete;

    /// Restart from `state` at `time`. Throws InvalidArgument if the state is not finite or its
    /// quaternion is not unit.
    void reset(const State& state, Scalar time = Scalar(0))
    {
        detail::require_finite(state.pose.position, "simulator", "state.pose.position");
        detail::require_unit_quaternion(state.pose.orientation, "simulator", "state.pose.orientation");
        detail::require_finite(state.twist, "simulator", "state.twist");
        state_ = state;
        start_time_ = time;
        steps_ = 0;
        status_ = Status{};
    }

    /// Advance one step of dt with inputs from `inputs` (see the class comment). Returns the
    /// status: a step that would produce a non-finite state is not taken (SimulationStatus).
    template <typename InputFunction> const Status& step(InputFunction&& inputs)
    {
        if (!status_.ok) {
            return status_;
        }
        const State start = state_;
        const bool finite = integrator_ == Integrator::runge_kutta_4 ? step_runge_kutta_4(inputs)
                                                                     : step_semi_implicit_euler(inputs);
        if (finite) {
            ++steps_;
        } else {
            state_ = start;
            status_.ok = false;
            status_.failed_step = steps_;
            status_.failed_time = time();
        }
        return status_;
    }

    /// Advance one step keeping the current setpoints() and disturbances().
    const Status& step()
    {
        return step([](Scalar, SetpointsType&, DisturbancesType&) noexcept {});
    }

    /// Take `steps` steps; before each, call observer(time, state, data) with the state the step
    /// starts from and the evaluation at that state (the per-step interaction wrenches). Stops at
    /// a failed step (not observed) and returns the status.
    template <typename InputFunction, typename Observer>
    const Status& run(Index steps, InputFunction&& inputs, Observer&& observer)
    {
        for (Index k = 0; k < steps && status_.ok; ++k) {
            const Scalar start_time = time();
            const State start_state = state_;
            if (step(inputs).ok) {
                observer(start_time, start_state, static_cast<const DataType&>(data_));
            }
        }
        return status_;
    }

    /// Evaluate the dynamics at the current state and time without stepping; result in data().
    template <typename InputFunction> const DataType& evaluate(InputFunction&& inputs)
    {
        call_inputs(inputs, time(), state_);
        interaction_dynamics(model_, data_, state_, setpoints_, disturbances_);
        return data_;
    }

    const State& state() const noexcept { return state_; }
    /// Start time + (steps since reset) dt: no rounding accumulates over long runs.
    Scalar time() const noexcept { return start_time_ + static_cast<Scalar>(static_cast<double>(steps_)) * time_step_; }
    /// Steps taken since the last reset.
    Index steps() const noexcept { return steps_; }
    const Status& status() const noexcept { return status_; }
    InputHold input_hold() const noexcept { return input_hold_; }
    Scalar time_step() const noexcept { return time_step_; }
    const ModelType& model() const noexcept { return model_; }
    /// Evaluation at the start of the last step (or the last evaluate()).
    const DataType& data() const noexcept { return data_; }
    /// Input buffers, for constant inputs set once before stepping.
    SetpointsType& setpoints() noexcept { return setpoints_; }
    DisturbancesType& disturbances() noexcept { return disturbances_; }

private:
    /// d/dt of (p, q, v, w): (v, 1/2 [0; w] (x) q, xdd_o).
    struct Derivative {
        Vector3<Scalar> position;
        Vector4<Scalar> orientation;  // Eigen coefficient order (x, y, z, w)
        Vector6<Scalar> twist;
    };

    /// Calls either form of the input function.
    template <typename InputFunction> void call_inputs(InputFunction& inputs, Scalar time, const State& state)
    {
        if constexpr (std::is_invocable_v<InputFunction&, Scalar, const State&, SetpointsType&, DisturbancesType&>) {
            inputs(time, state, setpoints_, disturbances_);
        } else {
            static_assert(std::is_invocable_v<InputFunction&, Scalar, SetpointsType&, DisturbancesType&>,
                          "inputs must be callable as (time, state, setpoints, disturbances) or "
                          "(time, setpoints, disturbances)");
            inputs(time, setpoints_, disturbances_);
        }
    }

    static bool is_finite(const State& state) noexcept
    {
        return state.pose.position.allFinite() && state.pose.orientation.coeffs().allFinite() &&
               state.twist.allFinite();
    }

    /// The derivative at a stage; `first_stage` marks the step's first evaluation (where a
    /// zero-order hold samples its inputs).
    /// False, with status_.input set, when the inputs are refused (the dynamics are then not
    /// evaluated).
    template <typename InputFunction>
    bool derivative(Scalar time, const State& state, DataType& data, InputFunction& inputs, bool first_stage,
                    Derivative& result)
    {
        if (first_stage || input_hold_ == InputHold::per_stage) {
            call_inputs(inputs, time, state);
            status_.input = check_setpoints(setpoints_);
            if (status_.input.ok()) {
                status_.input = check_disturbances(disturbances_);
            }
            if (!status_.input.ok()) {
                return false;
            }
        }
        interaction_dynamics(model_, data, state, setpoints_, disturbances_);
        result.position = state.twist.template head<3>();
        result.orientation =
            quaternion_derivative_world(state.pose.orientation, state.twist.template tail<3>()).coeffs();
        result.twist = data.object_acceleration();
        return true;
    }

    /// state + scale * derivative, with the quaternion renormalised so the dynamics are always
    /// evaluated at a rotation.
    static State advance(const State& state, const Derivative& slope, Scalar scale) noexcept
    {
        State result;
        result.pose.position = state.pose.position + scale * slope.position;
        result.pose.orientation.coeffs() = state.pose.orientation.coeffs() + scale * slope.orientation;
        result.pose.orientation.normalize();
        result.twist = state.twist + scale * slope.twist;
        return result;
    }

    /// One RK4 step; false (state_ partly updated) as soon as a stage state is not finite or a
    /// stage's inputs are refused, so the dynamics are never evaluated at a NaN state or input.
    template <typename InputFunction> bool step_runge_kutta_4(InputFunction& inputs)
    {
        const Scalar time = this->time();
        const Scalar dt = time_step_;
        const Scalar half = dt / Scalar(2);
        Derivative k1, k2, k3, k4;
        if (!derivative(time, state_, data_, inputs, true, k1)) {
            return false;
        }
        const State stage2 = advance(state_, k1, half);
        if (!is_finite(stage2) || !derivative(time + half, stage2, stage_data_, inputs, false, k2)) {
            return false;
        }
        const State stage3 = advance(state_, k2, half);
        if (!is_finite(stage3) || !derivative(time + half, stage3, stage_data_, inputs, false, k3)) {
            return false;
        }
        const State stage4 = advance(state_, k3, dt);
        if (!is_finite(stage4) || !derivative(time + dt, stage4, stage_data_, inputs, false, k4)) {
            return false;
        }
        const Scalar sixth = dt / Scalar(6);
        state_.pose.position += sixth * (k1.position + Scalar(2) * (k2.position + k3.position) + k4.position);
        state_.pose.orientation.coeffs() +=
            sixth * (k1.orientation + Scalar(2) * (k2.orientation + k3.orientation) + k4.orientation);
        state_.pose.orientation.normalize();
        state_.twist += sixth * (k1.twist + Scalar(2) * (k2.twist + k3.twist) + k4.twist);
        return is_finite(state_);
    }

    template <typename InputFunction> bool step_semi_implicit_euler(InputFunction& inputs)
    {
        const Scalar dt = time_step_;
        Derivative slope;
        if (!derivative(time(), state_, data_, inputs, true, slope)) {
            return false;
        }
        state_.twist += dt * slope.twist;
        state_.pose.position += dt * state_.twist.template head<3>();
        const Vector3<Scalar> rotation = dt * state_.twist.template tail<3>();
        state_.pose.orientation = quaternion_exp(rotation) * state_.pose.orientation;
        state_.pose.orientation.normalize();
        return is_finite(state_);
    }

    const ModelType& model_;
    Scalar time_step_;
    Integrator integrator_;
    InputHold input_hold_;
    State state_{};
    Scalar start_time_ = Scalar(0);
    Index steps_ = 0;
    Status status_{};
    SetpointsType setpoints_;
    DisturbancesType disturbances_;
    DataType data_;
    DataType stage_data_;
};

}  // namespace coopdyn
