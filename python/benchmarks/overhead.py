"""The Python side of the bindings' per-call overhead (docs/python.md, "Speed"): the same calls as
overhead.cpp on the same inputs, microseconds per call, the median of 7 runs."""

import timeit

import numpy as np

import coopdyn


def per_call(call, calls):
    runs = sorted(timeit.timeit(call, number=calls) / calls * 1e6 for _ in range(7))
    return runs[3]


def controller():
    parameters = coopdyn.ControllerParameters()
    parameters.joints = 12
    left, right = coopdyn.ContactPoint(), coopdyn.ContactPoint()
    s = np.sqrt(0.5)
    left.frame = coopdyn.Pose([-0.15, 0, 0], [s, 0, s, 0])
    right.frame = coopdyn.Pose([0.15, 0, 0], [0, -s, 0, s])
    left.friction.friction_coefficient = right.friction.friction_coefficient = 0.5
    parameters.contacts = [left, right]
    parameters.stiffness = 1000.0 * np.eye(6)
    parameters.damping = 100.0 * np.eye(6)
    parameters.posture_stiffness = parameters.posture_damping = np.zeros(12)
    model = coopdyn.ControllerModel(parameters)
    data = coopdyn.ControllerData(model)
    inp = coopdyn.ControllerInput(model)
    inp.inertia = 2.0 * np.eye(12)
    inp.bias = np.r_[0, 0, 2 * 9.81, 0, 0, 0, 0, 0, 2 * 9.81, 0, 0, 0]
    inp.jacobian = np.eye(12)
    inp.object.pose.position = [0, 0, -2 * 9.81 / 1000]
    coopdyn.controller_tick(model, data, inp)
    print("controller_tick status", data.status, "normal forces", data.contact_frame_wrenches[2])
    tick = per_call(lambda: coopdyn.controller_tick(model, data, inp), 20000)

    M, h, J = inp.inertia.copy(), inp.bias.copy(), inp.jacobian.copy()
    zeros12, zeros6 = np.zeros(12), np.zeros(6)

    def loop_tick():  # what a 1 kHz loop does: set the arrays, tick, read the torques
        inp.inertia = M
        inp.bias = h
        inp.jacobian = J
        inp.jacobian_rate_qdot = zeros12
        inp.velocities = zeros12
        inp.object_acceleration = zeros6
        coopdyn.controller_tick(model, data, inp)
        return data.status, data.tightest_margin

    loop = per_call(loop_tick, 20000)
    return tick, loop


def dynamics():
    arm = coopdyn.ImpedanceEndEffector(mass=10.0, rotational_inertia=0.5 * np.eye(3), translational_damping=180.0,
                                       rotational_damping=10.0, translational_stiffness=300.0,
                                       rotational_stiffness=50.0)
    beam = coopdyn.RigidObject(1.75, np.diag([0.055, 0.0, 0.055]))
    model = coopdyn.Model(beam, [coopdyn.Arm(arm, coopdyn.Pose([0, -0.4, 0])),
                                 coopdyn.Arm(arm, coopdyn.Pose([0, 0.4, 0]))])
    data = coopdyn.Data(model)
    state, setpoints, disturbances = coopdyn.RigidBodyState(), coopdyn.Setpoints(2), coopdyn.Disturbances(2)
    return per_call(lambda: coopdyn.interaction_dynamics(model, data, state, setpoints, disturbances), 50000)


def qp():
    n, m = 6, 30
    H = 2.0 * np.eye(n)
    g = np.cos(np.arange(n, dtype=float))
    C = np.sin(7.0 * np.arange(m)[:, None] + 3.0 * np.arange(n)[None, :])
    d = np.ones(m)
    assert coopdyn.solve_qp(H, g, C, d).status == coopdyn.QpStatus.solved
    return per_call(lambda: coopdyn.solve_qp(H, g, C, d), 20000)


if __name__ == "__main__":
    tick, loop = controller()
    print(f"Python us per call: controller_tick K=2 Q=12 {tick:.2f}, interaction_dynamics N=2 {dynamics():.2f}, "
          f"solve_qp 6x30 {qp():.2f}; a loop tick setting 6 input arrays {loop:.2f}")
