// The main job: the paper's two-arm beam (MODEL.md section 9, Section V of the first paper),
// held still by two impedance-controlled arms and pushed by a human-like force and torque.
//
// The beam is held at its grasp poses with the weight carried by the arms' desired wrenches
// (each arm takes half, which is the non-squeezing split for this symmetric grasp). A smooth push
// of --force newtons along x and a twist of --torque newton-metres about z are applied to the
// object and released; the program prints the object motion and the arm wrenches, and compares
// the held deflections with the apparent stiffness K = diag(600 I3, 196, 100, 196) of (61).

#include <coopdyn/coopdyn.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

struct Options {
    double duration = 10.0;  // s
    double force = 10.0;    // N, along x
    double torque = 1.0;    // N m, about z
};

void print_help()
{
    std::puts(
        "two_arm_beam: two impedance-controlled arms hold a 1 m aluminium beam (paper Section V)\n"
        "and a human pushes it. Prints the object motion and the arm wrenches.\n\n"
        "Options:\n"
        "  --duration SECONDS   simulated time (default 10, at least 9.5)\n"
        "  --force NEWTONS      push along x, held from 0.5 s to 4.5 s (default 10)\n"
        "  --torque NEWTON_M    twist about z, held from 5 s to 9 s (default 1)\n"
        "  --help               this text");
}

bool parse_number(const char* text, double& value)
{
    char* end = nullptr;
    value = std::strtod(text, &end);
    return end != text && *end == '\0' && std::isfinite(value);
}

/// Returns false (after printing why) on bad arguments.
bool parse(int argc, char** argv, Options& options, bool& help)
{
    for (int i = 1; i < argc; ++i) {
        const std::string name = argv[i];
        if (name == "--help" || name == "-h") {
            help = true;
            return true;
        }
        double* target = name == "--duration" ? &options.duration
                         : name == "--force"  ? &options.force
                         : name == "--torque" ? &options.torque
                                              : nullptr;
        if (target == nullptr) {
            std::fprintf(stderr, "two_arm_beam: unknown option '%s' (see --help)\n", argv[i]);
            return false;
        }
        if (i + 1 >= argc || !parse_number(argv[i + 1], *target)) {
            std::fprintf(stderr, "two_arm_beam: option '%s' needs a number\n", argv[i]);
            return false;
        }
        ++i;
    }
    if (options.duration < 9.5) {
        std::fprintf(stderr, "two_arm_beam: --duration must be at least 9.5 s to show both pushes\n");
        return false;
    }
    return true;
}

/// Smooth human-like push: raised-cosine ramps of 0.3 s up and down around a plateau on
/// [start, end].
double push_profile(double time, double start, double end)
{
    constexpr double ramp = 0.3;
    constexpr double pi = 3.14159265358979323846;
    if (time <= start || time >= end) {
        return 0.0;
    }
    if (time < start + ramp) {
        return 0.5 * (1.0 - std::cos(pi * (time - start) / ramp));
    }
    if (time > end - ramp) {
        return 0.5 * (1.0 - std::cos(pi * (end - time) / ramp));
    }
    return 1.0;
}

}  // namespace

int main(int argc, char** argv)
{
    using namespace coopdyn;
    Options options;
    bool help = false;
    if (!parse(argc, argv, options, help)) {
        return 2;
    }
    if (help) {
        print_help();
        return 0;
    }

    // Section V set-up: m_o = 1.75 kg, J_o about x and z 0.055 kg m^2 and (idealised) zero about
    // the beam's axis y; grasps at y = -+0.4 m; m_i = 10, d_i = 180, k_i = 300, J_i = 0.5 I3,
    // delta_i = 10, kappa_i = 50; T_s = 1 ms.
    ImpedanceEndEffector<double> arm;
    arm.mass = 10.0;
    arm.rotational_inertia = 0.5 * Eigen::Matrix3d::Identity();
    arm.translational_damping = 180.0;
    arm.rotational_damping = 10.0;
    arm.translational_stiffness = 300.0;
    arm.rotational_stiffness = 50.0;
    RigidObject<double> beam;
    beam.mass = 1.75;
    beam.inertia_body = Eigen::Vector3d(0.055, 0.0, 0.055).asDiagonal();
    const ImpedanceModel2 model(beam, {{arm, {Eigen::Vector3d(0.0, -0.4, 0.0)}},
                                       {arm, {Eigen::Vector3d(0.0, 0.4, 0.0)}}});

    constexpr double time_step = 1e-3;
    Simulator simulator(model, time_step, RigidBodyState<double>{});
    for (Index i = 0; i < model.arms(); ++i) {
        simulator.setpoints().set_pose(i, {model.grasp_offsets_body().col(i)});
        // h_i^d is the desired wrench ON arm i: half the beam's weight, pointing down.
        simulator.setpoints().wrench(i).head<3>() = 0.5 * beam.mass * model.gravity();
    }
    const auto inputs = [&options](double time, Setpoints<double, 2>&, Disturbances<double, 2>& disturbances) {
        disturbances.object.setZero();
        disturbances.object(0) = options.force * push_profile(time, 0.5, 4.5);
        disturbances.object(5) = options.torque * push_profile(time, 5.0, 9.0);
    };

    std::printf("coopdyn two-arm beam: m_o = 1.75 kg, arms at y = -0.4 / +0.4 m, RK4 at 1 kHz, %.1f s\n",
                options.duration);
    std::printf("push: %.2f N along x on [0.5, 4.5] s; twist: %.2f N m about z on [5, 9] s\n\n",
                options.force, options.torque);
    std::printf("%7s %10s %10s %10s %10s %10s %10s %10s\n", "t [s]", "f_x [N]", "t_z [Nm]", "x [mm]",
                "z [mm]", "rot_z [deg]", "arm0 f_x", "arm1 f_x");

    const auto steps = static_cast<Index>(std::llround(options.duration / time_step));
    double deflection_at_force_plateau = 0.0;
    double rotation_at_torque_plateau = 0.0;
    double peak_arm_force = 0.0;
    const auto wall_start = std::chrono::steady_clock::now();
    simulator.run(steps, inputs, [&](double time, const RigidBodyState<double>& state, const Data<ImpedanceModel2>& data) {
        const Eigen::AngleAxisd rotation(state.pose.orientation);
        const double rotation_z = rotation.angle() * rotation.axis().z();
        peak_arm_force = std::max(peak_arm_force, data.end_effector_wrench(0).head<3>().norm());
        const auto tick = std::llround(time / time_step);
        if (tick == 4200) {  // end of the force plateau, settled to 0.2 %
            deflection_at_force_plateau = state.pose.position.x();
        }
        if (tick == 8700) {  // end of the torque plateau, settled
            rotation_at_torque_plateau = rotation_z;
        }
        if (tick % 500 == 0) {
            std::printf("%7.2f %10.3f %10.3f %10.4f %10.4f %10.4f %10.3f %10.3f\n", time,
                        simulator.disturbances().object(0), simulator.disturbances().object(5),
                        1e3 * state.pose.position.x(), 1e3 * state.pose.position.z(),
                        rotation_z * 180.0 / 3.14159265358979323846, data.end_effector_wrench(0)(0),
                        data.end_effector_wrench(1)(0));
        }
    });
    const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    // Held deflections against the apparent stiffness (61): x = f / 600 exactly (linear springs),
    // rot_z ~ t / 196 for small angles (the springs' torque is nonlinear in the angle).
    const double expected_deflection = options.force / 600.0;
    const double expected_rotation = options.torque / 196.0;
    std::printf("\nsummary\n");
    std::printf("  deflection under the push:  %.5f mm  (apparent stiffness 600 N/m predicts %.5f mm)\n",
                1e3 * deflection_at_force_plateau, 1e3 * expected_deflection);
    std::printf("  rotation under the twist:   %.5f deg (apparent stiffness 196 N m/rad predicts %.5f deg, small angle)\n",
                rotation_at_torque_plateau * 180.0 / 3.14159265358979323846,
                expected_rotation * 180.0 / 3.14159265358979323846);
    std::printf("  final position:             (%.3g, %.3g, %.3g) m, peak arm force %.3f N\n",
                simulator.state().pose.position.x(), simulator.state().pose.position.y(),
                simulator.state().pose.position.z(), peak_arm_force);
    std::printf("  %lld steps in %.3f s wall clock (%.0fx real time)\n", static_cast<long long>(steps),
                wall_seconds, options.duration / wall_seconds);
    return 0;
}
