// The fault campaign's faults (docs/faults.md): each cell of the table names one fault of one
// class and how large it is; FaultHook applies it to one run of the box experiment loop
// (box_experiment.hpp, run_experiment_on's fault hook) and counts what the controller reported.
// The scenario-side faults (a push, added mass, the controller's friction) are set on the
// scenario by apply_cell. Scene-independent: fault_runs.hpp runs the cells on the scenes.
#pragma once

#include "box_experiment.hpp"

#include <coopdyn/control.hpp>

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace fault_campaign {

using box_example::Vector6d;

enum class FaultKind {
    none,               ///< the undisturbed hold
    dropout_nan,        ///< the object's measurement NaN for `value` ms
    dropout_stale,      ///< its last value repeated, flagged object_stale, for `value` ms
    dropout_unflagged,  ///< its last value repeated, NOT flagged, for `value` ms
    latency,            ///< the object's state (pose, twist, acceleration) `value` ticks late
    latency_pose,       ///< its pose and twist `value` ticks late, the acceleration on time
    torque_noise,       ///< Gaussian noise of `value` times each joint's limit (RMS) on the torque sent
    torque_limits,      ///< the library's torque_limits at `value` times the hold's peak torque
    model_scale,        ///< the controller's M and h times `value` (every link's inertia off)
    payload,            ///< `value` kg at the first palm the controller does not know
    friction,           ///< the controller's friction coefficient `value` times the true one
    push_beyond,        ///< a push `value` times the load the controller's friction holds at f_min
    mass_doubling,      ///< the object's mass times `value` at once
    random_push,        ///< a seeded random push (the Monte Carlo)
};

/// One cell of the table: a fault of a class, how large, and whether it lies inside the envelope
/// docs/faults.md states (a drop inside it is a finding; outside it, a drop must be reported).
/// The envelope is the measured one: the full campaign of 2026-11-27 set out with latency up to 5
/// ticks, 5 % torque noise and a model 20 % light inside it, dropped the box there on MuJoCo
/// (docs/faults.md, "Where the envelope ends"), and those cells are outside it since; the program's
/// exit code checks that the documented envelope still holds.
struct Cell {
    std::string name;
    std::string fault_class;
    FaultKind kind = FaultKind::none;
    double value = 0.0;
    bool in_envelope = true;
};

/// Every cell of the campaign, in the table's order.
inline std::vector<Cell> campaign_cells()
{
    using K = FaultKind;
    return {
        {"nominal", "none", K::none, 0.0, true},
        {"dropout_nan_10ms", "dropout", K::dropout_nan, 10.0, true},
        {"dropout_nan_100ms", "dropout", K::dropout_nan, 100.0, true},
        {"dropout_nan_1000ms", "dropout", K::dropout_nan, 1000.0, false},
        {"dropout_stale_10ms", "dropout", K::dropout_stale, 10.0, true},
        {"dropout_stale_100ms", "dropout", K::dropout_stale, 100.0, true},
        {"dropout_stale_1000ms", "dropout", K::dropout_stale, 1000.0, false},
        {"dropout_unflagged_100ms", "dropout", K::dropout_unflagged, 100.0, true},
        {"dropout_unflagged_1000ms", "dropout", K::dropout_unflagged, 1000.0, false},
        {"latency_1tick", "latency", K::latency, 1.0, true},
        {"latency_3ticks", "latency", K::latency, 3.0, false},
        {"latency_5ticks", "latency", K::latency, 5.0, false},
        {"latency_pose_3ticks", "latency", K::latency_pose, 3.0, true},
        {"latency_pose_5ticks", "latency", K::latency_pose, 5.0, false},
        {"torque_noise_1pct", "torque", K::torque_noise, 0.01, true},
        {"torque_noise_5pct", "torque", K::torque_noise, 0.05, false},
        {"torque_limits_90pct", "torque", K::torque_limits, 0.9, false},
        {"model_mass_x0.8", "model", K::model_scale, 0.8, false},
        {"model_mass_x0.9", "model", K::model_scale, 0.9, true},
        {"model_mass_x1.1", "model", K::model_scale, 1.1, true},
        {"model_mass_x1.2", "model", K::model_scale, 1.2, true},
        {"payload_0.5kg", "model", K::payload, 0.5, true},
        {"friction_x1.5", "friction", K::friction, 1.5, true},
        {"push_beyond_x20", "overload", K::push_beyond, 20.0, false},
        {"mass_doubling", "overload", K::mass_doubling, 2.0, true},
    };
}

/// The cells of --short (the tests): one of each kind of outcome.
inline std::vector<Cell> short_cells()
{
    std::vector<Cell> cells;
    for (const Cell& cell : campaign_cells()) {
        for (const char* name : {"nominal", "dropout_nan_100ms", "latency_1tick", "push_beyond_x20"}) {
            if (cell.name == name) {
                cells.push_back(cell);
            }
        }
    }
    return cells;
}

/// The load (N) the controller's friction model holds with every palm at its minimum normal
/// force: K mu f_min (each palm's Coulomb cone at f_min; the controller raises the squeeze above
/// f_min when its estimate F_x asks for more, so this is the load it holds without doing so).
inline double friction_load(const box_example::BoxScenario& scenario, std::size_t palms)
{
    return static_cast<double>(palms) * scenario.controller.friction * scenario.controller.minimum_normal_force;
}

/// When the faults start: a third into the run (the middle of the hold, after the settle).
inline double fault_start(double duration) { return duration / 3.0; }

/// The scenario-side faults: the run's duration, the push, the added mass, the controller's
/// friction; the rest is FaultHook's.
inline void apply_cell(const Cell& cell, double duration, std::size_t palms, box_example::BoxScenario& scenario)
{
    scenario.duration = duration;
    scenario.person_tremor = 0.0;
    const double start = fault_start(duration);
    if (cell.kind == FaultKind::friction) {
        scenario.controller.friction = cell.value * scenario.plant_friction.sliding;
    } else if (cell.kind == FaultKind::push_beyond) {
        box_example::Push push;
        push.start = start;
        push.force = cell.value * friction_load(scenario, palms);
        push.ramp = 0.2;
        push.hold = 1.0;
        push.period = 2.0 * duration;
        push.repeats = 1;
        push.direction = -Eigen::Vector3d::UnitZ();
        scenario.push = push;
    } else if (cell.kind == FaultKind::mass_doubling) {
        box_example::AddedMass added;
        added.start = start;
        added.step = (cell.value - 1.0) * scenario.box_mass;
        added.total = added.step;
        added.interval = 2.0 * duration;
        scenario.added_mass = added;
    }
}

/// What the controller reported in a run, counted over the logged ticks (t >= 0).
struct CellStats {
    std::array<long, 9> statuses{};  ///< ticks per ControlStatus (its enumerators' order)
    long saturated_ticks = 0;        ///< ticks the library's torque limits clamped a joint
    long slipping_ticks = 0;         ///< ticks with a contact marked slipping
    double controller_slip = 0.0;    ///< largest contact slip the controller measured (m)
    double first_report = std::numeric_limits<double>::quiet_NaN();  ///< first tick not ok (s)
    bool finite = true;              ///< every torque sent and computed was finite
    Eigen::VectorXd peak_torque;     ///< largest |tau_j| sent
};

inline constexpr std::array<coopdyn::ControlStatus, 9> all_statuses{
    coopdyn::ControlStatus::ok,          coopdyn::ControlStatus::friction_infeasible, coopdyn::ControlStatus::qp_failed,
    coopdyn::ControlStatus::singular,    coopdyn::ControlStatus::invalid_input,      coopdyn::ControlStatus::degraded,
    coopdyn::ControlStatus::safe_hold,   coopdyn::ControlStatus::torque_saturated,   coopdyn::ControlStatus::slipping};

/// The experiment loop's fault hook (box_experiment.hpp's NoFaults interface) for one cell:
/// corrupts the controller's input or the torque sent, and keeps CellStats. Allocates nothing
/// per tick (the latency's ring is sized at construction).
class FaultHook {
public:
    FaultHook(const Cell& cell, double duration, const Eigen::VectorXd& joint_limits, unsigned long long seed)
        : cell_(cell), start_(fault_start(duration)), end_(start_ + 1e-3 * cell.value), limits_(joint_limits),
          generator_(seed), ring_(delayed(cell) ? static_cast<std::size_t>(cell.value) + 1 : 0)
    {
        stats_.peak_torque = Eigen::VectorXd::Zero(joint_limits.size());
    }

    template <typename Input> void corrupt_input(long tick, double t, Input& input) noexcept
    {
        const bool window = t >= start_ - 1e-9 && t < end_ - 1e-9;
        switch (cell_.kind) {
        case FaultKind::dropout_nan:
            if (window) {
                input.object.pose.position(0) = std::numeric_limits<double>::quiet_NaN();
                input.object_acceleration.setConstant(std::numeric_limits<double>::quiet_NaN());
            }
            break;
        case FaultKind::dropout_stale:
        case FaultKind::dropout_unflagged:
            if (!window) {
                frozen_ = input.object;
                frozen_acceleration_ = input.object_acceleration;
                input.object_stale = false;  // read_plant leaves the flag as the last tick set it
            } else {
                input.object = frozen_;
                input.object_acceleration = frozen_acceleration_;
                input.object_stale = cell_.kind == FaultKind::dropout_stale;
            }
            break;
        case FaultKind::latency:
        case FaultKind::latency_pose: delay(tick, input); break;
        case FaultKind::model_scale:
            // Every link's mass, first moment and inertia times lambda scales M and h exactly by
            // lambda (both are linear in the inertial parameters; docs/faults.md).
            input.inertia *= cell_.value;
            input.bias *= cell_.value;
            break;
        default: break;
        }
    }

    template <typename Torque, typename Input, typename Data>
    void corrupt_torque(long tick, double t, Torque& tau, const Input& input, const Data& data) noexcept
    {
        if (cell_.kind == FaultKind::torque_noise) {
            for (Eigen::Index j = 0; j < tau.size(); ++j) {
                tau(j) += cell_.value * limits_(j) * normal_(generator_);
            }
        } else if (cell_.kind == FaultKind::payload) {
            // The payload's weight at the first palm's contact point, J_1^T [0, 0, -m g, 0, 0, 0]
            // (J's rows [v; w]): a static force at the contact point, no moment, no inertia.
            tau.noalias() += (-cell_.value * 9.81) * input.jacobian.row(2).transpose();
        }
        if (tick >= 0) {
            count(t, tau, data);
        }
    }

    const CellStats& stats() const noexcept { return stats_; }

private:
    static bool delayed(const Cell& cell) noexcept
    {
        return cell.kind == FaultKind::latency || cell.kind == FaultKind::latency_pose;
    }

    template <typename Input> void delay(long tick, Input& input) noexcept
    {
        const std::size_t size = ring_.size();
        if (!ring_started_) {  // the first ticks see the first state: nothing older was measured
            first_tick_ = tick;
            ring_started_ = true;
            for (Delayed& slot : ring_) {
                slot = {input.object, input.object_acceleration};
            }
        }
        const std::size_t slot = static_cast<std::size_t>(tick - first_tick_) % size;
        ring_[slot] = {input.object, input.object_acceleration};
        const Delayed& old = ring_[(slot + 1) % size];  // written `size - 1` ticks ago
        input.object = old.object;
        if (cell_.kind == FaultKind::latency) {
            input.object_acceleration = old.acceleration;
        }
    }

    template <typename Torque, typename Data> void count(double t, const Torque& tau, const Data& data) noexcept
    {
        stats_.statuses[static_cast<std::size_t>(data.status)] += 1;
        stats_.saturated_ticks += data.saturated_count > 0 ? 1 : 0;
        stats_.slipping_ticks += data.slipping_contacts > 0 ? 1 : 0;
        if (data.slip_measured) {
            stats_.controller_slip = std::max(stats_.controller_slip, data.slip_distance.maxCoeff());
        }
        const bool reported = data.status != coopdyn::ControlStatus::ok || data.slipping_contacts > 0 ||
                              data.saturated_count > 0;
        if (reported && std::isnan(stats_.first_report)) {
            stats_.first_report = t;
        }
        stats_.finite = stats_.finite && tau.allFinite() && data.torque.allFinite();
        for (Eigen::Index j = 0; j < tau.size(); ++j) {
            stats_.peak_torque(j) = std::max(stats_.peak_torque(j), std::abs(tau(j)));
        }
    }

    struct Delayed {
        coopdyn::RigidBodyState<double> object{};
        Vector6d acceleration = Vector6d::Zero();
    };

    Cell cell_;
    double start_;
    double end_;
    Eigen::VectorXd limits_;
    std::mt19937_64 generator_;
    std::normal_distribution<double> normal_{0.0, 1.0};
    std::vector<Delayed> ring_;
    long first_tick_ = 0;
    bool ring_started_ = false;
    coopdyn::RigidBodyState<double> frozen_{};
    Vector6d frozen_acceleration_ = Vector6d::Zero();
    CellStats stats_;
};

}  // namespace fault_campaign
