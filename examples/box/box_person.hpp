// What happens to the box in the dual-arm box experiments besides the controller
// (docs/dual-arm-box.md, "Experiments"): the desired motion (hold, the circle), the person's
// push and grab with a trembling hand, and the masses put on the box. Plain functions of the
// scenario and the time; box_experiment.hpp applies them each tick.
#pragma once

#include "box_model.hpp"
#include "box_scenario.hpp"
#include "lwr4.hpp"

#include <coopdyn/spatial/pose.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

namespace box_example {

/// The person's force magnitude at time t (the push profile: ramps, holds, releases).
inline double push_force(const Push& push, double t) noexcept
{
    for (int k = 0; k < push.repeats; ++k) {
        const double local = t - push.start - k * push.period;
        if (local < 0.0) {
            break;
        }
        const double up = push.ramp;
        const double held = up + push.hold;
        const double down = held + push.ramp;
        if (local < up) {
            return push.force * local / push.ramp;
        }
        if (local < held) {
            return push.force;
        }
        if (local < down) {
            return push.force * (down - local) / push.ramp;
        }
    }
    return 0.0;
}

/// Mass added on the box by time t (kg).
inline double added_mass(const AddedMass& added, double t) noexcept
{
    if (t < added.start) {
        return 0.0;
    }
    const double steps = std::floor((t - added.start) / added.interval) + 1.0;
    return std::min(added.total, steps * added.step);
}

/// The box's mass with all the mass a scenario adds (kg).
inline double heaviest_box_mass(const BoxScenario& scenario) noexcept
{
    return scenario.box_mass + (scenario.added_mass ? scenario.added_mass->total : 0.0);
}

/// The heaviest static load the palms carry in `scenario` (N): the weight of the box with all its
/// added mass plus, if a person pushes, the push force held steady.
inline double static_load(const BoxScenario& scenario) noexcept
{
    Eigen::Vector3d load = heaviest_box_mass(scenario) * Eigen::Vector3d(0.0, 0.0, -9.81);
    if (scenario.push) {
        load += scenario.push->force * scenario.push->direction;
    }
    return load.norm();
}

/// The desired pose, twist and acceleration at time t (the hold pose, or the circle).
struct Desired {
    coopdyn::Pose<double> pose{};
    Vector6d twist = Vector6d::Zero();
    Vector6d acceleration = Vector6d::Zero();
};

inline Desired desired_motion(const BoxScenario& scenario, const coopdyn::Pose<double>& hold, double t) noexcept
{
    Desired desired;
    desired.pose = hold;
    if (!scenario.circle) {
        return desired;
    }
    const Circle& circle = *scenario.circle;
    const double local = std::max(0.0, t - circle.start);
    // theta's rate ramps linearly from 0 to s over the ramp, then stays.
    double theta, rate, rate_of_rate;
    if (local < circle.ramp) {
        theta = 0.5 * circle.angular_speed * local * local / circle.ramp;
        rate = circle.angular_speed * local / circle.ramp;
        rate_of_rate = t >= circle.start ? circle.angular_speed / circle.ramp : 0.0;
    } else {
        theta = circle.angular_speed * (local - 0.5 * circle.ramp);
        rate = circle.angular_speed;
        rate_of_rate = 0.0;
    }
    const double r = circle.radius;
    const Eigen::Vector3d radial(0.0, std::cos(theta), std::sin(theta));
    const Eigen::Vector3d tangent(0.0, -std::sin(theta), std::cos(theta));
    desired.pose.position = hold.position + r * (radial - Eigen::Vector3d::UnitY());
    desired.twist.head<3>() = r * rate * tangent;
    desired.acceleration.head<3>() = r * rate_of_rate * tangent - r * rate * rate * radial;
    return desired;
}

/// The person's trembling hand (BoxScenario::person_tremor): white noise low-passed at 5 Hz,
/// scaled to the RMS per axis, reproducible from the seed.
///
/// The white noise is standard normal by Marsaglia's polar method on uniforms made of a
/// mt19937_64 draw's top 53 bits (exactly uniform on the doubles k 2^-53 in [0, 1)), both values
/// of each accepted pair used. Not std::normal_distribution: libstdc++'s turns each draw into a
/// double by std::generate_canonical, which evaluates a long-double logarithm per call (about a
/// quarter of the person's cost in the rigid experiments), and its sequence is the standard
/// library's choice, so it differed between standard libraries; this one is the same everywhere.
class Tremor {
public:
    Tremor(double rms, unsigned long long seed, double period)
        : generator_(seed),
          gain_(1.0 - std::exp(-2.0 * 3.14159265358979323846 * 5.0 * period)),
          // A first-order low-pass of unit white noise has variance gain / (2 - gain).
          scale_(rms * std::sqrt((2.0 - gain_) / gain_))
    {
    }
    Eigen::Vector3d next()
    {
        for (Eigen::Index k = 0; k < 3; ++k) {
            state_(k) += gain_ * (standard_normal() - state_(k));
        }
        return scale_ * state_;
    }

private:
    /// Uniform on [0, 1): the top 53 bits as a double's mantissa, exactly.
    double uniform() noexcept { return static_cast<double>(generator_() >> 11) * 0x1.0p-53; }

    /// Standard normal: a point uniform in the unit disc (rejection from the square, s = u^2 + v^2
    /// in (0, 1)) gives the independent pair u, v times sqrt(-2 ln s / s); the second is kept for
    /// the next call.
    double standard_normal() noexcept
    {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        double u, v, s;
        do {
            u = 2.0 * uniform() - 1.0;
            v = 2.0 * uniform() - 1.0;
            s = u * u + v * v;
        } while (s >= 1.0 || s == 0.0);
        const double factor = std::sqrt(-2.0 * std::log(s) / s);
        spare_ = v * factor;
        has_spare_ = true;
        return u * factor;
    }

    std::mt19937_64 generator_;
    double spare_ = 0.0;
    bool has_spare_ = false;
    double gain_;
    double scale_;
    Eigen::Vector3d state_ = Eigen::Vector3d::Zero();
};

/// What the person does to the box (BoxScenario's push, person_hold and person_tremor): the wrench
/// [F; T] on the box's centre at time t.
class Person {
public:
    Person(const BoxScenario& scenario, unsigned long long seed, double period)
        : scenario_(scenario), tremor_(scenario.person_tremor, seed, period)
    {
    }

    Vector6d wrench(double t, const Eigen::Vector3d& box_position, const Eigen::Vector3d& box_velocity)
    {
        Vector6d wrench = Vector6d::Zero();
        const Eigen::Vector3d trembling = tremor_.next();
        if (scenario_.push) {
            const double force = push_force(*scenario_.push, t);
            wrench.head<3>() = force * scenario_.push->direction;
            if (force > 0.0) {
                wrench.head<3>() += trembling;
            }
        }
        if (scenario_.person_hold) {
            // A grab holds the box where it was when grabbed.
            const PersonHold& hold = *scenario_.person_hold;
            const bool holding = t >= hold.start && t < hold.start + hold.duration;
            if (holding && !holding_) {
                grab_point_ = box_position;
            }
            holding_ = holding;
            if (holding) {
                wrench.head<3>() +=
                    -hold.stiffness * (box_position - grab_point_) - hold.damping * box_velocity + trembling;
            }
        }
        return wrench;
    }

private:
    const BoxScenario& scenario_;
    Tremor tremor_;
    Eigen::Vector3d grab_point_ = Eigen::Vector3d::Zero();
    bool holding_ = false;
};

}  // namespace box_example
