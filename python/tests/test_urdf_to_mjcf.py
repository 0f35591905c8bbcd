"""scripts/urdf_to_mjcf.py's inertia checks (docs/scenes.md, "Physically impossible inertias"): a link
whose principal moments break I1 + I2 >= I3 is refused by name, --fix-inertia repairs it minimally
(the two smaller moments raised by half the shortfall each) into what MuJoCo accepts, good inertias
are written unchanged (the shipped robots' trees byte for byte), and masses or tensors no repair
can make physical are refused even with the flag."""

import pathlib
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = SOURCE / "scripts" / "urdf_to_mjcf.py"

# Link "bad": principal moments 0.0017929, 0.0032071, 0.008 (the tensor below, turned by the
# inertial's rpy): 0.005 < 0.008, short by 0.003. Link "good" a physical tensor, turned as well.
URDF = """<robot name="two_links">
  <link name="base"/>
  <link name="good"><inertial><origin xyz="0 0 0.1" rpy="0.3 0 0"/><mass value="1.5"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/></inertial></link>
  <link name="bad"><inertial><origin xyz="0.1 0 0" rpy="0 0.4 0.2"/><mass value="{mass}"/>
    <inertia ixx="{ixx}" ixy="0.0005" ixz="0" iyy="0.003" iyz="0" izz="0.008"/></inertial></link>
  <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="good"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1"/></joint>
  <joint name="j2" type="revolute"><parent link="good"/><child link="bad"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1"/></joint>
  <joint name="j3" type="fixed"><parent link="bad"/><child link="tip"/><origin xyz="0.2 0 0"/></joint>
</robot>
"""


def convert(tmp_path, *flags, mass="1.2", ixx="0.002"):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(URDF.format(mass=mass, ixx=ixx))
    output = tmp_path / "arm.xml"
    run = subprocess.run([sys.executable, str(SCRIPT), str(urdf), "-o", str(output), "--palm", "tip", *flags],
                         capture_output=True, text=True)
    return run, output


def moments(output, body):
    # Without the header comment: it quotes the command line's "--" options, which expat refuses in a
    # comment (MuJoCo's parser takes them).
    text = re.sub(r"<!--.*?-->", "", output.read_text(), flags=re.S)
    inertial = ET.fromstring(text).find(".//body[@name='%s']/inertial" % body)
    return sorted(float(v) for v in inertial.get("diaginertia").split())


def test_a_broken_triangle_inequality_is_refused_naming_the_link(tmp_path):
    run, output = convert(tmp_path)
    assert run.returncode == 1 and not output.exists()
    assert "link 'bad'" in run.stderr and "link 'good'" not in run.stderr
    assert "I1 + I2 >= I3" in run.stderr and "0.00179289, 0.00320711, 0.008 kg m^2" in run.stderr
    assert "short by 0.003" in run.stderr and "--fix-inertia" in run.stderr


def test_fix_inertia_raises_the_two_smaller_moments_and_keeps_the_rest(tmp_path):
    run, output = convert(tmp_path, "--fix-inertia")
    assert run.returncode == 0, run.stderr
    assert "link 'bad'" in run.stdout and "0.00329289, 0.00470711, 0.008" in run.stdout and "good" not in run.stdout
    i1, i2, i3 = moments(output, "bad")
    assert i1 + i2 >= i3 and i3 == pytest.approx(0.008, rel=1e-14)
    assert i1 - 0.0017928932188134524 == pytest.approx(0.0015, rel=1e-12)
    assert i2 - 0.0032071067811865476 == pytest.approx(0.0015, rel=1e-12)
    assert moments(output, "good") == pytest.approx([0.01, 0.02, 0.025], rel=1e-14)


def test_mujoco_accepts_the_repaired_tree(tmp_path):
    coopdyn = pytest.importorskip("coopdyn")
    if not hasattr(coopdyn, "MujocoArms"):
        pytest.skip("coopdyn built without MuJoCo")
    run, _ = convert(tmp_path, "--fix-inertia")
    assert run.returncode == 0, run.stderr
    scene = tmp_path / "scene.xml"  # MuJoCo's own check (A + B >= C, no balanceinertia) on the result
    scene.write_text('<mujoco><compiler inertiafromgeom="false"/><worldbody><include file="arm.xml"/>'
                     "</worldbody></mujoco>")
    assert coopdyn.MujocoArms(str(scene), ["j1", "j2"], ["tip_contact"]).joints == 2


@pytest.mark.parametrize("robot, flags", [("panda", []), ("panda", ["--fix-inertia"]), ("ur5e", ["--fix-inertia"])])
def test_good_inertias_are_written_unchanged(tmp_path, robot, flags):
    urdf = "examples/robots/%s/%s.urdf" % (robot, robot)
    output = tmp_path / "robot.xml"
    run = subprocess.run([sys.executable, str(SCRIPT), urdf, "--palm", robot + "_palm", "-o", str(output),
                          "--source-name", urdf, *flags], cwd=SOURCE, capture_output=True, text=True)
    assert run.returncode == 0 and run.stdout == "" and run.stderr == ""
    assert output.read_bytes() == (SOURCE / "examples" / "scenes" / "robots" / (robot + ".xml")).read_bytes()


@pytest.mark.parametrize("mass, ixx, says", [("0", "0.002", "mass 0 must be finite and > 0"),
                                            ("1.2", "nan", "is not finite"),
                                            ("1.2", "-0.004", "must all be > 0")])
def test_what_no_repair_makes_physical_is_refused_even_with_the_flag(tmp_path, mass, ixx, says):
    run, output = convert(tmp_path, "--fix-inertia", mass=mass, ixx=ixx)
    assert run.returncode == 1 and not output.exists()
    assert "link 'bad'" in run.stderr and says in run.stderr
