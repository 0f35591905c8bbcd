"""The first paper's Model / Data / interaction_dynamics / Simulator from Python, against physics
and numpy: the README's quick start (the composite mass of Theorem 2, (31)), the interaction
wrenches against (18) evaluated in numpy on the stacked system built from (13)-(14), Newton's
third law, and a Simulator driven by a Python callback against closed-form motions."""

import numpy as np
import pytest

import coopdyn
from conftest import block_diag, constraint_by_hand, grasp_by_hand, skew


def beam(stiffness=300.0, damping=180.0, gravity=None, inertia=(0.055, 0.0, 0.055)):
    arm = coopdyn.ImpedanceEndEffector(mass=10.0, rotational_inertia=0.5 * np.eye(3),
                                       translational_damping=damping, rotational_damping=10.0 if damping else 0.0,
                                       translational_stiffness=stiffness, rotational_stiffness=50.0 if stiffness else 0.0)
    obj = coopdyn.RigidObject(1.75, np.diag(inertia))
    arms = [coopdyn.Arm(arm, coopdyn.Pose([0, -0.4, 0])), coopdyn.Arm(arm, coopdyn.Pose([0, 0.4, 0]))]
    return coopdyn.Model(obj, arms, gravity)


def test_readme_quick_start():
    model = beam()
    data = coopdyn.Data(model)
    setpoints = coopdyn.Setpoints(2)
    disturbances = coopdyn.Disturbances(2)
    offsets = model.grasp_offsets_body
    wrenches = np.zeros(12)
    for i in range(2):
        setpoints.set_pose(i, coopdyn.Pose(offsets[:, i]))
        wrenches[6 * i + 2] = -0.5 * 1.75 * 9.81
    setpoints.wrenches = wrenches
    disturbances.object = [10.0, 0, 0, 0, 0, 0]
    state = coopdyn.RigidBodyState()
    assert coopdyn.check_inputs(model, state, setpoints, disturbances)
    coopdyn.interaction_dynamics(model, data, state, setpoints, disturbances)
    # Theorem 2, (31): the object and both end-effectors move as one body of mass m_o + sum m_i.
    np.testing.assert_allclose(data.object_acceleration(), [10.0 / 21.75, 0, 0, 0, 0, 0], atol=1e-12)


def test_interaction_dynamics_against_eq_18_in_numpy(rng):
    model = beam(inertia=(0.055, 0.01, 0.06))  # a regular J_o: the stacked M has a Cholesky factor
    data = coopdyn.Data(model)
    setpoints = coopdyn.Setpoints(2)
    setpoints.positions = rng.standard_normal((3, 2))
    q = rng.standard_normal((4, 2))
    setpoints.orientations = q / np.linalg.norm(q, axis=0)
    setpoints.twists = rng.standard_normal(12)
    disturbances = coopdyn.Disturbances(2)
    disturbances.object = rng.standard_normal(6)
    state = coopdyn.RigidBodyState()
    state.pose.position = rng.standard_normal(3)
    qo = rng.standard_normal(4)
    state.pose.orientation = qo / np.linalg.norm(qo)
    state.twist = rng.standard_normal(6)
    h = coopdyn.interaction_dynamics(model, data, state, setpoints, disturbances)
    r = data.grasp_offsets
    omega = state.twist[3:]
    A, b = constraint_by_hand(r, omega)
    J_o = data.object_rotation @ np.diag([0.055, 0.01, 0.06]) @ data.object_rotation.T
    M_o = block_diag(1.75 * np.eye(3), J_o)
    M_ee = block_diag(10.0 * np.eye(3), 0.5 * np.eye(3))
    M = block_diag(M_o, M_ee, M_ee)
    L = np.linalg.cholesky(M)
    reference = L @ np.linalg.pinv(A @ np.linalg.inv(L).T) @ (b - A @ np.linalg.solve(M, data.h_sigma))
    np.testing.assert_allclose(h, reference, rtol=1e-9, atol=1e-9 * np.abs(reference).max())
    np.testing.assert_allclose(data.wrenches, h)
    # (22)-(23): h_o = -G h'; the per-arm wrenches about the centre sum to h_o.
    np.testing.assert_allclose(h[:6], -grasp_by_hand(r) @ h[6:], atol=1e-9 * np.abs(h).max())
    np.testing.assert_allclose(sum(data.wrench_on_object_at_centre(i) for i in range(2)), data.object_wrench(),
                               atol=1e-9 * np.abs(h).max())
    # M xdd = hSigma + h.
    np.testing.assert_allclose(M @ data.accelerations, data.h_sigma + h, atol=1e-9 * np.abs(h).max())


def test_simulator_with_a_python_feedback_callback():
    """No springs, no dampers, no gravity: the assembly is one free body of mass 21.75 kg. A
    Python callback pushes it with F - c v (feedback of the stage's state); RK4 follows
    v(t) = F/c (1 - exp(-c t / m)) to its truncation error."""
    model = beam(stiffness=0.0, damping=0.0, gravity=[0.0, 0.0, 0.0])
    mass, force, drag = 21.75, 10.0, 5.0
    calls = []

    def inputs(time, state, setpoints, disturbances):
        calls.append(time)
        disturbances.object = [force - drag * state.twist[0], 0, 0, 0, 0, 0]

    simulator = coopdyn.Simulator(model, 1e-3, coopdyn.RigidBodyState())
    for _ in range(500):
        status = simulator.step(inputs)
        assert status.ok
    t = simulator.time
    assert t == pytest.approx(0.5)
    assert len(calls) == 4 * 500  # RK4, per stage
    v = force / drag * (1 - np.exp(-drag * t / mass))
    x = force / drag * (t - mass / drag * (1 - np.exp(-drag * t / mass)))
    assert simulator.state.twist[0] == pytest.approx(v, rel=1e-10)
    assert simulator.state.pose.position[0] == pytest.approx(x, rel=1e-9)
    # An exception in the callback propagates and the step is not taken.
    def failing(time, state, setpoints, disturbances):
        raise RuntimeError("from the callback")
    with pytest.raises(RuntimeError, match="from the callback"):
        simulator.step(failing)
    assert simulator.steps == 500


def test_simulator_conserves_energy_without_dampers():
    model = beam(damping=0.0, gravity=[0.0, 0.0, 0.0])
    state = coopdyn.RigidBodyState()
    state.twist = [0.1, -0.05, 0.02, 0.1, 0.2, -0.1]
    simulator = coopdyn.Simulator(model, 1e-3, state)
    offsets = model.grasp_offsets_body
    for i in range(2):
        simulator.setpoints.set_pose(i, coopdyn.Pose(offsets[:, i]))

    def energy():
        data = coopdyn.Data(model)
        coopdyn.interaction_dynamics(model, data, simulator.state, simulator.setpoints, coopdyn.Disturbances(2))
        return coopdyn.kinetic_energy(model, data) + coopdyn.spring_potential_energy(model, data, simulator.setpoints)

    start = energy()
    for _ in range(1000):
        simulator.step()
    assert energy() == pytest.approx(start, rel=1e-6)
    assert start > 0


def test_model_errors_name_the_arm():
    arm = coopdyn.ImpedanceEndEffector(mass=-2.0, rotational_inertia=np.eye(3))
    good = coopdyn.ImpedanceEndEffector(mass=1.0, rotational_inertia=np.eye(3))
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.Model(coopdyn.RigidObject(1.0, np.eye(3)), [coopdyn.Arm(good), coopdyn.Arm(arm)])
    assert (error.value.parameter, error.value.arm) == ("mass", 1)
    assert "arm 1: 'mass'" in str(error.value)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.Simulator(beam(), -1e-3)
    assert error.value.parameter == "time_step"
    model = beam()
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.interaction_dynamics(model, coopdyn.Data(model), coopdyn.RigidBodyState(), coopdyn.Setpoints(3),
                                     coopdyn.Disturbances(2))
    assert error.value.parameter == "setpoints"
    with pytest.raises(ValueError) as error:
        coopdyn.Setpoints(2).positions = np.zeros((3, 3))
    assert "(3, 2)" in str(error.value)
    bad = coopdyn.Setpoints(2)
    bad.orientations = np.zeros((4, 2))
    check = coopdyn.check_inputs(model, coopdyn.RigidBodyState(), bad, coopdyn.Disturbances(2))
    assert not check and check.problem == coopdyn.InputProblem.setpoint_orientation and check.arm == 0


def test_model_parameters_print_compare_and_pickle():
    import pickle
    arm = coopdyn.Arm(coopdyn.ImpedanceEndEffector(mass=10.0, rotational_inertia=0.5 * np.eye(3)),
                      coopdyn.Pose([0, 0.4, 0]))
    resolved = coopdyn.ResolvedAccelerationEndEffector()
    resolved.apparent_inertia = np.diag([1.0, 2, 3, 4, 5, 6])
    for obj in (arm, arm.end_effector, coopdyn.RigidObject(1.75, np.diag([0.055, 0.0, 0.055])), resolved,
                coopdyn.ResolvedAccelerationArm(resolved, coopdyn.Pose([1, 2, 3]))):
        again = pickle.loads(pickle.dumps(obj))
        assert again == obj and repr(again) == repr(obj)
    assert repr(arm).startswith("Arm(end_effector=ImpedanceEndEffector(mass=10.0")
    other = pickle.loads(pickle.dumps(arm))
    other.end_effector.mass = 11.0  # a reference into `other`: writes go through
    assert other.end_effector.mass == 11.0 and other != arm


def test_a_built_model_is_constant_from_python():
    model = beam()
    model.object.mass = 100.0  # a copy: the validated model does not change
    assert model.object.mass == 1.75
    arm = model.end_effector(0)
    arm.mass = -1.0
    with pytest.raises(coopdyn.InvalidModel):
        model.set_end_effector(0, arm)
    assert model.end_effector(0).mass == 10.0
    arm.mass = 12.0
    model.set_end_effector(0, arm)
    assert model.end_effector(0).mass == 12.0


def test_simulator_run_logs_a_free_body():
    """Simulator.run's log against x(t) = F t^2 / (2 m) of the free assembly (no springs, dampers or
    gravity: one body of 21.75 kg, Theorem 2 (31)) pushed by a constant 10 N."""
    model = beam(stiffness=0.0, damping=0.0, gravity=[0.0, 0.0, 0.0])
    simulator = coopdyn.Simulator(model, 1e-3)
    simulator.disturbances.object = [10.0, 0, 0, 0, 0, 0]
    log = simulator.run(250)
    assert set(log) == {"time", "position", "orientation", "twist", "object_acceleration", "wrenches"}
    assert log["wrenches"].shape == (250, 18) and log["position"].shape == (250, 3)
    np.testing.assert_allclose(log["time"], np.arange(250) * 1e-3, atol=1e-15)
    np.testing.assert_allclose(log["position"][:, 0], 10.0 * log["time"] ** 2 / (2 * 21.75), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(log["object_acceleration"][:, 0], 10.0 / 21.75, rtol=1e-12)
    np.testing.assert_allclose(log["orientation"], np.tile([0, 0, 0, 1.0], (250, 1)), atol=1e-15)
    # The arms accelerate with the object, pushed by it alone: M_i xdd_i = h_i (hSigma_i = 0), so the
    # wrench on arm i is h_i = m_i a = 10 kg x 0.4598 m/s^2 along x.
    np.testing.assert_allclose(log["wrenches"][:, 6], 10.0 * 10.0 / 21.75, rtol=1e-12)
    assert simulator.steps == 250 and simulator.time == pytest.approx(0.25)


def test_resolved_acceleration_model_against_eq_18_in_numpy(rng):
    """(20)-(21): end-effectors with general SPD apparent inertias Lambda_i (the solver's dense
    path); the wrenches against (18) in numpy with A, b of (13)-(14) by hand, and h_i^Pi of (20)
    at identity orientations (no rotation error) by hand."""
    from conftest import random_spd
    arms = []
    lambdas, kd, kp = [], [], []
    for y in (-0.4, 0.4):
        ee = coopdyn.ResolvedAccelerationEndEffector()
        lambdas.append(random_spd(rng, 6))
        kd.append(np.diag(rng.uniform(5, 10, 6)))
        kp.append(np.diag(rng.uniform(20, 50, 6)))
        ee.apparent_inertia, ee.derivative_gain, ee.proportional_gain = lambdas[-1], kd[-1], kp[-1]
        arms.append(coopdyn.ResolvedAccelerationArm(ee, coopdyn.Pose([0, y, 0])))
    model = coopdyn.ResolvedAccelerationModel(coopdyn.RigidObject(1.75, np.diag([0.055, 0.01, 0.06])), arms)
    data = coopdyn.ResolvedAccelerationData(model)
    setpoints = coopdyn.Setpoints(2)
    setpoints.positions = rng.standard_normal((3, 2)) * 0.01 + model.grasp_offsets_body
    setpoints.twists = rng.standard_normal(12)
    setpoints.accelerations = rng.standard_normal(12)
    disturbances = coopdyn.Disturbances(2)
    state = coopdyn.RigidBodyState()
    state.twist = rng.standard_normal(6)
    h = coopdyn.interaction_dynamics(model, data, state, setpoints, disturbances)
    # (20) at identity orientations: h_i^Pi = Lambda_i (xdd_d - K_D (xdot_i - xdot_d) - K_P [p_i - p_d; 0]).
    for i in range(2):
        twist_i = data.end_effector_twists[6 * i:6 * i + 6]
        error = np.r_[data.end_effector_positions[:, i] - setpoints.positions[:, i], 0, 0, 0]
        expected = lambdas[i] @ (setpoints.accelerations[6 * i:6 * i + 6]
                                 - kd[i] @ (twist_i - setpoints.twists[6 * i:6 * i + 6]) - kp[i] @ error)
        np.testing.assert_allclose(data.motion_wrenches[6 * i:6 * i + 6], expected, rtol=1e-12, atol=1e-12)
    r = data.grasp_offsets
    omega = state.twist[3:]
    A, b = constraint_by_hand(r, omega)
    M = block_diag(block_diag(1.75 * np.eye(3), np.diag([0.055, 0.01, 0.06])), *lambdas)
    L = np.linalg.cholesky(M)
    reference = L @ np.linalg.pinv(A @ np.linalg.inv(L).T) @ (b - A @ np.linalg.solve(M, data.h_sigma))
    np.testing.assert_allclose(h, reference, rtol=1e-9, atol=1e-9 * np.abs(reference).max())
    bad = coopdyn.ResolvedAccelerationEndEffector()
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.ResolvedAccelerationModel(coopdyn.RigidObject(1.0, np.eye(3)), [coopdyn.ResolvedAccelerationArm(bad)])
    assert (error.value.parameter, error.value.arm) == ("apparent_inertia", 0)
