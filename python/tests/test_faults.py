"""The controller's fault handling from Python (docs/control.md, "Faults: dropout, safe hold, slip,
torque limits"; docs/python.md): a motion-capture dropout is predicted (degraded) and recovers, a
dropout past the limit holds with h + J^T w of the last computed tick, torque limits clamp, a moved
contact is reported as slip by the distance it was moved. References: the undisturbed tick, numpy
formulas of the documented torques, np.clip, and the displacement the test applies."""

import pickle

import numpy as np
import pytest

import coopdyn
from test_controller import box_input, two_palms


def contact_frames_in_world(parameters, inp):
    """Each contact frame in {w} from the object's measured pose (identity orientation here)."""
    assert np.allclose(inp.object.pose.orientation, [0, 0, 0, 1])
    positions = np.column_stack([inp.object.pose.position + c.frame.position for c in parameters.contacts])
    orientations = np.column_stack([c.frame.orientation for c in parameters.contacts])
    return positions, orientations


def test_a_dropout_is_predicted_then_measured_again():
    parameters = two_palms()
    model = coopdyn.ControllerModel(parameters)
    data = coopdyn.ControllerData(model)
    inp = box_input(model)
    undisturbed = coopdyn.controller_tick(model, data, inp)
    assert data.status == coopdyn.ControlStatus.ok
    measured = inp.object.pose.position.copy()
    for tick in range(10):
        inp.object.pose.position = [np.nan, 0.0, 0.0]
        tau = coopdyn.controller_tick(model, data, inp)
        assert data.status == coopdyn.ControlStatus.degraded
        assert data.replaced_input == coopdyn.ReplacedInput.object_state_from_twist
        assert data.prediction_age == pytest.approx(0.001 * (tick + 1))
        # At rest the prediction is the last measurement, so the torque is the undisturbed one.
        np.testing.assert_allclose(data.object.pose.position, measured, rtol=0, atol=1e-15)
        np.testing.assert_allclose(tau, undisturbed, rtol=1e-12, atol=1e-12)
    inp.object.pose.position = measured
    coopdyn.controller_tick(model, data, inp)
    assert data.status == coopdyn.ControlStatus.ok
    assert data.replaced_input == coopdyn.ReplacedInput.none
    inp.object_stale = True  # the caller's flag replaces a finite measurement too
    coopdyn.controller_tick(model, data, inp)
    assert data.status == coopdyn.ControlStatus.degraded


def test_a_dropout_past_the_limit_holds_with_the_last_wrenches():
    parameters = two_palms()
    parameters.faults.prediction_limit = 0.005
    model = coopdyn.ControllerModel(parameters)
    data = coopdyn.ControllerData(model)
    inp = box_input(model)
    coopdyn.controller_tick(model, data, inp)
    held = data.contact_wrenches.copy()
    inp.object.pose.position = [np.nan, 0.0, 0.0]
    statuses = []
    for _ in range(10):
        tau = coopdyn.controller_tick(model, data, inp)
        statuses.append(data.status)
    assert statuses[:5] == [coopdyn.ControlStatus.degraded] * 5
    assert statuses[-1] == coopdyn.ControlStatus.safe_hold
    # The documented safe-hold torque: h + J^T w with the wrenches of the last computed tick (at
    # rest, those of the measured tick), never zero.
    expected = inp.bias + inp.jacobian.T @ held
    np.testing.assert_allclose(tau, expected, rtol=1e-12, atol=1e-12)
    assert np.linalg.norm(tau) > 1.0


def test_torque_limits_clamp_and_report():
    parameters = two_palms()
    parameters.torque_limits = np.full(12, 5.0)
    model = coopdyn.ControllerModel(parameters)
    assert model.has_torque_limits and not model.has_torque_rate_limits
    data = coopdyn.ControllerData(model)
    tau = coopdyn.controller_tick(model, data, box_input(model))
    requested = data.requested_torque
    assert np.max(np.abs(requested)) > 5.0, "the test needs a limit that binds"
    np.testing.assert_array_equal(tau, np.clip(requested, -5.0, 5.0))
    np.testing.assert_array_equal(data.saturated_joints, np.abs(requested) > 5.0)
    assert data.saturated_count == int(np.sum(np.abs(requested) > 5.0))
    assert data.saturated_joints.dtype == bool and not data.saturated_joints.flags.writeable


def test_a_moved_contact_is_reported_as_slip():
    parameters = two_palms()
    model = coopdyn.ControllerModel(parameters)
    data = coopdyn.ControllerData(model)
    inp = box_input(model)
    positions, orientations = contact_frames_in_world(parameters, inp)
    inp.contact_positions = positions
    inp.contact_orientations = orientations
    inp.contact_poses_filled = True
    coopdyn.controller_tick(model, data, inp)
    assert data.slip_measured
    np.testing.assert_allclose(data.slip_distance, 0.0, atol=1e-12)
    assert data.slipping_contacts == 0
    moved = positions.copy()
    moved[:, 0] += [0.012, 0.0, -0.005]  # 13 mm
    inp.contact_positions = moved
    coopdyn.controller_tick(model, data, inp)
    np.testing.assert_allclose(data.slip_distance, [0.013, 0.0], atol=1e-12)
    np.testing.assert_allclose(data.slip_displacement[:, 0], [0.012, 0.0, -0.005], atol=1e-12)
    np.testing.assert_array_equal(data.slipping, [True, False])
    assert data.slipping_contacts == 1


def test_fault_parameters_validate_print_compare_and_pickle():
    parameters = two_palms()
    parameters.torque_limits = np.full(11, 5.0)
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.ControllerModel(parameters)
    assert error.value.parameter == "torque_limits"
    parameters.torque_limits = np.full(12, 5.0)
    parameters.faults.slip_squeeze_factor = 0.5
    with pytest.raises(coopdyn.InvalidModel) as error:
        coopdyn.ControllerModel(parameters)
    assert error.value.parameter == "faults.slip_squeeze_factor"
    parameters.faults.slip_squeeze_factor = 2.0
    copy = pickle.loads(pickle.dumps(parameters))
    assert copy == parameters
    assert copy.faults.slip_squeeze_factor == 2.0
    np.testing.assert_array_equal(copy.torque_limits, np.full(12, 5.0))
    assert "slip_squeeze_factor=2.0" in repr(parameters)
    copy.faults.prediction_limit = 0.2
    assert copy != parameters
    assert coopdyn.ControlStatus.safe_hold.name == "safe_hold"
    assert coopdyn.ControllerInputProblem.object_stale.name == "object_stale"


def test_statuses_read_from_python_are_copies():
    """A status kept from one tick does not change with the next (pybind11's def_readonly would
    return a reference into the data)."""
    model = coopdyn.ControllerModel(two_palms())
    data = coopdyn.ControllerData(model)
    inp = box_input(model)
    coopdyn.controller_tick(model, data, inp)
    first, first_qp, first_replaced = data.status, data.qp_status, data.replaced_input
    inp.object.pose.position = [np.nan, 0.0, 0.0]
    coopdyn.controller_tick(model, data, inp)
    assert data.status == coopdyn.ControlStatus.degraded
    assert first == coopdyn.ControlStatus.ok
    assert first_replaced == coopdyn.ReplacedInput.none
    assert first_qp == coopdyn.QpStatus.solved
