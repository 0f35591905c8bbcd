// scene_hold: the hold experiment on one scene (docs/scenes.md), in MuJoCo, with a printed summary.
//
//     scene_hold examples/scenes/ur5e_panda.json [seconds] [mujoco|rigid|rigid-rk4]
//
// rigid: the rigid plant with its default integrator (semi-implicit Euler); rigid-rk4: with RK4.
#include "scene_hold.hpp"
#include "scene_rigid.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

int main(int argc, char** argv)
{
    const std::string plant_name = argc == 4 ? argv[3] : "mujoco";
    if (argc < 2 || argc > 4 || (plant_name != "mujoco" && plant_name != "rigid" && plant_name != "rigid-rk4")) {
        std::fprintf(stderr, "usage: scene_hold <scene.json> [seconds] [mujoco|rigid|rigid-rk4]\n");
        return 2;
    }
    try {
        scenes::SceneWorld world(scenes::read_scene(argv[1]));
        const scenes::StartReport start = world.start();
        std::printf("%s: K = %ld, Q = %ld\n", argv[1], static_cast<long>(world.arms().arms()),
                    static_cast<long>(world.arms().joints()));
        if (start.inverse_kinematics) {
            std::printf("IK: %s, residual %.3g after %d steps; contact frames off by %.3g m, %.3g rad\n",
                        coopdyn::numerics::to_string(start.ik.status), start.ik.residual, start.ik.iterations,
                        start.contact_position_error, start.contact_orientation_error);
        }
        std::printf("start q:");
        for (Eigen::Index j = 0; j < world.start_positions().size(); ++j) {
            std::printf(" %.4f", world.start_positions()(j));
        }
        std::printf("\n");
        scenes::HoldSettings settings;
        if (argc >= 3) {
            settings.seconds = std::atof(argv[2]);
        }
        scenes::HoldResult hold;
        if (plant_name != "mujoco") {
            scenes::RigidScenePlant plant(world, plant_name == "rigid" ? coopdyn::Integrator::semi_implicit_euler
                                                                       : coopdyn::Integrator::runge_kutta_4);
            hold = scenes::run_hold_on(world, plant, settings);
            const std::array<double, 2> weld = plant.weld_error();
            std::printf("rigid plant: weld error at the end %.3g m, %.3g rad\n", weld[0], weld[1]);
        } else {
            hold = scenes::run_hold(world, settings);
        }
        std::printf("hold %.2f s (%ld ticks): %s, slip %.3g mm, object moved %.3g mm / %.3g mrad; not-ok ticks %ld, "
                    "fallback ticks %ld, max |tau| %.1f N m; real-time factor %.1f, controller tick %.1f us\n",
                    static_cast<double>(hold.ticks) * 1e-3, hold.ticks, hold.dropped ? "DROPPED" : "held",
                    1e3 * hold.max_slip, 1e3 * hold.max_position_error, 1e3 * hold.max_orientation_error,
                    hold.not_ok_ticks, hold.fallback_ticks, hold.max_torque, hold.real_time_factor,
                    hold.tick_microseconds);
        for (std::size_t i = 0; i < hold.palms.size(); ++i) {
            const scenes::PalmHold& palm = hold.palms[i];
            std::printf("  palm %zu: slip %.3g mm, normal force mean %.2f N, last %.2f N (QP %.2f N), >= %d contact points\n",
                        i, 1e3 * palm.max_slip, palm.mean_normal_force, palm.final_normal_force,
                        palm.predicted_normal_force, palm.min_contact_points);
        }
        return hold.dropped ? 1 : 0;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "scene_hold: %s\n", error.what());
        return 1;
    }
}
