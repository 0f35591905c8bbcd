"""coopdyn.experiments against the programs (docs/python.md, "The experiments"): the same scenario,
seed and duration run by dual_arm_box / two_arm_beam write CSV files whose every cell the function's
columns reproduce at the CSV's printed precision (10 significant digits). Short runs (1 to 1.5 s of
simulated time; the programs' least --duration is 1 s)."""

import csv
import math
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import coopdyn

experiments = coopdyn.experiments
pytestmark = pytest.mark.skipif(experiments._experiments is None,
                                reason="coopdyn built without its experiments (MuJoCo, nlohmann-json)")

SOURCE = pathlib.Path(__file__).resolve().parents[2]


def program(name, folder):
    """The program built next to this module (build/<preset>/examples/<folder>/<name>), or $COOPDYN_<NAME>."""
    given = os.environ.get("COOPDYN_" + name.upper())
    path = pathlib.Path(given) if given else (pathlib.Path(coopdyn.__file__).resolve().parents[2] / "examples" /
                                              folder / name)
    if not path.is_file():
        pytest.fail(f"{path} not built (build the target {name}, or set COOPDYN_{name.upper()})")
    return str(path)


def read_csv(path):
    with open(path, newline="") as file:
        rows = list(csv.reader(file))
    return rows[0], rows[1:]


def printed(value, nan="nan"):
    """A cell as examples/common/csv_table.hpp's CsvWriter prints it: %.10g (std::to_chars general, 10)."""
    if isinstance(value, str):
        return value
    if math.isnan(value):
        return nan
    return format(float(value), ".10g")


def assert_columns_match_csv(columns, path, nan="nan"):
    """Every cell; `nan`: how the file spells a missing number ("" for CsvWriter::optional's)."""
    header, rows = read_csv(path)
    assert list(columns) == header
    for name in header:
        assert len(columns[name]) == len(rows), name
        cells = [printed(v, nan) for v in columns[name].tolist()]
        expected = [row[header.index(name)] for row in rows]
        assert cells == expected, name


def run_box_program(tmp_path, scenario_file, plant, duration):
    subprocess.run([program("dual_arm_box", "box"), "--scenario", str(scenario_file), "--plant", plant,
                    "--duration", str(duration), "--seed", "3", "--no-plots", "--quiet", "--no-minimum-squeeze", "--output",
                    str(tmp_path)], check=True, capture_output=True)


@pytest.mark.parametrize("plant", ["mujoco", "rigid"])
def test_box_matches_the_program(tmp_path, plant):
    shipped = SOURCE / "examples" / "box" / "scenarios" / "push.json"
    run_box_program(tmp_path, shipped, plant, 1.5)
    log, summary = experiments.box("push", plant=plant, duration=1.5, seed=3)
    assert_columns_match_csv(log, tmp_path / f"push_{plant}.csv")
    assert log["time"].shape == (1500,) and log["time"].dtype == np.float64
    assert np.abs(log["person_fz"]).max() > 10.0  # the person's push has begun: the seed counts
    assert summary["experiment"] == "push" and summary["plant"] == plant
    assert summary["simulated_seconds"] == pytest.approx(1.5)
    assert not summary["dropped"]
    # The summary's numbers are the log's (box_report.hpp's summarise over the same ticks).
    assert summary["max_slip"] == max(log["left_slip"].max(), log["right_slip"].max())
    assert summary["peak_normal_measured"] == max(log["left_meas_fz"].max(), log["right_meas_fz"].max())
    assert summary["minimum_squeeze"] is None


def test_box_scene_scenario_matches_the_program(tmp_path):
    shipped = SOURCE / "examples" / "box" / "scenarios" / "ur5e_panda" / "hold.json"
    run_box_program(tmp_path, shipped, "rigid", 1.0)
    log, summary = experiments.box("hold", plant="rigid", duration=1.0, seed=3, scene="ur5e_panda")
    assert_columns_match_csv(log, tmp_path / "hold_rigid.csv")
    # Named as a path below the shipped folder, the same run.
    again, _ = experiments.box("ur5e_panda/hold", plant="rigid", duration=1.0, seed=3, log_every=100)
    np.testing.assert_array_equal(again["tau_u_1"], log["tau_u_1"][::100])
    assert summary["plant"] == "rigid"


def test_box_scenario_dir_and_file(tmp_path):
    shutil.copy(SOURCE / "examples" / "box" / "scenarios" / "hold.json", tmp_path / "hold.json")
    by_dir, _ = experiments.box("hold", plant="rigid", duration=0.2, scenario_dir=tmp_path)
    by_file, _ = experiments.box(tmp_path / "hold.json", plant="rigid", duration=0.2)
    for name in ("time", "z", "left_pred_fz", "status"):
        np.testing.assert_array_equal(by_dir[name], by_file[name])
    assert by_dir["status"].dtype.kind == "U" and by_dir["status"][0] == "ok"


def test_box_errors(tmp_path):
    with pytest.raises(ValueError, match="plant"):
        experiments.box("hold", plant="soft")
    with pytest.raises(OSError, match="nope.json"):
        experiments.box(tmp_path / "nope.json")
    (tmp_path / "bad.json").write_text('{"name": "bad"}')
    with pytest.raises(ValueError, match="invalid scenario"):
        experiments.box(tmp_path / "bad.json")
    with pytest.raises(ValueError, match="duration"):
        experiments.box("hold", duration=-1.0)


def test_beam_matches_the_program(tmp_path):
    subprocess.run([program("two_arm_beam", "beam"), "--experiment", "rot_z", "--duration", "1", "--runs", "2",
                    "--seed", "5", "--no-plots", "--quiet", "--output", str(tmp_path)], check=True,
                   capture_output=True)
    log, summary = experiments.beam("rot_z", duration=1.0, seed=5, runs=2)
    assert_columns_match_csv(log, tmp_path / "beam_rot_z.csv")
    table = {name: value for name, value in summary.items() if isinstance(value, np.ndarray)}
    assert_columns_match_csv(table, tmp_path / "beam_identification.csv", nan="")
    assert summary["simulated_seconds"] >= 2.0  # two runs of 1 s and their warm-up


def test_beam_errors():
    with pytest.raises(ValueError, match="experiment"):
        experiments.beam("y")
    with pytest.raises(ValueError, match="runs"):
        experiments.beam("x", runs=3)
    with pytest.raises(ValueError, match="100 samples"):
        experiments.beam("x", duration=0.05)


def test_the_box_friction_sweep_example(tmp_path):
    """examples/python/sweep_box_friction.py: a run per mu, the squeeze rises as mu falls, a plot."""
    import importlib.util
    pytest.importorskip("matplotlib")
    path = SOURCE / "examples" / "python" / "sweep_box_friction.py"
    spec = importlib.util.spec_from_file_location("sweep_box_friction", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    runs = module.main(["--duration", "2", "--mu", "0.2", "1.0", "--output", str(tmp_path)])
    assert list(runs) == [0.2, 1.0]
    # The person's push (from 1 s on) needs more squeeze under the controller's smaller mu.
    assert runs[0.2].log["left_pred_fz"].max() > runs[1.0].log["left_pred_fz"].max()
    assert (tmp_path / "sweep_box_friction_rigid.png").stat().st_size > 10000


def test_box_minimum_squeeze_is_coulombs_estimate():
    """minimum_squeeze=True: the least squeeze that holds the 0.7 kg box in MuJoCo (mu = 0.5) is at
    least Coulomb's W / (2 mu) = 6.87 N and within 15 % of it (the sag's moment on the 8 x 8 cm
    palms; test_box_plants.cpp's bounds); the rigid plant measures none."""
    coulomb = 0.7 * 9.81 / (2 * 0.5)
    _, summary = experiments.box("hold", plant="mujoco", duration=1.0, minimum_squeeze=True)
    assert summary["coulomb_estimate"] == pytest.approx(coulomb, rel=1e-3)
    assert coulomb <= summary["minimum_squeeze"] <= 1.15 * coulomb
    _, rigid = experiments.box("hold", plant="rigid", duration=0.2, minimum_squeeze=True)
    assert rigid["minimum_squeeze"] is None
