/// \file
/// \brief Per-tick input checks (docs/conventions.md, "Per-tick inputs"): finite values and unit
/// quaternions in the object state, the setpoints and the disturbances. check_inputs() is cheap
/// (no allocation, about 20 ns per arm) and can run in Release on every tick; the per-tick
/// functions run the same checks as debug assertions.
///
/// Why the library does not normalise: a quaternion of norm 1.5 is not a rotation, and scaling it
/// silently would hide the caller's bug (a state integrated without renormalisation, a setpoint
/// left at zero). The tolerance is generous enough for a quaternion normalised in float and used
/// in double: |norm - 1| <= unit_quaternion_tolerance (1e-6 for double, 1.2e-5 for float).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/model/cooperative_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopdyn {

/// Which per-tick input is bad (InputCheck).
enum class InputProblem {
    none,
    state_position,       ///< object position not finite
    state_orientation,    ///< object quaternion not finite or not unit
    state_twist,          ///< object twist not finite
    setpoint_position,    ///< p_i^d not finite
    setpoint_orientation, ///< q_i^d not finite or not unit (a zero quaternion included)
    setpoint_twist,       ///< xdot_i^d not finite
    setpoint_acceleration,///< xdd_i^d not finite
    setpoint_wrench,      ///< h_i^d not finite
    object_disturbance,   ///< htilde_o not finite
    arm_disturbance,      ///< htilde_i not finite
    object_wrench,        ///< a desired object wrench h_o^d not finite
};

/// \brief The outcome of check_inputs: the first bad input found and its arm (no_arm for the
/// object's inputs). Converts to true when every input is good.
struct InputCheck {
    InputProblem problem = InputProblem::none;
    Index arm = no_arm;

    bool ok() const noexcept { return problem == InputProblem::none; }
    explicit operator bool() const noexcept { return ok(); }
    /// The input's name, as in the parameter names of the exceptions.
    const char* input() const noexcept
    {
        switch (problem) {
        case InputProblem::none: return "none";
        case InputProblem::state_position: return "state.pose.position (not finite)";
        case InputProblem::state_orientation: return "state.pose.orientation (not finite or not unit)";
        case InputProblem::state_twist: return "state.twist (not finite)";
        case InputProblem::setpoint_position: return "setpoints.positions (not finite)";
        case InputProblem::setpoint_orientation: return "setpoints.orientations (not finite or not unit)";
        case InputProblem::setpoint_twist: return "setpoints.twists (not finite)";
        case InputProblem::setpoint_acceleration: return "setpoints.accelerations (not finite)";
        case InputProblem::setpoint_wrench: return "setpoints.wrenches (not finite)";
        case InputProblem::object_disturbance: return "disturbances.object (not finite)";
        case InputProblem::arm_disturbance: return "disturbances.end_effectors (not finite)";
        case InputProblem::object_wrench: return "object_wrench (not finite)";
        }
        return "unknown";
    }
};

/// \brief Checks an object state: finite position and twist, finite unit quaternion.
template <typename Scalar> InputCheck check_state(const RigidBodyState<Scalar>& state) noexcept
{
    if (!detail::all_finite(state.pose.position)) {
        return {InputProblem::state_position, no_arm};
    }
    if (!detail::is_unit_quaternion(state.pose.orientation.coeffs())) {
        return {InputProblem::state_orientation, no_arm};
    }
    if (!detail::all_finite(state.twist)) {
        return {InputProblem::state_twist, no_arm};
    }
    return {};
}

/// \brief Checks the setpoints of every arm: finite values, unit quaternions.
template <typename Scalar, int Arms> InputCheck check_setpoints(const Setpoints<Scalar, Arms>& setpoints) noexcept
{
    for (Index i = 0; i < setpoints.arms(); ++i) {
        if (!detail::all_finite(setpoints.positions.col(i))) {
            return {InputProblem::setpoint_position, i};
        }
        if (!detail::is_unit_quaternion(setpoints.orientations.col(i))) {
            return {InputProblem::setpoint_orientation, i};
        }
        if (!detail::all_finite(setpoints.twist(i))) {
            return {InputProblem::setpoint_twist, i};
        }
        if (!detail::all_finite(setpoints.acceleration(i))) {
            return {InputProblem::setpoint_acceleration, i};
        }
        if (!detail::all_finite(setpoints.wrench(i))) {
            return {InputProblem::setpoint_wrench, i};
        }
    }
    return {};
}

/// \brief Checks the disturbances: finite wrenches.
template <typename Scalar, int Arms>
InputCheck check_disturbances(const Disturbances<Scalar, Arms>& disturbances) noexcept
{
    if (!detail::all_finite(disturbances.object)) {
        return {InputProblem::object_disturbance, no_arm};
    }
    for (Index i = 0; i < disturbances.arms(); ++i) {
        if (!detail::all_finite(disturbances.end_effector(i))) {
            return {InputProblem::arm_disturbance, i};
        }
    }
    return {};
}

/// \brief Checks every input of a tick of interaction_dynamics (state, setpoints, disturbances)
/// and returns the first bad one. noexcept, allocation-free; cheap enough for every tick in
/// Release. The shapes are not checked here (they stop the program, docs/model.md).
template <typename ModelType>
InputCheck check_inputs(const ModelType& model, const RigidBodyState<typename ModelType::Scalar>& state,
                        const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints,
                        const Disturbances<typename ModelType::Scalar, ModelType::arms_at_compile_time>& disturbances) noexcept
{
    (void)model;
    if (const InputCheck result = check_state(state); !result) {
        return result;
    }
    if (const InputCheck result = check_setpoints(setpoints); !result) {
        return result;
    }
    return check_disturbances(disturbances);
}

}  // namespace coopdyn

/// Debug builds: stop with the bad input's name when `check` (an InputCheck expression) fails.
/// Removed by NDEBUG or COOPDYN_DISABLE_ASSERTS, like COOPDYN_ASSERT.
#if defined(NDEBUG) || defined(COOPDYN_DISABLE_ASSERTS)
#define COOPDYN_ASSERT_INPUTS(check) ((void)0)
#else
#define COOPDYN_ASSERT_INPUTS(check)                                                \
    do {                                                                            \
        const ::coopdyn::InputCheck coopdyn_input_check_ = (check);                 \
        if (!coopdyn_input_check_) {                                                \
            ::coopdyn::detail::stop_on_misuse(__func__, coopdyn_input_check_.input(), coopdyn_input_check_.arm); \
        }                                                                           \
    } while (false)
#endif
