"""coopdyn.MujocoArms (docs/python.md, "The MuJoCo adapter"; docs/adapters.md, "Conventions") on the
C++ tests' models (tests/adapters/): J against central differences of the contact poses read
through the binding, Jdot qdot against central differences of J along qdot, M and h against one
MuJoCo step (Newton: qvel' - qvel = dt M^-1 (tau - h)), the contact pose against the URDF's forward
kinematics by hand, the errors; and a controller loop in Python against the same loop in C++
(identical torques). The forces (docs/adapters.md, "Applied wrenches and contact forces"): an
applied wrench against Newton and Euler for a free body, the palms' contact wrenches against the
held box's momentum rate, place_hands to its targets within the joints' ranges, and the box
program's push run as a Python loop against the C++ program (the same slip and palm forces)."""

import json
import pathlib

import numpy as np
import pytest

import coopdyn
from conftest import axis_angle

pytestmark = pytest.mark.skipif(not hasattr(coopdyn, "MujocoArms"), reason="coopdyn built without MuJoCo")

SOURCE = pathlib.Path(__file__).resolve().parents[2]
URDF = str(SOURCE / "tests" / "adapters" / "two_link_arm.urdf")
TORSO = str(SOURCE / "tests" / "adapters" / "torso_arms.xml")
BOX = str(SOURCE / "examples" / "box" / "dual_arm_box.xml")
TORSO_JOINTS = ["right_shoulder", "torso_lift", "left_shoulder", "left_elbow", "left_extend", "left_wrist",
                "right_elbow", "right_wrist"]  # q's order differs from the model's (test_mujoco_adapter.cpp)
TORSO_SITES = ["left_tip", "right_tip", "torso_site"]
BOX_JOINTS = [f"{side}_joint{j}" for side in ("left", "right") for j in range(1, 8)]


def urdf_arms():
    return coopdyn.MujocoArms(URDF, ["shoulder", "elbow", "wrist_slide"], ["palm"])


def box_arms():
    return coopdyn.MujocoArms(BOX, BOX_JOINTS, ["left_palm", "right_palm"])


def skew_vee(m):
    return np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]]) / 2


def random_arm_state(arms, rng):
    """The chosen joints moved by up to +-0.3 (rad or m/10) from qpos0 and random velocities."""
    qpos, qvel = arms.qpos, np.zeros(arms.nv)
    for j in range(arms.joints):
        qpos[arms.qpos_address(j)] += 0.3 * rng.uniform(-1, 1) * (0.1 if j == 2 and arms.joints == 3 else 1)
        qvel[arms.dof_address(j)] = rng.uniform(-1.5, 1.5)
    return qpos, qvel


def poses(arms):
    return [(arms.contact_position(i), arms.contact_rotation(i)) for i in range(arms.arms)]


@pytest.mark.parametrize("model", ["urdf", "torso"])
def test_jacobian_is_the_derivative_of_the_contact_poses(model, rng):
    arms = urdf_arms() if model == "urdf" else coopdyn.MujocoArms(TORSO, TORSO_JOINTS, TORSO_SITES)
    qpos, qvel = random_arm_state(arms, rng)
    arms.set_state(qpos, qvel)
    jacobian, rate, velocities = arms.jacobian(), arms.jacobian_rate_qdot(), arms.velocities()
    step = 1e-6
    for j in range(arms.joints):
        plus, minus = qpos.copy(), qpos.copy()
        plus[arms.qpos_address(j)] += step
        minus[arms.qpos_address(j)] -= step
        arms.set_state(plus)
        after = poses(arms)
        arms.set_state(minus)
        before = poses(arms)
        for i in range(arms.arms):
            v = (after[i][0] - before[i][0]) / (2 * step)
            w = skew_vee(after[i][1] @ before[i][1].T) / (2 * step)  # log(R+ R-^T) / (2 e) to O(e^2)
            np.testing.assert_allclose(jacobian[6 * i:6 * i + 3, j], v, atol=1e-8)
            np.testing.assert_allclose(jacobian[6 * i + 3:6 * i + 6, j], w, atol=1e-8)
    # Jdot qdot: central differences of J along qdot at constant qdot (docs/adapters.md).
    jacobians = []
    for sign in (1, -1):
        moved = qpos.copy()
        for j in range(arms.joints):
            moved[arms.qpos_address(j)] += sign * step * qvel[arms.dof_address(j)]
        arms.set_state(moved, qvel)
        jacobians.append(arms.jacobian())
    expected = (jacobians[0] - jacobians[1]) / (2 * step) @ velocities
    np.testing.assert_allclose(rate, expected, atol=1e-7)
    np.testing.assert_array_equal(velocities, [qvel[arms.dof_address(j)] for j in range(arms.joints)])


def test_inertia_and_bias_give_mujocos_step(rng):
    """All the URDF arm's joints are chosen: one semi-implicit Euler step of MuJoCo moves qvel by
    dt M^-1 (tau - h) (L(1)), with M and h as read (no contact, no passive force in the model)."""
    arms = urdf_arms()
    qpos, qvel = random_arm_state(arms, rng)
    arms.set_state(qpos, qvel)
    inertia, bias = arms.inertia(), arms.bias()
    np.testing.assert_allclose(inertia, inertia.T, atol=1e-15)
    assert np.all(np.linalg.eigvalsh(inertia) > 0)
    tau = rng.uniform(-2, 2, arms.joints)
    arms.step(tau)
    np.testing.assert_allclose((arms.qvel - qvel) / arms.timestep, np.linalg.solve(inertia, tau - bias),
                               rtol=1e-9, atol=1e-9)


def rpy(r, p, y):
    """URDF's rpy: R = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def test_contact_pose_is_the_urdfs_forward_kinematics():
    """two_link_arm.urdf's joints' origins and axes, chained by hand: the palm's frame."""
    arms = urdf_arms()
    q = np.array([0.4, -0.7, 0.03])
    qpos = arms.qpos
    for j in range(3):
        qpos[arms.qpos_address(j)] = q[j]
    arms.set_state(qpos)
    R, p = np.eye(3), np.zeros(3)
    for origin, angles, motion in (([0, 0, 0.5], (0, 0.2, 0), axis_angle([0, 0, 1], q[0])),
                                   ([0.3, 0, 0], (0.3, 0, 0), axis_angle([0, 1, 0], q[1])),
                                   ([0.25, 0, 0], (0, 0, 0), None),
                                   ([0.04, 0.01, 0], (0, np.pi / 2, 0), np.eye(3))):
        p = p + R @ np.array(origin, dtype=float)
        R = R @ rpy(*angles)
        if motion is None:  # the prismatic wrist along x
            p = p + R @ np.array([q[2], 0, 0])
        else:
            R = R @ motion
    np.testing.assert_allclose(arms.contact_position(0), p, atol=1e-12)
    np.testing.assert_allclose(arms.contact_rotation(0), R, atol=1e-12)
    np.testing.assert_allclose(arms.contact_pose(0).rotation(), R, atol=1e-12)
    np.testing.assert_array_equal(arms.positions(), q)


def test_read_fills_the_input_as_the_single_reads(rng):
    """read(input) on the dual-arm box: M, h, J, Jdot qdot, q, qdot as the reads one at a time, and the
    contacts' poses (the palms' sites, z into the box: the left palm's normal points at the right's)."""
    arms = box_arms()
    arms.reset("hold")
    qpos, qvel = random_arm_state(arms, rng)
    arms.set_state(qpos, qvel)
    parameters = coopdyn.ControllerParameters()
    parameters.joints = arms.joints
    parameters.contacts = arms.contact_points("box")
    parameters.posture_stiffness = parameters.posture_damping = np.zeros(arms.joints)
    inp = coopdyn.ControllerInput(coopdyn.ControllerModel(parameters))
    assert not inp.contact_poses_filled
    arms.read(inp)
    for name in ("inertia", "bias", "jacobian", "jacobian_rate_qdot", "positions", "velocities"):
        np.testing.assert_array_equal(getattr(inp, name), getattr(arms, name)(), err_msg=name)
    assert inp.contact_poses_filled
    for i in range(2):
        np.testing.assert_array_equal(inp.contact_positions[:, i], arms.contact_position(i))
        np.testing.assert_allclose(coopdyn.Pose([0, 0, 0], inp.contact_orientations[:, i]).rotation(),
                                   arms.contact_rotation(i), atol=1e-12)
    arms.reset("hold")
    between = arms.contact_position(1) - arms.contact_position(0)
    assert arms.contact_rotation(0)[:, 2] @ between > 0.9 * np.linalg.norm(between)


def test_errors_name_the_joint_and_the_site(tmp_path):
    with pytest.raises(coopdyn.InvalidModel, match="left_joint9") as error:
        coopdyn.MujocoArms(BOX, BOX_JOINTS[:6] + ["left_joint9"] + BOX_JOINTS[7:], ["left_palm", "right_palm"])
    assert error.value.parameter == "joint_names[6]"
    with pytest.raises(coopdyn.InvalidModel, match="right_plam") as error:
        coopdyn.MujocoArms(BOX, BOX_JOINTS, ["left_palm", "right_plam"])
    assert error.value.arm == 1 and error.value.parameter == "contact_sites[1]"
    with pytest.raises(coopdyn.InvalidModel, match="cannot load") as error:
        coopdyn.MujocoArms(str(tmp_path / "none.xml"), BOX_JOINTS, ["left_palm", "right_palm"])
    assert error.value.parameter == "model_path"
    arms = box_arms()
    with pytest.raises(coopdyn.InvalidArgument, match=r"\(%d,\)" % arms.nq):
        arms.set_state(np.zeros(arms.nq + 1))
    parameters = coopdyn.ControllerParameters()
    parameters.joints = 13
    parameters.contacts = [coopdyn.ContactPoint(), coopdyn.ContactPoint()]
    parameters.check_contact_normals = False  # both frames at the centre: only the sizes matter here
    parameters.posture_stiffness = parameters.posture_damping = np.zeros(13)
    with pytest.raises(coopdyn.InvalidArgument, match="13 joints"):
        arms.read(coopdyn.ControllerInput(coopdyn.ControllerModel(parameters)))
    with pytest.raises(coopdyn.InvalidArgument, match="keyframe"):
        arms.reset("no_such_key")


def test_a_body_named_for_a_site_is_described_or_refused():
    """The box's right_link7 named where its palm's site right_palm (0.02 m out) was meant."""
    arms = coopdyn.MujocoArms(BOX, BOX_JOINTS, ["left_palm", "right_link7"])
    assert [arms.contact_frame_kind(i) for i in range(2)] == ["site", "body"]
    assert arms.contact_description(0) == "site 'left_palm' on body 'left_link7'"
    assert arms.contact_description(1).startswith("body 'right_link7' (no site has that name")
    assert "sites on this body: 'right_palm'" in arms.contact_description(1)
    assert np.linalg.norm(arms.contact_position(1) - box_arms().contact_position(1)) == pytest.approx(0.02, abs=1e-15)
    assert urdf_arms().contact_frame_kind(0) == "body"  # URDF: a fixed link's frame
    with pytest.raises(coopdyn.InvalidModel, match="'right_link7' is a body") as error:
        coopdyn.MujocoArms(BOX, BOX_JOINTS, ["left_palm", "right_link7"], sites_only=True)
    assert error.value.arm == 1 and error.value.parameter == "contact_sites[1]"


def box_controller(arms):
    """The box scenarios' controller settings (examples/box/scenarios/hold.json), the plant's mu."""
    parameters = coopdyn.ControllerParameters()
    parameters.joints = 14
    friction = coopdyn.ContactFriction()
    friction.friction_coefficient, friction.torsional_coefficient = 0.5, 0.002
    friction.patch_half_length_x = friction.patch_half_length_y = 0.04
    friction.minimum_normal_force = 30.0
    parameters.contacts = arms.contact_points("box", friction)
    parameters.stiffness = np.diag([100.0, 100.0, 100.0, 30.0, 30.0, 30.0])
    parameters.damping = np.diag([120.0, 120.0, 120.0, 4.0, 4.0, 4.0])
    parameters.posture_stiffness = np.full(14, 20.0)
    parameters.posture_damping = np.full(14, 4.0)
    return coopdyn.ControllerModel(parameters)


def test_a_python_loop_gives_the_torques_of_the_same_loop_in_cpp():
    """docs/adapters.md's loop: read, the object's state, controller_tick, step; 200 ticks on the
    dual-arm box from its hold keyframe, in Python and in C++ (coopdyn._mujoco._controller_loop)."""
    from coopdyn import _mujoco
    arms = box_arms()
    arms.reset("hold")
    model = box_controller(arms)
    inp = coopdyn.ControllerInput(model)
    arms.read(inp)
    inp.posture = inp.positions
    start = arms.object_state("box")
    inp.desired_pose = coopdyn.Pose(start.pose.position + [0.0, 0.0, 0.02], start.pose.orientation)
    ticks = 200
    cpp = _mujoco._controller_loop(arms, model, inp, "box", ticks)

    arms.reset("hold")
    data = coopdyn.ControllerData(model)
    python = np.zeros((ticks, 14))
    for tick in range(ticks):
        arms.read(inp)
        inp.object = arms.object_state("box")
        python[tick] = coopdyn.controller_tick(model, data, inp)
        arms.step(python[tick])
    assert data.status == coopdyn.ControlStatus.ok
    assert np.abs(python).max() > 1.0  # the arms carry themselves and the box
    np.testing.assert_array_equal(python, cpp)


# -- What the arms do to and measure of the world: applied wrenches, contact wrenches, place_hands ----

# torso_arms.xml's free object, as the file gives it: mass, centre of mass in its frame, principal
# inertia and its axes (quaternion w, x, y, z), and the model's gravity.
OBJECT_MASS = 1.3
OBJECT_CENTRE = np.array([0.01, -0.02, 0.03])
OBJECT_AXES = np.array([0.9, 0.1, 0.3, 0.2]) / np.linalg.norm([0.9, 0.1, 0.3, 0.2])
OBJECT_PRINCIPAL = np.diag([0.02, 0.03, 0.04])
TORSO_GRAVITY = np.array([0.3, -0.2, -9.81])
# dual_arm_box.xml's box: 0.7 kg, 0.2 x 0.3 x 0.4 m, uniform; its frame at its centre.
BOX_MASS = 0.7
BOX_INERTIA = BOX_MASS / 12 * np.diag([0.3**2 + 0.4**2, 0.2**2 + 0.4**2, 0.2**2 + 0.3**2])
LWR4_TORQUE_LIMITS = np.tile([176.0, 176.0, 100.0, 100.0, 100.0, 38.0, 38.0], 2)  # examples/box/lwr4.hpp


def rotation_wxyz(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_an_applied_wrench_moves_a_free_body_by_newton_and_euler(rng):
    """set_applied_wrench on torso_arms.xml's free object (its own tree, at rest, turned, its centre
    of mass off its frame): the change of its accelerations is F / m and I^-1 (T + (point - c) x F),
    with m, c and I from the model file."""
    arms = coopdyn.MujocoArms(TORSO, TORSO_JOINTS, TORSO_SITES)
    qpos = arms.qpos
    turn = axis_angle([1.0, -2.0, 0.5] / np.linalg.norm([1.0, -2.0, 0.5]), 0.8)
    w = np.sqrt(1 + np.trace(turn)) / 2
    qpos[3:7] = [w, (turn[2, 1] - turn[1, 2]) / (4 * w), (turn[0, 2] - turn[2, 0]) / (4 * w),
                 (turn[1, 0] - turn[0, 1]) / (4 * w)]
    arms.set_state(qpos, np.zeros(arms.nv))
    origin = qpos[:3]
    centre = origin + turn @ OBJECT_CENTRE
    inertia = turn @ rotation_wxyz(OBJECT_AXES) @ OBJECT_PRINCIPAL @ rotation_wxyz(OBJECT_AXES).T @ turn.T
    free = arms.qacc[:6]  # the free joint: its frame origin's acceleration in {w}, then alpha in its axes
    np.testing.assert_allclose(free, np.r_[TORSO_GRAVITY, 0, 0, 0], atol=1e-13)
    for point in (None, centre + rng.uniform(-0.2, 0.2, 3)):
        force, torque = rng.uniform(-3, 3, 3), rng.uniform(-1, 1, 3)
        arms.set_applied_wrench("object", np.r_[force, torque], point=point)
        at_centre = torque if point is None else torque + np.cross(point - centre, force)
        np.testing.assert_allclose(arms.applied_wrench("object"), np.r_[force, at_centre], rtol=1e-15, atol=1e-15)
        arms.set_state(qpos)  # mj_forward with the wrench
        alpha = turn @ arms.qacc[3:6]
        np.testing.assert_allclose(alpha, np.linalg.solve(inertia, at_centre), rtol=0, atol=1e-13)  # 8e-15 of 21 rad/s^2
        # the origin's acceleration: the centre's, F / m + g, plus alpha x (origin - centre) (at rest)
        np.testing.assert_allclose(arms.qacc[:3], force / OBJECT_MASS + TORSO_GRAVITY + np.cross(alpha, origin - centre),
                                   rtol=0, atol=1e-13)
    arms.clear_applied_wrenches()
    np.testing.assert_array_equal(arms.applied_wrench("object"), np.zeros(6))
    arms.set_state(qpos)
    np.testing.assert_allclose(arms.qacc[:6], free, atol=1e-14)


def test_applied_wrench_errors_name_the_argument():
    arms = box_arms()
    for kwargs, parameter in (({"body": "crate", "wrench": np.zeros(6)}, "body"),
                              ({"body": "world", "wrench": np.zeros(6)}, "body"),
                              ({"body": "box", "wrench": np.zeros(5)}, "wrench"),
                              ({"body": "box", "wrench": [0, 0, float("nan"), 0, 0, 0]}, "wrench"),
                              ({"body": "box", "wrench": np.zeros(6), "point": [0, 0]}, "point"),
                              ({"body": "box", "wrench": np.zeros(6), "point": [0, 0, float("inf")]}, "point")):
        with pytest.raises(coopdyn.InvalidArgument) as error:
            arms.set_applied_wrench(**kwargs)
        assert error.value.parameter == parameter, kwargs
    with pytest.raises(coopdyn.InvalidArgument, match="crate") as error:
        arms.contact_wrenches("crate")
    assert error.value.parameter == "object_body"
    np.testing.assert_array_equal(arms.applied_wrench("box"), np.zeros(6))


def test_the_palms_contact_wrenches_hold_the_box_by_newton_and_euler():
    """The box held by the controller for 0.3 s, then one more tick: the palms' contact wrenches of
    that step (contact_wrenches), its weight and a push give the box's momentum rate from MuJoCo's
    qacc, m a and I alpha + w x I w (with the box's m and I from the file); their vertical sum
    carries the weight m (g + a_z)."""
    arms = box_arms()
    arms.reset("hold")
    model = box_controller(arms)
    data, inp = coopdyn.ControllerData(model), coopdyn.ControllerInput(model)
    arms.read(inp)
    inp.posture = inp.positions
    inp.desired_pose = arms.object_state("box").pose
    push = np.array([1.0, -2.0, -5.0, 0.05, -0.02, 0.03])
    for tick in range(301):
        arms.read(inp)
        box = arms.object_state("box")
        inp.object = box
        palms = [arms.contact_position(i) for i in range(2)]
        rotations = [arms.contact_rotation(i) for i in range(2)]
        tau = coopdyn.controller_tick(model, data, inp)
        if tick == 300:
            arms.set_applied_wrench("box", push)
        arms.step(tau)
    assert data.status == coopdyn.ControlStatus.ok
    measured = arms.contact_wrenches("box")
    R = box.pose.rotation()
    omega, alpha = box.twist[3:], R @ arms.qacc[17:20]
    acceleration = arms.qacc[14:17]  # the box's frame origin is its centre
    force = measured.world[:3].sum(axis=1) + BOX_MASS * np.array([0, 0, -9.81]) + push[:3]
    moment = sum(measured.world[3:, i] + np.cross(palms[i] - box.pose.position, measured.world[:3, i]) for i in range(2))
    inertia = R @ BOX_INERTIA @ R.T
    np.testing.assert_allclose(force, BOX_MASS * acceleration, atol=1e-13)  # measured 6e-15 N
    np.testing.assert_allclose(moment + push[3:], inertia @ alpha + np.cross(omega, inertia @ omega), atol=1e-13)
    assert measured.world[2].sum() == pytest.approx(BOX_MASS * (9.81 + acceleration[2]) - push[2], abs=1e-13)
    assert np.all(measured.points >= 1) and np.all(measured.contact_frame[2] > 25.0)
    for i in range(2):  # in the palm's frame where the step began: [R^T f; R^T t]
        np.testing.assert_allclose(rotations[i] @ measured.contact_frame[:3, i], measured.world[:3, i], atol=1e-13)
        np.testing.assert_allclose(rotations[i] @ measured.contact_frame[3:, i], measured.world[3:, i], atol=1e-13)
    # the palms' z (the contact frames' normals) against MuJoCo's own contact normals: the box turns
    # a little in the palms (measured 1.1e-6)
    np.testing.assert_allclose(measured.contact_frame[2], measured.normal_forces, rtol=1e-5)
    untouched = arms.contact_wrenches("left_link3")
    np.testing.assert_array_equal(untouched.world, np.zeros((6, 2)))
    np.testing.assert_array_equal(untouched.points, [0, 0])


def test_place_hands_reaches_reachable_targets_and_keeps_joint_ranges(rng):
    """place_hands on the box (targets: the palms at a random posture near the hold, one as a Pose,
    one as a (position, quaternion) pair) reaches them to 1e-9 and leaves the box; on the torso model
    an unreachable target ends short of it with every limited joint within the file's range."""
    arms = box_arms()
    arms.reset("hold")
    start = arms.qpos
    moved = start.copy()
    moved[:14] += 0.4 * rng.uniform(-1, 1, 14)
    arms.set_state(moved)
    targets = [arms.contact_pose(0), (arms.contact_position(1), arms.contact_pose(1).orientation)]
    rotations = [arms.contact_rotation(i) for i in range(2)]
    arms.set_state(start)
    result = arms.place_hands(targets)
    assert result.converged() and result.status == coopdyn.InverseKinematicsStatus.converged, result
    assert result.residual <= 1e-10 and 0 < result.iterations < 100
    for i, target in enumerate((targets[0].position, targets[1][0])):
        np.testing.assert_allclose(arms.contact_position(i), target, atol=1e-9)
        np.testing.assert_allclose(arms.contact_rotation(i), rotations[i], atol=1e-9)
    np.testing.assert_array_equal(arms.qpos[14:], start[14:])  # the box stays
    np.testing.assert_array_equal(arms.positions(), arms.qpos[:14])  # mj_forward ran: the reads see it

    torso = coopdyn.MujocoArms(TORSO, TORSO_JOINTS, TORSO_SITES[:2])  # the two hands
    far = [(torso.contact_position(0) + [0.0, 2.0, 1.0], torso.contact_pose(0).orientation), torso.contact_pose(1)]
    result = torso.place_hands(far, coopdyn.InverseKinematicsOptions(iteration_limit=300))
    assert not result.converged() and result.residual > 1.0, result
    ranges = {"torso_lift": (-0.3, 0.3), "left_shoulder": (-2, 2), "left_extend": (-0.1, 0.1), "right_shoulder": (-2, 2)}
    q = torso.positions()
    for j, name in enumerate(TORSO_JOINTS):
        if name in ranges:
            assert ranges[name][0] <= q[j] <= ranges[name][1], name
    assert q[TORSO_JOINTS.index("torso_lift")] == pytest.approx(0.3, abs=1e-12)  # pulled up as far as it goes


def test_place_hands_errors_name_the_argument():
    arms = box_arms()
    arms.reset("hold")
    good = [arms.contact_pose(0), arms.contact_pose(1)]
    cases = (([good[0]], {}, "targets"),
             ([good[0], "palm"], {}, "targets[1]"),
             ([good[0], ([0, 0], [0, 0, 0, 1])], {}, "targets[1]"),
             ([([0, float("nan"), 0], [0, 0, 0, 1]), good[1]], {}, "targets[0]"),
             (good, {"options": coopdyn.InverseKinematicsOptions(max_step=0.0)}, "options.max_step"),
             (good, {"options": coopdyn.InverseKinematicsOptions(damping=-1.0)}, "options.damping"))
    for targets, kwargs, parameter in cases:
        with pytest.raises(coopdyn.InvalidArgument) as error:
            arms.place_hands(targets, **kwargs)
        assert error.value.parameter == parameter, (parameter, str(error.value))
    assert "max_step=0.5" in repr(coopdyn.InverseKinematicsOptions())


def push_force(push, t):
    """examples/box/box_person.hpp's push_force: the push profile's magnitude at time t."""
    for k in range(push["repeats"]):
        local = t - push["start"] - k * push["period"]
        if local < 0.0:
            break
        up, held = push["ramp"], push["ramp"] + push["hold"]
        down = held + push["ramp"]
        if local < up:
            return push["force"] * local / push["ramp"]
        if local < held:
            return push["force"]
        if local < down:
            return push["force"] * (down - local) / push["ramp"]
    return 0.0


def objective_of(settings):
    """The scenario's objective as examples/box/box_scenario_loader.hpp reads it: the preset, then
    each weight given."""
    objective = getattr(coopdyn.SqueezeObjective, settings["objective"])()
    for name in ("internal_weight", "torque_weight", "moment_weight", "squeeze_weight"):
        if name in settings:
            setattr(objective, name, settings[name])
    return objective


def python_box_run(scenario, duration):
    """examples/box/box_experiment.hpp's run_experiment_on the MuJoCo plant (mujoco_plant.hpp), written
    with the bindings: 0.2 s of settling, then per 1 ms tick MujocoArms.read, the box's state and its
    last acceleration low-passed, controller_tick, the LWR 4's torque limits, the person's push through
    set_applied_wrench, step; logged: each palm's slip (the box's centre in the palm's contact plane
    since t = 0) and contact wrench (contact_wrenches, contact frame)."""
    settings, push = scenario["controller"], scenario["push"]
    assert scenario["plant_friction"] == {"sliding": 0.5, "torsional": 0.005}  # dual_arm_box.xml's pairs
    arms = box_arms()
    arms.reset("hold")
    friction = coopdyn.ContactFriction()
    friction.friction_coefficient = settings["friction"]
    friction.torsional_coefficient = settings["torsional_friction"]
    friction.patch_half_length_x = friction.patch_half_length_y = settings["patch_half_size"]
    friction.minimum_normal_force = settings["minimum_normal_force"]
    parameters = coopdyn.ControllerParameters()
    parameters.joints = 14
    parameters.contacts = arms.contact_points("box", friction)
    parameters.stiffness = np.diag([settings["translational_stiffness"]] * 3 + [settings["rotational_stiffness"]] * 3)
    parameters.damping = np.diag([settings["translational_damping"]] * 3 + [settings["rotational_damping"]] * 3)
    parameters.posture_stiffness = np.full(14, settings["posture_stiffness"])
    parameters.posture_damping = np.full(14, settings["posture_damping"])
    parameters.objective = objective_of(settings)
    parameters.torque_limits = LWR4_TORQUE_LIMITS  # as the program's limited_parameters
    model = coopdyn.ControllerModel(parameters)
    data, inp = coopdyn.ControllerData(model), coopdyn.ControllerInput(model)
    inp.posture = arms.positions()
    inp.desired_pose = arms.object_state("box").pose
    period = arms.timestep
    gain = 1.0 - np.exp(-2.0 * np.pi * settings["acceleration_cutoff"] * period)
    direction = np.asarray(push["direction"], dtype=float) / np.linalg.norm(push["direction"])
    filtered, last = np.zeros(6), np.zeros(6)
    ticks = round(duration / period)
    slip, normal, world = np.zeros((ticks, 2)), np.zeros((ticks, 2)), np.zeros((ticks, 6, 2))
    for tick in range(-round(0.2 / period), ticks):
        t = tick * period
        arms.read(inp)
        box = arms.object_state("box")
        inp.object = box
        filtered += gain * (last - filtered)
        inp.object_acceleration = filtered
        palms = [(arms.contact_position(i), arms.contact_rotation(i)) for i in range(2)]
        tau = np.clip(coopdyn.controller_tick(model, data, inp), -LWR4_TORQUE_LIMITS, LWR4_TORQUE_LIMITS)
        arms.set_applied_wrench("box", np.r_[push_force(push, t) * direction, 0.0, 0.0, 0.0])
        arms.step(tau)
        qacc = arms.qacc
        last = np.r_[qacc[14:17], box.pose.rotation() @ qacc[17:20]]
        if tick < 0:
            continue
        in_palm = [R.T @ (box.pose.position - p) for p, R in palms]
        if tick == 0:
            start = in_palm
        slip[tick] = [np.linalg.norm((in_palm[i] - start[i])[:2]) for i in range(2)]
        measured = arms.contact_wrenches("box")
        normal[tick], world[tick] = measured.contact_frame[2], measured.world
    assert data.status == coopdyn.ControlStatus.ok
    return slip, normal, world


def test_a_push_through_the_python_adapter_slips_as_the_cpp_program(tmp_path):
    """The issue's "done": the box program's push (examples/box/scenarios/push.json: 40 N down on the
    box held by friction, MuJoCo plant), shortened to one push ramped over 0.2 s from 0.1 s, held
    0.1 s and released, without the person's trembling hand (the program's own random stream), run
    as a Python loop (python_box_run) and by the C++ program's code (coopdyn.experiments.box) on the
    same scenario file: the same slip and palm forces, tick by tick."""
    if coopdyn.experiments._experiments is None:
        pytest.skip("coopdyn built without its experiments")
    scenario = json.loads((SOURCE / "examples" / "box" / "scenarios" / "push.json").read_text())
    scenario["push"].update(start=0.1, ramp=0.2, hold=0.1, repeats=1)
    scenario["person_tremor"] = 0.0
    scenario["controller"].setdefault("objective", "least_squeeze")  # the library's default, named
    file = tmp_path / "short_push.json"
    file.write_text(json.dumps(scenario))
    duration = 0.6
    cpp = coopdyn.experiments.box(str(file), "mujoco", duration=duration)
    slip, normal, world = python_box_run(scenario, duration)
    cpp_slip = np.c_[cpp.log["left_slip"], cpp.log["right_slip"]]
    cpp_normal = np.c_[cpp.log["left_meas_fz"], cpp.log["right_meas_fz"]]
    assert cpp_slip.shape == slip.shape == (600, 2)
    np.testing.assert_allclose(cpp.log["person_fz"], [-push_force(scenario["push"], t) for t in cpp.log["time"]])
    # it pushes, the palms squeeze harder (119 N from 70 N), the box slips 0.095 mm in them
    assert cpp_normal.max() > 1.2 * cpp_normal[0].max() and 1e-5 < cpp_slip.max() < 1e-3
    np.testing.assert_allclose(slip, cpp_slip, rtol=0, atol=1e-12)  # measured 1e-15 m
    np.testing.assert_allclose(normal, cpp_normal, rtol=1e-9, atol=1e-9)  # measured 7e-13 (relative)
    # the palms carry the weight and the push: their vertical forces sum to m g + F (+ m a_z)
    assert world[:, 2].sum(axis=1).max() == pytest.approx(BOX_MASS * 9.81 + scenario["push"]["force"], rel=0.02)
