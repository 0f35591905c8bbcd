/// \file
/// \brief Fixed-step simulation of the cooperative system in reduced coordinates (the block
/// scheme of paper Fig. 2): the state is the object's pose and twist; the end-effector states
/// follow from the rigid grasp, so the constraints hold exactly at every step.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/spatial/quaternion.hpp"

#include <cmath>
#include <utility>

namespace coopdyn {

/// Integration scheme of Simulator.
enum class Integrator {
    /// Classical 4th-order Runge-Kutta on (p, q, v, w), quaternion renormalised after each step.
    /// Four evaluations of the dynamics per step.
    runge_kutta_4,
    /// Semi-implicit (symplectic) Euler: v += dt a, then p += dt v and q = exp(dt w) (x) q with the
    /// new velocity. One evaluation per step; first order, but with bounded energy error for
    /// the undamped springs.
    semi_implicit_euler,
};

/// \brief Steps a cooperative Model at a fixed time step.
///
/// Inputs come from a caller-supplied function `inputs(time, setpoints, disturbances)` that
/// writes the setpoints and disturbances at `time` into the buffers it is given (they keep their
/// previous values if it writes nothing). RK4 calls it at t, t + dt/2 (twice) and t + dt.
/// After each step, data() holds the full evaluation (accelerations and every wrench) at the
/// state and time the step started from, for a logger; run() hands exactly that to an observer.
/// Nothing allocates after construction.
template <typename ModelType> class Simulator {
public:
    using Scalar = typename ModelType::Scalar;
    static constexpr int Arms = ModelType::arms_at_compile_time;
    using State = RigidBodyState<Scalar>;
    using SetpointsType = Setpoints<Scalar, Arms>;
    using DisturbancesType = Disturbances<Scalar, Arms>;
    using DataType = Data<ModelType>;

    /// \param model kept by reference: it must outlive the simulator.
    /// \param time_step dt > 0, seconds.
    /// \param initial_state object pose (unit quaternion) and twist.
    /// Throws InvalidArgument on a non-positive or non-finite time step or an invalid initial state.
    Simulator(const ModelType& model, Scalar time_step, const State& initial_state,
              Integrator integrator = Integrator::runge_kutta_4)
        : model_(model),
          time_step_(time_step),
          integrator_(integrator),
          setpoints_(model.arms()),
          disturbances_(model.arms()),
          data_(model),
          stage_data_(model)
    {
        detail::require_positive(time_step, "simulator", "time_step");
        reset(initial_state);
    }

    /// Restart from `state` at `time`. Throws InvalidArgument if the state is not finite or its
    /// quaternion is not unit.
    void reset(const State& state, Scalar time = Scalar(0))
    {
        detail::require_finite(state.pose.position, "simulator", "state.pose.position");
        detail::require_unit_quaternion(state.pose.orientation, "simulator", "state.pose.orientation");
        detail::require_finite(state.twist, "simulator", "state.twist");
        state_ = state;
        time_ = time;
    }

    /// Advance one step of dt with inputs from `inputs(time, setpoints, disturbances)`.
    template <typename InputFunction> void step(InputFunction&& inputs)
    {
        if (integrator_ == Integrator::runge_kutta_4) {
            step_runge_kutta_4(inputs);
        } else {
            step_semi_implicit_euler(inputs);
        }
    }

    /// Advance one step keeping the current setpoints() and disturbances().
    void step()
    {
        step([](Scalar, SetpointsType&, DisturbancesType&) noexcept {});
    }

    /// Take `steps` steps; before each, call observer(time, state, data) with the state the step
    /// starts from and the evaluation at that state (the per-step interaction wrenches).
    template <typename InputFunction, typename Observer>
    void run(Index steps, InputFunction&& inputs, Observer&& observer)
    {
        for (Index k = 0; k < steps; ++k) {
            const Scalar start_time = time_;
            const State start_state = state_;
            step(inputs);
            observer(start_time, start_state, static_cast<const DataType&>(data_));
        }
    }

    /// Evaluate the dynamics at the current state and time without stepping; result in data().
    template <typename InputFunction> const DataType& evaluate(InputFunction&& inputs)
    {
        inputs(time_, setpoints_, disturbances_);
        interaction_dynamics(model_, data_, state_, setpoints_, disturbances_);
        return data_;
    }

    const State& state() const noexcept { return state_; }
    Scalar time() const noexcept { return time_; }
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

    template <typename InputFunction>
    Derivative derivative(Scalar time, const State& state, DataType& data, InputFunction& inputs)
    {
        inputs(time, setpoints_, disturbances_);
        interaction_dynamics(model_, data, state, setpoints_, disturbances_);
        Derivative result;
        result.position = state.twist.template head<3>();
        result.orientation =
            quaternion_derivative_world(state.pose.orientation, state.twist.template tail<3>()).coeffs();
        result.twist = data.object_acceleration();
        return result;
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

    template <typename InputFunction> void step_runge_kutta_4(InputFunction& inputs)
    {
        const Scalar dt = time_step_;
        const Scalar half = dt / Scalar(2);
        const Derivative k1 = derivative(time_, state_, data_, inputs);
        const Derivative k2 = derivative(time_ + half, advance(state_, k1, half), stage_data_, inputs);
        const Derivative k3 = derivative(time_ + half, advance(state_, k2, half), stage_data_, inputs);
        const Derivative k4 = derivative(time_ + dt, advance(state_, k3, dt), stage_data_, inputs);
        const Scalar sixth = dt / Scalar(6);
        state_.pose.position += sixth * (k1.position + Scalar(2) * (k2.position + k3.position) + k4.position);
        state_.pose.orientation.coeffs() +=
            sixth * (k1.orientation + Scalar(2) * (k2.orientation + k3.orientation) + k4.orientation);
        state_.pose.orientation.normalize();
        state_.twist += sixth * (k1.twist + Scalar(2) * (k2.twist + k3.twist) + k4.twist);
        time_ += dt;
    }

    template <typename InputFunction> void step_semi_implicit_euler(InputFunction& inputs)
    {
        const Scalar dt = time_step_;
        const Derivative slope = derivative(time_, state_, data_, inputs);
        state_.twist += dt * slope.twist;
        state_.pose.position += dt * state_.twist.template head<3>();
        const Vector3<Scalar> rotation = dt * state_.twist.template tail<3>();
        state_.pose.orientation = quaternion_exp(rotation) * state_.pose.orientation;
        state_.pose.orientation.normalize();
        time_ += dt;
    }

    const ModelType& model_;
    Scalar time_step_;
    Integrator integrator_;
    State state_{};
    Scalar time_ = Scalar(0);
    SetpointsType setpoints_;
    DisturbancesType disturbances_;
    DataType data_;
    DataType stage_data_;
};

}  // namespace coopdyn
