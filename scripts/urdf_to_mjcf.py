#!/usr/bin/env python3
"""Writes a serial arm's URDF as an MJCF body tree for a scene file to <include> (docs/scenes.md).

    scripts/urdf_to_mjcf.py examples/robots/panda/panda.urdf --palm panda_palm \
        -o examples/scenes/robots/panda.xml [--prefix b_]

Why not MuJoCo's own conversion (mj_loadXML of the URDF, then mj_saveLastXML): MuJoCo 2.2.2 writes
the saved file with 6 significant digits, and it stores each link's inertia as principal moments in
a frame found by its own 3 x 3 eigen-solver, which reproduces a full URDF tensor only to about 1e-7
relative (docs/adapters.md, "Tests"). This script diagonalises each tensor itself (cyclic Jacobi to
the last bit) and writes every number with 17 significant digits, so that the MJCF's joint-space
inertia equals the URDF's (KDL's) to rounding (tests/examples/test_scenes.cpp measures it).

What it handles: the shipped robots' subset of URDF, a chain (or tree) of revolute, continuous,
prismatic and fixed joints with <origin xyz rpy>, <axis>, <limit lower upper> and <inertial>
(origin xyz rpy, mass, inertia). Visual and collision elements are dropped; the scene adds its own
contact geometry: with --palm LINK the link gets a flat square palm plate (a box geom
<prefix>LINK_geom of --palm-size x --palm-size x --palm-thickness m, on the link's +z side) and a
site <prefix>LINK_contact at the plate's outer face: the contact frame, z = the outward normal.
Every geom has contype = conaffinity = 0 (the scene's explicit <pair>s are the only contacts) and no
mass (the scene's compiler must say inertiafromgeom="false"). Every name gets --prefix in front.
Standard library only (no numpy, no MuJoCo).

Inertias are checked (docs/scenes.md, "Physically impossible inertias"): each <inertial> needs a
finite mass > 0 and a finite tensor whose principal moments are > 0 and satisfy the triangle
inequality I1 + I2 >= I3 (sorted; the two smaller moments of any body sum to at least the largest:
I1 + I2 - I3 = 2 * the second moment of mass along the third axis). A link that fails is named with
its principal moments and the failed inequality, and nothing is written (exit code 1). With
--fix-inertia a broken triangle inequality is repaired minimally: the two smaller moments are raised
by half the shortfall each, the largest and the principal axes kept (the negative second moment of
mass set to zero, the other two kept), and the change is printed. A shortfall within rounding (1e-12
of I3: a flat body's tensor after diagonalisation) is repaired that way without the flag, with a note.
"""

import argparse
import math
import sys
import xml.etree.ElementTree as ET

ROUNDING = 1e-12  # a triangle shortfall below ROUNDING * I3 is the diagonalisation's rounding


def number(x):
    """17 significant digits at most (repr is the shortest string that reads back to x)."""
    if x == 0.0:
        return "0"
    return repr(float(x))


def numbers(values):
    return " ".join(number(v) for v in values)


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def rpy_matrix(roll, pitch, yaw):
    """URDF's fixed-axis rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def quaternion(r):
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method), w >= 0."""
    trace = r[0][0] + r[1][1] + r[2][2]
    if trace > 0.0:
        s = math.sqrt(trace + 1.0) * 2.0
        q = [0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s]
    elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
        s = math.sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2.0
        q = [(r[2][1] - r[1][2]) / s, 0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s]
    elif r[1][1] > r[2][2]:
        s = math.sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2.0
        q = [(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s]
    else:
        s = math.sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2.0
        q = [(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s]
    norm = math.sqrt(sum(c * c for c in q))
    q = [c / norm for c in q]
    return q if q[0] >= 0.0 else [-c for c in q]


def jacobi_eigen(a):
    """Eigenvalues and eigenvectors (columns of V, det V = +1) of a symmetric 3 x 3 matrix:
    cyclic Jacobi rotations until the off-diagonal part vanishes to rounding, A = V diag V^T."""
    a = [row[:] for row in a]
    v = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
    for _ in range(50):
        off = sum(a[i][j] ** 2 for i in range(3) for j in range(3) if i != j)
        if off <= 1e-300 or off <= (1e-17 * sum(a[i][i] ** 2 for i in range(3))) ** 2:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if a[p][q] == 0.0:
                continue
            theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q])
            t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
            c = 1.0 / math.sqrt(t * t + 1.0)
            s = t * c
            rot = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
            rot[p][p] = c
            rot[q][q] = c
            rot[p][q] = s
            rot[q][p] = -s
            a = matmul(transpose(rot), matmul(a, rot))
            v = matmul(v, rot)
    det = (v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) - v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
           v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]))
    if det < 0.0:
        for i in range(3):
            v[i][2] = -v[i][2]
    return [a[0][0], a[1][1], a[2][2]], v


def moments_text(values):
    return ", ".join("%.6g" % v for v in values)


def balance_triangle(moments):
    """The principal moments with I1 + I2 >= I3 restored minimally: the two smaller ones raised by half
    the shortfall each (the second moment of mass along the largest moment's axis, (I1 + I2 - I3) / 2,
    from negative to zero; the other two second moments kept), the largest kept; then nudged up by
    the last bit where rounding would leave the sum short."""
    k = max(range(3), key=lambda n: moments[n])
    i, j = [n for n in range(3) if n != k]
    shortfall = moments[k] - moments[i] - moments[j]
    fixed = list(moments)
    fixed[i] += shortfall / 2.0
    fixed[j] += shortfall / 2.0
    while fixed[i] + fixed[j] < fixed[k]:
        fixed[j] = math.nextafter(fixed[j], math.inf)
    return fixed


def origin(element):
    """(xyz, R) of an <origin> child (identity when absent)."""
    node = element.find("origin") if element is not None else None
    if node is None:
        return [0.0, 0.0, 0.0], rpy_matrix(0.0, 0.0, 0.0)
    xyz = [float(c) for c in node.get("xyz", "0 0 0").split()]
    rpy = [float(c) for c in node.get("rpy", "0 0 0").split()]
    return xyz, rpy_matrix(*rpy)


class Converter:
    def __init__(self, root, args):
        self.root = root
        self.args = args
        self.links = {link.get("name"): link for link in root.findall("link")}
        self.children = {}
        for joint in root.findall("joint"):
            self.children.setdefault(joint.find("parent").get("link"), []).append(joint)
        children = {joint.find("child").get("link") for joint in root.findall("joint")}
        roots = [name for name in self.links if name not in children]
        if len(roots) != 1:
            sys.exit("urdf_to_mjcf: expected one root link, found %s" % roots)
        self.root_link = roots[0]
        self.palm_found = False
        self.errors = []    # links whose inertia is refused (all reported, nothing written)
        self.repaired = []  # links whose inertia was repaired (--fix-inertia or rounding)

    def name(self, name):
        return self.args.prefix + name

    def inertial(self, link, body):
        node = link.find("inertial")
        if node is None:
            return
        where = "link '%s'" % link.get("name")
        mass_node, tensor = node.find("mass"), node.find("inertia")
        try:
            mass = float(mass_node.get("value")) if mass_node is not None else math.nan
            get = lambda key: float(tensor.get(key, "0")) if tensor is not None else 0.0
            inertia = [[get("ixx"), get("ixy"), get("ixz")], [get("ixy"), get("iyy"), get("iyz")],
                       [get("ixz"), get("iyz"), get("izz")]]
        except (TypeError, ValueError) as error:
            self.errors.append("%s: <inertial> holds a value that is not a number (%s)" % (where, error))
            return
        if not (math.isfinite(mass) and mass > 0.0):
            self.errors.append("%s: mass %s must be finite and > 0 (a massless link has no <inertial>)" %
                               (where, mass_node.get("value") if mass_node is not None else "missing"))
            return
        if not all(math.isfinite(v) for row in inertia for v in row):
            self.errors.append("%s: the inertia tensor %s is not finite" % (where, tensor.attrib))
            return
        xyz, rotation = origin(node)
        in_link = matmul(rotation, matmul(inertia, transpose(rotation)))  # the tensor in the link frame
        moments, axes = jacobi_eigen(in_link)
        moments = self.checked_moments(where, moments)
        if moments is None:
            return
        ET.SubElement(body, "inertial", {"pos": numbers(xyz), "quat": numbers(quaternion(axes)),
                                         "mass": number(mass), "diaginertia": numbers(moments)})

    def checked_moments(self, where, moments):
        """The principal moments to write, or None (and an error) when the tensor is not physical."""
        ordered = sorted(moments)
        if ordered[0] <= 0.0:
            self.errors.append(
                "%s: physically impossible inertia: principal moments %s kg m^2 must all be > 0 (the tensor "
                "is not positive definite); --fix-inertia does not repair this: correct the URDF" %
                (where, moments_text(ordered)))
            return None
        shortfall = ordered[2] - ordered[0] - ordered[1]
        if shortfall <= 0.0:
            return moments
        fixed = balance_triangle(moments)
        change = "the two smaller raised by %.3g each to %s kg m^2, the largest kept" % (
            shortfall / 2.0, moments_text(sorted(fixed)))
        if shortfall > ROUNDING * ordered[2] and not self.args.fix_inertia:
            self.errors.append(
                "%s: physically impossible inertia: principal moments %s kg m^2 break the triangle inequality "
                "I1 + I2 >= I3 (%.6g + %.6g = %.6g < %.6g, short by %.3g; no mass distribution has these, and "
                "MuJoCo refuses them). Correct the URDF, or pass --fix-inertia for the smallest repair: %s" %
                (where, moments_text(ordered), ordered[0], ordered[1], ordered[0] + ordered[1], ordered[2],
                 shortfall, change))
            return None
        if shortfall > ROUNDING * ordered[2]:
            print("urdf_to_mjcf: %s: --fix-inertia: principal moments %s kg m^2 broke I1 + I2 >= I3 by %.3g: %s" %
                  (where, moments_text(ordered), shortfall, change))
        else:
            print("urdf_to_mjcf: note: %s: principal moments %s kg m^2 missed I1 + I2 >= I3 by %.3g, the rounding "
                  "of a flat body's tensor: the two smaller raised by half that each" %
                  (where, moments_text(ordered), shortfall))
        self.repaired.append(where)
        return fixed

    def palm(self, body, link_name):
        size, thickness = self.args.palm_size, self.args.palm_thickness
        ET.SubElement(body, "geom", {"name": self.name(link_name + "_geom"), "type": "box",
                                     "pos": numbers([0.0, 0.0, thickness / 2.0]),
                                     "size": numbers([size / 2.0, size / 2.0, thickness / 2.0]),
                                     "contype": "0", "conaffinity": "0", "mass": "0", "group": "1",
                                     "rgba": "0.3 0.3 0.3 1"})
        ET.SubElement(body, "site", {"name": self.name(link_name + "_contact"), "pos": numbers([0.0, 0.0, thickness]),
                                     "size": "0.01"})
        self.palm_found = True

    def body(self, parent, link_name, joint):
        link = self.links[link_name]
        attributes = {"name": self.name(link_name)}
        if joint is not None:
            xyz, rotation = origin(joint)
            attributes["pos"] = numbers(xyz)
            attributes["quat"] = numbers(quaternion(rotation))
        body = ET.SubElement(parent, "body", attributes)
        self.inertial(link, body)
        if joint is not None and joint.get("type") != "fixed":
            kind = joint.get("type")
            if kind not in ("revolute", "continuous", "prismatic"):
                sys.exit("urdf_to_mjcf: joint %s: type %s is not supported" % (joint.get("name"), kind))
            axis = joint.find("axis")
            element = {"name": self.name(joint.get("name")), "type": "slide" if kind == "prismatic" else "hinge",
                       "pos": "0 0 0", "axis": axis.get("xyz") if axis is not None else "1 0 0",
                       "damping": "0", "armature": "0", "frictionloss": "0"}
            limit = joint.find("limit")
            if kind != "continuous" and limit is not None and "lower" in limit.attrib:
                element["limited"] = "true"
                element["range"] = numbers([float(limit.get("lower")), float(limit.get("upper"))])
            else:
                element["limited"] = "false"
            ET.SubElement(body, "joint", element)
        if link_name == self.args.palm:
            self.palm(body, link_name)
        for child in self.children.get(link_name, []):
            self.body(body, child.find("child").get("link"), child)

    def document(self, source):
        mujoco = ET.Element("mujoco")
        mujoco.text = "\n"
        comment = ET.Comment(
            " Generated by scripts/urdf_to_mjcf.py from %s%s%s: do not edit; regenerate (docs/scenes.md). "
            "Inertials: the URDF's tensors diagonalised by the script, 17 digits. " %
            (source, " --palm " + self.args.palm if self.args.palm else "",
             " --prefix " + self.args.prefix if self.args.prefix else ""))
        mujoco.append(comment)
        self.body(mujoco, self.root_link, None)
        if self.errors:
            sys.exit("\n".join("urdf_to_mjcf: " + error for error in self.errors))
        if self.repaired:
            comment.text += "Repaired (I1 + I2 >= I3, the two smaller principal moments raised): %s. " % ", ".join(
                self.repaired)
        if self.args.palm and not self.palm_found:
            sys.exit("urdf_to_mjcf: no link named %s" % self.args.palm)
        ET.indent(mujoco, space="  ")
        return ET.tostring(mujoco, encoding="unicode") + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("urdf")
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--prefix", default="", help="put in front of every name (two copies of one robot)")
    parser.add_argument("--palm", default="", help="the link that gets the palm plate and the contact site")
    parser.add_argument("--palm-size", type=float, default=0.08, help="plate side (m), default 0.08")
    parser.add_argument("--palm-thickness", type=float, default=0.02, help="plate thickness (m), default 0.02")
    parser.add_argument("--source-name", default="", help="the URDF's path as written in the comment")
    parser.add_argument("--fix-inertia", action="store_true",
                        help="repair principal moments that break I1 + I2 >= I3 (the two smaller raised by half the "
                             "shortfall each) and print the change, instead of refusing them")
    args = parser.parse_args()
    converter = Converter(ET.parse(args.urdf).getroot(), args)
    text = converter.document(args.source_name or args.urdf)
    with open(args.output, "w", encoding="utf-8") as output:
        output.write(text)


if __name__ == "__main__":
    main()
