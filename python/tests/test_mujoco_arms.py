"""coopdyn.MujocoArms (docs/python.md, "The MuJoCo adapter"; docs/adapters.md, "Conventions") on the
C++ tests' models (tests/adapters/): J against central differences of the contact poses read
through the binding, Jdot qdot against central differences of J along qdot, M and h against one
MuJoCo step (Newton: qvel' - qvel = dt M^-1 (tau - h)), the contact pose against the URDF's forward
kinematics by hand, the errors; and a controller loop in Python against the same loop in C++
(identical torques)."""

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
