"""The second paper's controller from Python: its kernels against numpy formulas from
docs/control.md (G^+, Jc, Jx, P, Mc, Lambda_c; the friction rows L(17)-(19) with E9), and a tick
against physical invariants (the README's two palms: the least squeeze m g / (2 mu), a massless
object in balance G w = -F_x, every friction margin >= 0) and numpy re-computations of its outputs."""

import pickle
import threading

import numpy as np
import pytest

import coopdyn
from conftest import grasp_by_hand, random_spd


def two_palms(mu=0.5):
    """The README's controller example: two free 6-DOF hands (J = I) squeezing a 2 kg box."""
    parameters = coopdyn.ControllerParameters()
    parameters.joints = 12
    left, right = coopdyn.ContactPoint(), coopdyn.ContactPoint()
    left_frame = np.array([[0, 0, 1], [0, -1, 0], [1, 0, 0]], dtype=float)
    right_frame = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], dtype=float)
    left.frame = coopdyn.Pose([-0.15, 0, 0], quaternion_of(left_frame))
    right.frame = coopdyn.Pose([0.15, 0, 0], quaternion_of(right_frame))
    left.friction.friction_coefficient = mu
    right.friction.friction_coefficient = mu
    parameters.contacts = [left, right]
    parameters.stiffness = 1000.0 * np.eye(6)
    parameters.damping = 100.0 * np.eye(6)
    parameters.posture_stiffness = np.zeros(12)
    parameters.posture_damping = np.zeros(12)
    return parameters


def quaternion_of(R):
    """[x, y, z, w] of a rotation matrix (trace method; these frames have trace >= -1 + margin)."""
    w = 0.5 * np.sqrt(max(1.0 + np.trace(R), 0.0))
    if w > 1e-6:
        return np.array([(R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w), w])
    x = 0.5 * np.sqrt(max(1.0 + R[0, 0] - R[1, 1] - R[2, 2], 0.0))
    return np.array([x, (R[0, 1] + R[1, 0]) / (4 * x), (R[0, 2] + R[2, 0]) / (4 * x), (R[2, 1] - R[1, 2]) / (4 * x)])


def box_input(model, mass=2.0):
    inp = coopdyn.ControllerInput(model)
    inp.inertia = 2.0 * np.eye(12)
    bias = np.zeros(12)
    bias[2] = bias[8] = 2 * 9.81
    inp.bias = bias
    inp.jacobian = np.eye(12)
    inp.object.pose.position = [0.0, 0.0, -mass * 9.81 / 1000.0]
    return inp


def friction_rows_by_hand(f):
    """A [f; t] <= b of L(17)-(19) with errata E9 (docs/control.md), in the library's row order."""
    n = f.pyramid_edges
    rows, bounds = [], []
    rows.append([0, 0, -1, 0, 0, 0]); bounds.append(-f.minimum_normal_force)
    for k in range(n):
        a = 2 * np.pi * (k + 0.5) / n
        rows.append([np.cos(a), np.sin(a), -f.friction_coefficient * np.cos(np.pi / n), 0, 0, 0]); bounds.append(0)
    for s in (1, -1):
        rows.append([0, 0, -f.torsional_coefficient, 0, 0, s]); bounds.append(0)
    for s in (1, -1):
        rows.append([0, 0, -f.patch_half_length_y, s, 0, 0]); bounds.append(0)
    for s in (1, -1):
        rows.append([0, 0, -f.patch_half_length_x, 0, s, 0]); bounds.append(0)
    return np.array(rows, dtype=float), np.array(bounds, dtype=float)


def margin_by_hand(f, w):
    A, b = friction_rows_by_hand(f)
    return np.min((b - A @ w) / np.linalg.norm(A, axis=1))


def test_friction_rows_and_margin_by_hand(rng):
    f = coopdyn.ContactFriction()
    f.friction_coefficient, f.torsional_coefficient = 0.7, 0.01
    f.patch_half_length_x, f.patch_half_length_y, f.minimum_normal_force, f.pyramid_edges = 0.04, 0.03, 2.0, 6
    A, b = coopdyn.contact_frame_friction_rows(f)
    A_ref, b_ref = friction_rows_by_hand(f)
    np.testing.assert_allclose(A, A_ref, atol=1e-15)
    np.testing.assert_allclose(b, b_ref, atol=1e-15)
    for _ in range(20):
        w = rng.standard_normal(6) + np.r_[0, 0, 10, 0, 0, 0]
        assert coopdyn.friction_margin(f, w) == pytest.approx(margin_by_hand(f, w), rel=1e-12, abs=1e-12)
        force, moment = coopdyn.friction_margins(f, w)
        assert min(force, moment) == pytest.approx(coopdyn.friction_margin(f, w), rel=1e-15)
    f.pyramid_edges = 2
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.friction_margin(f, np.zeros(6))
    assert error.value.parameter == "pyramid_edges"


def test_grasp_jacobians_and_projection_against_numpy(rng):
    K, Q = 2, 14
    r = rng.standard_normal((3, K))
    J = rng.standard_normal((6 * K, Q))
    M = random_spd(rng, Q)
    G = grasp_by_hand(r)
    G_plus = G.T @ np.linalg.inv(G @ G.T)
    Jx = np.linalg.solve(G @ G.T, G @ J)
    Jc = (np.eye(6 * K) - G_plus @ G) @ J
    np.testing.assert_allclose(coopdyn.object_jacobian(r, J), Jx, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(coopdyn.constraint_jacobian(r, J), Jc, rtol=1e-10, atol=1e-10)
    B = coopdyn.internal_wrench_basis(r)
    assert B.shape == (12, 6)
    np.testing.assert_allclose(B.T @ B, np.eye(6), atol=1e-12)
    np.testing.assert_allclose(G @ B, 0, atol=1e-12)
    # qdot in the grasp's null space (Jc qdot = 0), h arbitrary.
    qdot = (np.eye(Q) - np.linalg.pinv(Jc) @ Jc) @ rng.standard_normal(Q)
    p = coopdyn.projected_dynamics(M, rng.standard_normal(Q), J, rng.standard_normal(6 * K), qdot, r)
    assert p.status == coopdyn.ProjectionStatus.ok
    P = np.eye(Q) - np.linalg.pinv(Jc) @ Jc  # L(4)
    Mc = P @ M + np.eye(Q) - P  # L(26)
    Lambda_c = np.linalg.inv(Jx @ np.linalg.solve(Mc, P @ Jx.T))  # below L(15)
    np.testing.assert_allclose(p.projector, P, atol=1e-10)
    np.testing.assert_allclose(p.constrained_inertia, Mc, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(p.task_inertia, Lambda_c, rtol=1e-8, atol=1e-8 * np.abs(Lambda_c).max())
    np.testing.assert_allclose(p.object_twist, Jx @ qdot, rtol=1e-9, atol=1e-9)
    with pytest.raises(ValueError) as error:
        coopdyn.projected_dynamics(M[:-1, :-1], np.zeros(Q), J, np.zeros(12), np.zeros(Q), r)
    assert error.value.parameter == "M" and "(14, 14)" in str(error.value)


def test_tick_on_the_readme_palms_meets_the_physics():
    model = coopdyn.ControllerModel(two_palms(mu=0.5))
    assert (model.arms, model.joints, model.rows) == (2, 12, 30)
    data = coopdyn.ControllerData(model)
    inp = box_input(model)
    tau = coopdyn.controller_tick(model, data, inp)
    assert data.status == coopdyn.ControlStatus.ok
    assert data.input_problem == coopdyn.ControllerInputProblem.none
    # The least squeeze: each palm's normal force m g / (2 mu) (README, docs/control.md).
    np.testing.assert_allclose(data.contact_frame_wrenches[2], 2 * 9.81 / (2 * 0.5), rtol=1e-6)
    # A massless object in balance: G w = -F_x (docs/control.md).
    r = data.dynamics.contact_offsets
    np.testing.assert_allclose(grasp_by_hand(r) @ data.contact_wrenches, -data.external_wrench, atol=1e-9)
    # Every friction row holds, by the margins recomputed in numpy from the rows by hand.
    for i, contact in enumerate(model.contacts):
        margin = margin_by_hand(contact.friction, data.contact_frame_wrenches[:, i])
        assert margin >= -1e-9
        assert data.friction_margins[i] == pytest.approx(margin, abs=1e-9)
    # The outputs agree with their definitions: tau = tau_u + tau_c + tau_n, tau_c = J^T B z,
    # contact-frame wrenches = blkdiag(R_ci^T, R_ci^T) w_i.
    np.testing.assert_allclose(tau, data.motion_torque + data.squeeze_torque + data.posture_torque, atol=1e-12)
    np.testing.assert_array_equal(tau, data.torque)
    np.testing.assert_allclose(data.squeeze_torque, np.eye(12).T @ data.dynamics.internal_basis @ data.squeeze,
                               atol=1e-10)
    for i in range(2):
        R = data.contact_rotations[:, 3 * i:3 * i + 3]
        w = data.contact_wrenches[6 * i:6 * i + 6]
        np.testing.assert_allclose(data.contact_frame_wrenches[:, i], np.r_[R.T @ w[:3], R.T @ w[3:]], atol=1e-10)


def test_less_friction_needs_more_squeeze():
    forces = []
    for mu in (0.3, 0.5, 0.9):
        model = coopdyn.ControllerModel(two_palms(mu))
        data = coopdyn.ControllerData(model)
        coopdyn.controller_tick(model, data, box_input(model))
        assert data.status == coopdyn.ControlStatus.ok
        forces.append(data.contact_frame_wrenches[2, 0])
        assert forces[-1] == pytest.approx(9.81 / mu, rel=1e-6)
    assert forces[0] > forces[1] > forces[2]


def test_invalid_parameters_and_inputs():
    parameters = two_palms()
    contacts = parameters.contacts
    contacts[1].friction.friction_coefficient = -1.0
    parameters.contacts = contacts
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.ControllerModel(parameters)
    assert isinstance(error.value, ValueError)
    assert (error.value.parameter, error.value.arm, error.value.component) == ("friction_coefficient", 1, "contact")
    parameters = two_palms()
    parameters.posture_stiffness = np.zeros(11)
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.ControllerModel(parameters)
    assert error.value.parameter == "posture_stiffness" and error.value.arm is None

    model = coopdyn.ControllerModel(two_palms())
    model.objective.internal_weight = -1.0  # a copy: the validated model does not change
    assert model.objective.internal_weight == 1.0
    inp = coopdyn.ControllerInput(model)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        inp.inertia = np.eye(11)
    assert error.value.parameter == "inertia" and "(12, 12)" in str(error.value)
    with pytest.raises(ValueError):
        inp.inertia[0, 0] = 3.0  # read-only copy: assign the whole array
    with pytest.raises(ValueError):
        coopdyn.ControllerData(model).torque[0] = 1.0
    # A non-finite input is a status, not an exception (the per-tick path never throws).
    data = coopdyn.ControllerData(model)
    # Before any computed tick nothing is held: a bad arm input is refused with zero torque
    # (docs/control.md, "Faults"); a bad object acceleration is replaced by the last valid one.
    bad = box_input(model)
    bias = bad.bias.copy()  # the getter returns a read-only copy
    bias[3] = np.nan
    bad.bias = bias
    tau = coopdyn.controller_tick(model, data, bad)
    assert data.status == coopdyn.ControlStatus.invalid_input
    assert data.input_problem == coopdyn.ControllerInputProblem.bias_not_finite
    np.testing.assert_array_equal(tau, 0)
    bad = box_input(model)
    bad.object_acceleration = [np.nan, 0, 0, 0, 0, 0]
    tau = coopdyn.controller_tick(model, data, bad)
    assert data.status == coopdyn.ControlStatus.degraded
    assert data.input_problem == coopdyn.ControllerInputProblem.object_acceleration_not_finite
    assert data.replaced_input == coopdyn.ReplacedInput.object_acceleration
    assert np.all(np.isfinite(tau))
    # Data or input of another model.
    parameters = two_palms()
    parameters.joints = 13
    parameters.posture_stiffness = parameters.posture_damping = np.zeros(13)
    other = coopdyn.ControllerModel(parameters)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.controller_tick(model, coopdyn.ControllerData(other), inp)
    assert error.value.parameter == "data"
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.controller_tick(model, coopdyn.ControllerData(model), coopdyn.ControllerInput(other))
    assert error.value.parameter == "input"


def test_a_contact_facing_the_wrong_way_is_refused_by_name():
    """A palm's z flipped outward, or turned tangential, is refused naming the contact (z . r >= 0,
    docs/control.md, "Contact frames"); check_contact_normals = False accepts it."""
    flip = np.diag([1.0, -1.0, -1.0])  # pi about the frame's x: z -> -z
    tangential = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])  # pi/2 about x: z -> -y
    for turn, words in ((flip, "points out of the object"), (tangential, "lies along the object's surface")):
        parameters = two_palms()
        contacts = parameters.contacts
        right_frame = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], dtype=float)
        contacts[1].frame = coopdyn.Pose([0.15, 0, 0], quaternion_of(right_frame @ turn))
        parameters.contacts = contacts
        with pytest.raises(coopdyn.InvalidModel, match=words) as error:
            coopdyn.ControllerModel(parameters)
        assert (error.value.component, error.value.arm, error.value.parameter) == ("contact", 1, "frame.orientation")
        parameters.check_contact_normals = False
        assert coopdyn.ControllerModel(parameters).arms == 2


def test_joints_and_joint_names_in_errors():
    parameters = two_palms()
    parameters.posture_stiffness = parameters.posture_damping = np.zeros(13)  # a 13-joint cell, joints = 12
    with pytest.raises(coopdyn.InvalidModel, match="set joints to the arms' joint count") as error:
        coopdyn.ControllerModel(parameters)
    assert error.value.parameter == "joints"
    parameters = two_palms()
    parameters.joint_names = [f"arm_joint{j + 1}" for j in range(12)]
    limits = np.full(12, 10.0)
    limits[3] = -1.0
    parameters.torque_limits = limits
    with pytest.raises(coopdyn.InvalidModel, match=r"joint 3 \(arm_joint4\)") as error:
        coopdyn.ControllerModel(parameters)
    assert error.value.parameter == "torque_limits"
    parameters.joint_names = ["a", "b"]
    parameters.torque_limits = np.zeros(0)
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.ControllerModel(parameters)
    assert error.value.parameter == "joint_names"


def test_a_clipped_torque_is_the_status():
    """The README's palms holding 2 kg, their torques limited below what the hold needs: the tick
    that clips says torque_saturated (it was ok until this release)."""
    parameters = two_palms()
    free = coopdyn.ControllerModel(parameters)
    wanted = coopdyn.controller_tick(free, coopdyn.ControllerData(free), box_input(free))
    parameters.torque_limits = np.maximum(0.5 * np.abs(wanted), 1e-3)
    model = coopdyn.ControllerModel(parameters)
    data = coopdyn.ControllerData(model)
    tau = coopdyn.controller_tick(model, data, box_input(model))
    assert data.saturated_count > 0
    assert data.status == coopdyn.ControlStatus.torque_saturated
    assert np.all(np.abs(tau) <= parameters.torque_limits)


def test_parameters_print_compare_and_pickle():
    parameters = two_palms()
    copy = pickle.loads(pickle.dumps(parameters))
    assert copy == parameters and copy is not parameters
    assert "ControllerParameters(joints=12" in repr(parameters)
    assert "friction_coefficient=0.5" in repr(parameters)
    copy.stiffness = 2000.0 * np.eye(6)
    assert copy != parameters
    for obj in (coopdyn.ContactFriction(), coopdyn.SqueezeObjective.paper(), coopdyn.ContactQpOptions(),
                coopdyn.Pose([1, 2, 3]), parameters.contacts[0]):
        again = pickle.loads(pickle.dumps(obj))
        assert again == obj and repr(again) == repr(obj)
    assert coopdyn.SqueezeObjective.paper() != coopdyn.SqueezeObjective.least_squeeze()
    # The model built from the unpickled parameters gives the same torques.
    a, b = coopdyn.ControllerModel(parameters), coopdyn.ControllerModel(pickle.loads(pickle.dumps(parameters)))
    da, db = coopdyn.ControllerData(a), coopdyn.ControllerData(b)
    np.testing.assert_array_equal(coopdyn.controller_tick(a, da, box_input(a)), coopdyn.controller_tick(b, db, box_input(b)))


def test_ticks_from_threads_agree():
    """controller_tick releases the GIL: ticks on separate data from several threads give the
    single-threaded torques."""
    model = coopdyn.ControllerModel(two_palms())
    inp = box_input(model)
    expected = coopdyn.controller_tick(model, coopdyn.ControllerData(model), inp)
    results = []

    def run():
        data = coopdyn.ControllerData(model)
        for _ in range(200):
            tau = coopdyn.controller_tick(model, data, inp)
        results.append(tau)

    threads = [threading.Thread(target=run) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 3
    for tau in results:
        np.testing.assert_allclose(tau, expected, rtol=1e-12, atol=1e-12)


def test_docstrings_cite_the_equations():
    assert "L(16)" in coopdyn.controller_tick.__doc__ and "E12" in coopdyn.controller_tick.__doc__
    assert "(24)" in coopdyn.grasp_matrix.__doc__
    assert "(18)" in coopdyn.udwadia_kalaba.__doc__
    assert "L(13)" in coopdyn.constraint_jacobian.__doc__


def test_a_python_loop_at_1khz_keeps_the_physics():
    """1000 ticks (1 s at 1 kHz) written in Python, the box displaced along a circle and pushed so
    that the estimate F_x changes every tick: every tick is ok, balances the massless object
    (G w = -F_x) and keeps every friction margin >= 0. (Its speed is measured by
    python/benchmarks/overhead.py, not asserted here: a loaded machine would fail a timed test.)"""
    model = coopdyn.ControllerModel(two_palms(mu=0.5))
    data = coopdyn.ControllerData(model)
    inp = box_input(model)
    base = np.array(inp.object.pose.position)
    worst_balance, worst_margin = 0.0, np.inf
    for k in range(1000):
        t = k * 1e-3
        inp.object.pose.position = base + 0.01 * np.array([np.cos(2 * np.pi * t), np.sin(2 * np.pi * t), 0.0])
        inp.object_acceleration = np.r_[0.5 * np.sin(2 * np.pi * t), 0, 0, 0, 0, 0]
        coopdyn.controller_tick(model, data, inp)
        assert data.status == coopdyn.ControlStatus.ok
        balance = grasp_by_hand(data.dynamics.contact_offsets) @ data.contact_wrenches + data.external_wrench
        worst_balance = max(worst_balance, np.abs(balance).max())
        worst_margin = min(worst_margin, data.tightest_margin)
    assert worst_balance < 1e-9
    assert worst_margin > -1e-9
