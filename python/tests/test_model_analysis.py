"""The first paper's analysis on a Model and its Data (docs/analysis.md) from Python, each against
something it is not computed from: M and D of (31)-(32) in numpy, K as the finite-difference
Jacobian of the springs' restoring wrench, the reduced model (30) against the full interaction
dynamics (18), the storage function of Lemma 1 against the kinetic and spring energies, the
internal / external split (53)-(54) against G h_int = 0 and a pure squeeze, the synthesis round
trip, and the resolved-acceleration Simulator against a free body's closed-form motion."""

import numpy as np
import pytest

import coopdyn
from conftest import block_diag, grasp_block, grasp_by_hand, quaternion_exp, quaternion_product


def three_arms(rng, gravity=(0.0, 0.0, 0.0)):
    """An asymmetric three-arm grasp: different masses, inertias, gains and grasp poses."""
    arms, gains = [], []
    for i in range(3):
        k, kappa = rng.uniform(100, 400), rng.uniform(10, 40)
        d, delta = rng.uniform(20, 80), rng.uniform(2, 8)
        ee = coopdyn.ImpedanceEndEffector(mass=rng.uniform(2, 8), rotational_inertia=np.diag(rng.uniform(0.1, 0.5, 3)),
                                          translational_damping=d, rotational_damping=delta,
                                          translational_stiffness=k, rotational_stiffness=kappa)
        q = rng.standard_normal(4)
        arms.append(coopdyn.Arm(ee, coopdyn.Pose(rng.uniform(-0.4, 0.4, 3), q / np.linalg.norm(q))))
        gains.append((ee, d, delta, k, kappa))
    model = coopdyn.Model(coopdyn.RigidObject(2.3, np.diag([0.05, 0.08, 0.11])), arms, list(gravity))
    return model, gains


def random_state(rng, twist_scale=1.0):
    state = coopdyn.RigidBodyState()
    state.pose.position = rng.standard_normal(3)
    q = rng.standard_normal(4)
    state.pose.orientation = q / np.linalg.norm(q)
    state.twist = twist_scale * rng.standard_normal(6)
    return state


def setpoints_at(model, data):
    """Setpoints at the end-effectors' poses in data: every spring unloaded."""
    setpoints = coopdyn.Setpoints(model.arms)
    setpoints.positions = data.end_effector_positions
    setpoints.orientations = data.end_effector_orientations
    return setpoints


def restoring_at(model, state, setpoints):
    data = coopdyn.Data(model)
    coopdyn.grasp_kinematics(model, data, state)
    return coopdyn.restoring_wrench(model, data, setpoints)


def test_apparent_impedance_of_a_model(rng):
    """M, D of (31)-(32) in numpy from the model's parts; K of Theorem 2 (E3) as the central
    finite-difference Jacobian of the exact restoring wrench h_o^K (it enters (30) as -h_o^K) at an
    unloaded configuration, the object turned about {w}'s axes."""
    model, gains = three_arms(rng)
    state = random_state(rng)
    data = coopdyn.Data(model)
    coopdyn.grasp_kinematics(model, data, state)
    impedance = coopdyn.apparent_impedance(model, data)

    R = data.object_rotation
    r = data.grasp_offsets
    np.testing.assert_allclose(r, R @ model.grasp_offsets_body, atol=1e-14)
    M_o = block_diag(2.3 * np.eye(3), R @ np.diag([0.05, 0.08, 0.11]) @ R.T)
    M = M_o + sum(grasp_block(r[:, i]) @ block_diag(ee.mass * np.eye(3), ee.rotational_inertia) @ grasp_block(r[:, i]).T
                  for i, (ee, *_) in enumerate(gains))
    D = sum(grasp_block(r[:, i]) @ np.diag([d] * 3 + [delta] * 3) @ grasp_block(r[:, i]).T
            for i, (_, d, delta, _, _) in enumerate(gains))
    np.testing.assert_allclose(impedance.inertia, M, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(impedance.damping, D, rtol=1e-12, atol=1e-12)

    setpoints = setpoints_at(model, data)
    np.testing.assert_allclose(coopdyn.restoring_wrench(model, data, setpoints), 0.0, atol=1e-10)
    step = 1e-6
    jacobian = np.zeros((6, 6))
    for j in range(6):
        columns = []
        for sign in (1.0, -1.0):
            moved = coopdyn.RigidBodyState()
            delta = np.zeros(6)
            delta[j] = sign * step
            moved.pose.position = state.pose.position + delta[:3]
            moved.pose.orientation = quaternion_product(quaternion_exp(delta[3:]), state.pose.orientation)
            columns.append(restoring_at(model, moved, setpoints))
        jacobian[:, j] = (columns[0] - columns[1]) / (2 * step)
    np.testing.assert_allclose(jacobian, impedance.stiffness, rtol=1e-6, atol=1e-6 * np.abs(impedance.stiffness).max())


def test_reduced_model_is_the_full_model_without_gravity(rng):
    """(30) against (18): no gravity, no desired wrenches, constant (loaded) setpoints, a moving
    object, an object disturbance: the reduced model's acceleration is the full model's."""
    model, _ = three_arms(rng)
    for _ in range(3):
        state = random_state(rng)
        setpoints = coopdyn.Setpoints(3)
        setpoints.positions = rng.standard_normal((3, 3))
        q = rng.standard_normal((4, 3))
        setpoints.orientations = q / np.linalg.norm(q, axis=0)
        disturbances = coopdyn.Disturbances(3)
        disturbances.object = rng.standard_normal(6)
        full = coopdyn.Data(model)
        coopdyn.interaction_dynamics(model, full, state, setpoints, disturbances)
        reduced = coopdyn.reduced_model_acceleration(model, coopdyn.Data(model), state, setpoints, disturbances.object)
        scale = np.abs(full.object_acceleration()).max()
        np.testing.assert_allclose(reduced, full.object_acceleration(), atol=1e-10 * scale)


def test_storage_function_is_kinetic_plus_spring_energy(rng):
    """Lemma 1's V = 1/2 xdot^T M xdot + sum U_i against the full model's kinetic energy (7) (from
    every body's own twist) plus the springs' energy (39); V is constant along an undamped motion."""
    model, _ = three_arms(rng)
    state = random_state(rng)
    setpoints = coopdyn.Setpoints(3)
    setpoints.positions = rng.standard_normal((3, 3)) * 0.05 + state.pose.position[:, None]
    data = coopdyn.Data(model)
    coopdyn.interaction_dynamics(model, data, state, setpoints, coopdyn.Disturbances(3))
    expected = coopdyn.kinetic_energy(model, data) + coopdyn.spring_potential_energy(model, data, setpoints)
    assert coopdyn.storage_function(model, data, setpoints) == pytest.approx(expected, rel=1e-12)


def test_decompose_wrenches(rng):
    """(53)-(54): internal + external = h', G h_int = 0 (G by hand, (24)); a symmetric pull on a
    beam at rest is all internal (nothing moves), a push on the object all external."""
    model, _ = three_arms(rng)
    state = random_state(rng)
    setpoints = coopdyn.Setpoints(3)
    setpoints.positions = rng.standard_normal((3, 3))
    disturbances = coopdyn.Disturbances(3)
    disturbances.object = rng.standard_normal(6)
    data = coopdyn.Data(model)
    coopdyn.interaction_dynamics(model, data, state, setpoints, disturbances)
    parts = coopdyn.decompose_wrenches(model, data)
    h = data.wrenches[6:]
    np.testing.assert_allclose(parts["internal"] + parts["external"], h, atol=1e-12 * np.abs(h).max())
    G = grasp_by_hand(data.grasp_offsets)
    assert np.abs(G @ parts["internal"]).max() < 1e-10 * np.abs(h).max()
    assert np.abs(parts["internal"]).max() > 1e-3 * np.abs(h).max()

    arm = coopdyn.ImpedanceEndEffector(mass=10.0, rotational_inertia=0.5 * np.eye(3), translational_damping=50.0,
                                       rotational_damping=5.0, translational_stiffness=300.0, rotational_stiffness=30.0)
    beam = coopdyn.Model(coopdyn.RigidObject(1.75, np.diag([0.055, 0.001, 0.055])),
                         [coopdyn.Arm(arm, coopdyn.Pose([0, -0.4, 0])), coopdyn.Arm(arm, coopdyn.Pose([0, 0.4, 0]))],
                         [0.0, 0.0, 0.0])
    pull = coopdyn.Setpoints(2)
    pull.positions = np.array([[0, 0], [-0.45, 0.45], [0, 0]]).astype(float)
    beam_data = coopdyn.Data(beam)
    coopdyn.interaction_dynamics(beam, beam_data, coopdyn.RigidBodyState(), pull, coopdyn.Disturbances(2))
    squeeze = coopdyn.decompose_wrenches(beam, beam_data)
    np.testing.assert_allclose(np.abs(beam_data.wrenches[6:]).max(), 300.0 * 0.05, rtol=1e-12)  # k times 5 cm
    np.testing.assert_allclose(squeeze["internal"], beam_data.wrenches[6:], atol=1e-12)
    np.testing.assert_allclose(squeeze["external"], 0.0, atol=1e-12)
    at_rest = coopdyn.Setpoints(2)
    at_rest.positions = beam.grasp_offsets_body
    push = coopdyn.Disturbances(2)
    push.object = [10.0, 0, 0, 0, 0, 0]
    coopdyn.interaction_dynamics(beam, beam_data, coopdyn.RigidBodyState(), at_rest, push)
    pushed = coopdyn.decompose_wrenches(beam, beam_data)
    np.testing.assert_allclose(pushed["internal"], 0.0, atol=1e-12)
    # Each 10 kg end-effector carried at the assembly's 10 / 21.75 m/s^2 (Theorem 2, (31)).
    np.testing.assert_allclose(pushed["external"][[0, 6]], 10.0 * 10.0 / 21.75, rtol=1e-12)


def test_synthesis_of_a_model_round_trip(rng):
    """synthesize_stiffness for the K of known gains (E3 in numpy), with_stiffness, then the new
    model's apparent stiffness is the target; an unreachable target is refused by with_stiffness
    and applied deliberately by arms_with_stiffness."""
    model, _ = three_arms(rng)
    data = coopdyn.Data(model)
    coopdyn.grasp_kinematics(model, data, random_state(rng))
    r = data.grasp_offsets
    k, kappa = rng.uniform(100, 300, 3), rng.uniform(10, 30, 3)
    target = sum(grasp_block(r[:, i]) @ np.diag([k[i]] * 3 + [kappa[i]] * 3) @ grasp_block(r[:, i]).T
                 for i in range(3))
    gains = coopdyn.synthesize_stiffness(model, data, target)
    assert gains.achievable
    tuned = coopdyn.with_stiffness(model, gains)
    tuned_data = coopdyn.Data(tuned)
    coopdyn.grasp_kinematics(tuned, tuned_data, data.object_state)
    np.testing.assert_allclose(coopdyn.apparent_impedance(tuned, tuned_data).stiffness, target,
                               rtol=1e-8, atol=1e-8 * np.abs(target).max())
    damped = coopdyn.with_damping(model, coopdyn.synthesize_damping(model, data, 0.3 * target))
    damped_data = coopdyn.Data(damped)
    coopdyn.grasp_kinematics(damped, damped_data, data.object_state)
    np.testing.assert_allclose(coopdyn.apparent_impedance(damped, damped_data).damping, 0.3 * target,
                               rtol=1e-8, atol=1e-8 * np.abs(target).max())

    unreachable = np.eye(6)
    unreachable[0, 3] = unreachable[3, 0] = 0.9
    closest = coopdyn.synthesize_stiffness(model, data, unreachable)
    assert not closest.achievable
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.with_stiffness(model, closest)
    assert error.value.parameter == "gains"
    arms = coopdyn.arms_with_stiffness(model, closest)
    assert [arm.end_effector.translational_stiffness for arm in arms] == pytest.approx(list(closest.translational))
    with pytest.raises(coopdyn.InvalidArgument):
        coopdyn.apparent_impedance(model, coopdyn.Data(coopdyn.Model(model.object, arms[:2])))


def test_resolved_acceleration_simulator_moves_a_free_body():
    """Resolved-acceleration end-effectors with zero gains and setpoint accelerations command no
    wrench (20): the assembly is one free body of 1.75 + 2 x 10 kg pushed by 10 N, x = F t^2 / 2m;
    run() with a Python input callable (the push) gives the same log as step()."""
    arms = []
    for y in (-0.4, 0.4):
        ee = coopdyn.ResolvedAccelerationEndEffector()
        ee.apparent_inertia = block_diag(10.0 * np.eye(3), 0.5 * np.eye(3))
        ee.derivative_gain = np.zeros((6, 6))
        ee.proportional_gain = np.zeros((6, 6))
        arms.append(coopdyn.ResolvedAccelerationArm(ee, coopdyn.Pose([0, y, 0])))
    model = coopdyn.ResolvedAccelerationModel(coopdyn.RigidObject(1.75, np.diag([0.055, 0.01, 0.06])), arms,
                                              [0.0, 0.0, 0.0])

    def push(time, state, setpoints, disturbances):
        disturbances.object = [10.0, 0, 0, 0, 0, 0]

    simulator = coopdyn.ResolvedAccelerationSimulator(model, 1e-3)
    log = simulator.run(200, push)
    assert log["wrenches"].shape == (200, 18)
    np.testing.assert_allclose(log["position"][:, 0], 10.0 * log["time"] ** 2 / (2 * 21.75), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(log["position"][:, 1:], 0.0, atol=1e-15)
    stepped = coopdyn.ResolvedAccelerationSimulator(model, 1e-3)
    positions = []
    for _ in range(200):
        positions.append(stepped.state.pose.position)
        stepped.step(push)
    np.testing.assert_array_equal(np.array(positions), log["position"])
    assert simulator.time == pytest.approx(0.2) and simulator.status.ok


def test_wrong_sizes_and_a_failed_run():
    model, _ = three_arms(np.random.default_rng(3))
    two = coopdyn.Setpoints(2)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.restoring_wrench(model, coopdyn.Data(model), two)
    assert error.value.parameter == "setpoints"
    with pytest.raises(ValueError, match=r"\(6,\)"):
        coopdyn.reduced_model_acceleration(model, coopdyn.Data(model), coopdyn.RigidBodyState(),
                                           coopdyn.Setpoints(3), np.zeros(5))
    simulator = coopdyn.Simulator(model, 1e-3)
    with pytest.raises(coopdyn.InvalidArgument):
        simulator.run(-1)

    def spoil(time, state, setpoints, disturbances):
        if time >= 0.0095:
            disturbances.object = [np.nan, 0, 0, 0, 0, 0]

    log = simulator.run(50, spoil)
    assert not simulator.status.ok and len(log["time"]) == simulator.status.failed_step
    assert np.isfinite(log["position"]).all()
