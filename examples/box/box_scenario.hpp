// One dual-arm box experiment as plain data (docs/dual-arm-box.md, "Scenario files"): the plant's
// true friction and the box's true mass, the controller's own (conservative) friction model and
// gains, the desired motion and what the person does to the box. box_scenario_loader.hpp reads it
// from JSON; the defaults here are the shipped hold experiment's.
#pragma once

#include "box_model.hpp"

#include "../common/ranges.hpp"

#include <coopdyn/control/controller_model.hpp>

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>

namespace box_example {

enum class Experiment { hold, push, add_mass, circle };

inline const char* to_string(Experiment experiment) noexcept
{
    switch (experiment) {
    case Experiment::hold: return "hold";
    case Experiment::push: return "push";
    case Experiment::add_mass: return "add_mass";
    case Experiment::circle: return "circle";
    }
    return "unknown";
}

/// A friction coefficient's range, one definition for --friction, the scenario's
/// controller.friction and plant_friction.sliding (a coefficient above 2 is no material pair a
/// palm meets, and the MuJoCo contact is tuned for those below).
inline constexpr example_common::NumberRange friction_range{0.01, 2.0};

/// What the controller knows and how it behaves (Lin et al.; docs/control.md).
struct ControllerSettings {
    double friction = 0.2;              ///< mu of its friction model (the plant's is larger)
    double torsional_friction = 0.002;  ///< gamma (m)
    double patch_half_size = 0.04;      ///< delta_x = delta_y (m): the 8 x 8 cm palm
    double minimum_normal_force = 60.0; ///< f_min (N)
    double translational_stiffness = 100.0;  ///< K_d (N/m), all three axes
    double rotational_stiffness = 30.0;      ///< K_d (N m/rad)
    double translational_damping = 60.0;     ///< D_d (N s/m)
    double rotational_damping = 4.0;         ///< D_d (N m s/rad)
    double posture_stiffness = 20.0;         ///< K_n (N m/rad), every joint
    double posture_damping = 4.0;            ///< D_n (N m s/rad)
    /// The contact QP's objective (docs/control.md, "The least squeeze"): the scenario's
    /// `objective` preset, then its `internal_weight`, `torque_weight`, `moment_weight`,
    /// `squeeze_weight` if given; without them the library's default, the least squeeze (one
    /// default for the library, the programs and the shipped scenarios; docs/dual-arm-box.md,
    /// "The objective": with f_min = 70 N it presses the paper's 70 N at rest).
    coopdyn::SqueezeObjective<double> objective{};
    /// Cut-off (Hz) of the first-order low-pass on the box's measured acceleration that feeds the
    /// external-wrench estimate L(7); 0 leaves the acceleration out (a quasi-static estimate).
    double acceleration_cutoff = 20.0;
};

/// A person pushes the box: a force along `direction` ramping up to `force`, held, released,
/// `repeats` times every `period` seconds from `start`.
struct Push {
    double start = 1.0;
    double force = 40.0;
    double ramp = 0.5;
    double hold = 2.0;
    double period = 4.0;
    int repeats = 2;
    Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
};

/// Masses put on the box: `step` kg every `interval` s from `start` until `total` kg were added.
struct AddedMass {
    double start = 1.0;
    double step = 0.5;
    double interval = 2.0;
    double total = 2.5;
};

/// A person grabs the box and holds it where it is (a stiff spring-damper to the grab point).
struct PersonHold {
    double start = 3.0;
    double duration = 1.0;
    double stiffness = 3000.0;  ///< N/m
    double damping = 150.0;     ///< N s/m
};

/// x_d = c + [0, r cos(theta), r sin(theta)], c chosen so that it starts at the hold pose;
/// theta's rate ramps from 0 to `angular_speed` over `ramp` seconds from `start`.
struct Circle {
    double start = 0.5;
    double radius = 0.1;
    double angular_speed = 1.5;  ///< s of the paper (rad/s)
    double ramp = 1.0;
};

/// The paper's numbers next to which the run is printed (Lin et al., section IV).
struct PaperNumbers {
    std::optional<double> squeeze_at_rest;   ///< N per arm (70)
    std::optional<double> squeeze_pushed;    ///< N per arm (110)
};

struct BoxScenario {
    std::string source = "(built in)";
    std::string name = "hold";
    /// The scene file (examples/scenes, docs/scenes.md) whose arms hold the object, resolved against
    /// the scenario file's folder; empty: the LWR 4 pair of dual_arm_box.xml at its fixed sizes.
    std::optional<std::string> scene;
    Experiment experiment = Experiment::hold;
    double duration = 4.0;           ///< s
    double box_mass = 0.7;           ///< kg, true (unknown to the controller)
    PlantFriction plant_friction{};  ///< true
    ControllerSettings controller{};
    std::optional<Push> push;
    std::optional<AddedMass> added_mass;
    std::optional<PersonHold> person_hold;
    std::optional<Circle> circle;
    /// A person's hand trembles: while the person pushes or holds the box, a random force of this
    /// RMS per axis (N), white noise low-passed at 5 Hz, seeded by the run's seed, adds to theirs.
    double person_tremor = 0.0;
    PaperNumbers paper{};
};

}  // namespace box_example
