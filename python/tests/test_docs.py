"""The Python examples of docs/python.md run as printed (in order, in one namespace), and what
they say they print holds."""

import pathlib
import re

import numpy as np
import pytest

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def test_docs_python_examples_run():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    assert len(blocks) >= 4
    namespace = {}
    exec(compile(blocks[0], str(DOC), "exec"), namespace)
    coopdyn = namespace["coopdyn"]
    # The first example: status ok, 19.62 N per palm (m g / (2 mu)).
    assert namespace["data"].status == coopdyn.ControlStatus.ok
    np.testing.assert_allclose(namespace["data"].contact_frame_wrenches[2], 19.62, rtol=1e-6)
    import contextlib
    import io
    printed = io.StringIO()
    # The experiments' and the MuJoCo adapter's examples need the extensions built with MuJoCo.
    built = {"experiments.box": coopdyn.experiments._experiments is not None,
             "MujocoArms": hasattr(coopdyn, "MujocoArms") and coopdyn.experiments._experiments is not None}
    ran = []
    with contextlib.redirect_stdout(printed):
        for block in blocks[1:]:
            needs = [name for name in built if name in block]
            if all(built[name] for name in needs):
                exec(compile(block, str(DOC), "exec"), namespace)
                ran += needs
    assert namespace["hold_box"](0.5) == pytest.approx(19.62, rel=1e-6)
    assert namespace["hold_box"](0.3) == pytest.approx(9.81 / 0.3, rel=1e-6)
    # The quick start: 10 N / 21.75 kg.
    model = namespace["model"]
    data = coopdyn.Data(model)
    coopdyn.interaction_dynamics(model, data, coopdyn.RigidBodyState(), namespace["setpoints"],
                                 namespace["disturbances"])
    np.testing.assert_allclose(data.object_acceleration()[0], 10.0 / 21.75, rtol=1e-12)
    assert namespace["simulator"].time == pytest.approx(1.5)  # 1000 steps, then run(500)
    assert namespace["log"]["wrenches"].shape == (500, 18)
    # The exceptions example raised and printed the fields as its comment says.
    assert "contact friction_coefficient 1 must be positive and finite, got -1" in printed.getvalue()
    # The faults example: a dropout after a measured tick is predicted from the twist.
    assert "ControlStatus.degraded ReplacedInput.object_state_from_twist" in printed.getvalue()
    if "experiments.box" in ran:  # the sweep: the smaller mu, the harder the squeeze (docs/control.md)
        peaks = re.findall(r"mu (\S+): peak squeeze (\S+) N, 2000 ticks", printed.getvalue())
        assert [mu for mu, _ in peaks] == ["0.2", "0.5", "1.0"]
        assert float(peaks[0][1]) > 1.5 * float(peaks[2][1]) and float(peaks[2][1]) >= 70.0
    if "MujocoArms" in ran:  # 100 ticks of the adapter's loop
        assert "ControlStatus.ok 0.1" in printed.getvalue()


def test_docs_contact_frames_match_the_readme_matrices():
    """The quaternions of docs/python.md's first example are the README's frame matrices."""
    import coopdyn
    left = np.array([[0, 0, 1], [0, -1, 0], [1, 0, 0]], dtype=float)
    right = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], dtype=float)
    np.testing.assert_allclose(coopdyn.Pose([0, 0, 0], np.sqrt(0.5) * np.array([1, 0, 1, 0])).rotation(), left, atol=1e-15)
    np.testing.assert_allclose(coopdyn.Pose([0, 0, 0], np.sqrt(0.5) * np.array([0, -1, 0, 1])).rotation(), right, atol=1e-15)


def test_readme_python_example_runs():
    readme = DOC.parents[1] / "README.md"
    blocks = re.findall(r"```python\n(.*?)```", readme.read_text(), flags=re.S)
    assert len(blocks) == 2
    namespace = {}
    exec(compile(blocks[0], str(readme), "exec"), namespace)
    coopdyn = namespace["coopdyn"]
    assert namespace["result"].status == coopdyn.QpStatus.solved
    np.testing.assert_allclose(namespace["result"].x, [1.0, -1.0], atol=1e-12)
    assert namespace["G"].shape == (6, 12)
    if coopdyn.experiments._experiments is None:
        pytest.skip("coopdyn built without its experiments (MuJoCo, nlohmann-json)")
    # The sweep, then the beam: its log's columns and the x experiment's identified parameters.
    exec(compile(blocks[1], str(readme), "exec"), namespace)
    assert "meas_fx" in namespace["log"] and set(namespace["summary"]["axis"]) == {"x"}


def test_the_friction_sweep_example(tmp_path):
    """examples/python/sweep_friction.py: m g / (2 mu) per palm over the sweep, margins >= 0, a plot."""
    import importlib.util
    pytest.importorskip("matplotlib")
    path = DOC.parents[1] / "examples" / "python" / "sweep_friction.py"
    spec = importlib.util.spec_from_file_location("sweep_friction", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    forces, margins = module.main(["--output", str(tmp_path)])
    mus = np.linspace(0.2, 1.0, 9)
    for i, m in enumerate((0.5, 2.0, 4.0)):
        np.testing.assert_allclose(forces[i], m * 9.81 / (2 * mus), rtol=1e-6)
    assert np.all(margins > -1e-9)
    assert (tmp_path / "sweep_friction.png").stat().st_size > 10000
