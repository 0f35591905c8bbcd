// The arms of the dual-arm box example: two KUKA LWR 4-like 7-joint arms on a fixed torso, facing
// each other, with flat square palms pressing on two opposite faces of a box held in front of the
// torso. Plain data and a few small functions; depends on Eigen only.
//
// World frame: x forward, y left, z up, gravity (0, 0, -9.81) m/s^2.
//
// Kinematics: the LWR 4's published standard (distal) Denavit-Hartenberg parameters,
//
//     T_{i-1,i}(q_i) = RotZ(q_i) TransZ(d_i) TransX(a_i) RotX(alpha_i),
//
// frame 0 = the arm's base (on the torso), frame i attached to link i (its origin on joint i+1's
// axis z_i), frame 7 = the flange. In q = 0 the arm stands straight up along z_0. KDL's
// Frame::DH(a, alpha, d, theta) is the same convention.
//
// Dynamics: masses, centres of mass and inertias of the public LWR 4 description of Centro
// E. Piaggio (University of Pisa), repository CentroEPiaggio/kuka-lwr, file
// lwr_description/model/kuka_lwr.urdf.xacro (commit 464d48c000bb0cf79ebf2073d73e42dfb6a7b17b),
// with its inertia macro `cuboid_inertia_def` of lwr_description/model/utils.xacro:
// ixx = m (height^2 + length^2) / 12, iyy = m (width^2 + length^2) / 12,
// izz = m (width^2 + height^2) / 12 (sic; taken as the source defines it), about the centre of
// mass, axes of the URDF link frame. Those are nominal (box-shaped) values, not identified ones:
// links 1-5 are 2.35 kg cuboids 0.12 x 0.06 x 0.26 m (link 5: 0.248 m), link 6 a 1.1 kg cube of
// 0.125 m, link 7 (the flange) a 0.25 kg cube of 0.1 m. The base link (2 kg) is fixed and does
// not enter the dynamics.
//
// How the numbers were moved into the DH frames: the URDF's link k moves with joint k, its frame
// sits on joint k's axis and at q = 0 all URDF link frames are parallel to the base, stacked along
// z at heights 0.11, 0.3105, 0.5105, 0.7105, 0.9105, 1.1005, 1.1785 m. The URDF joint axes are
// z, -y, z, +y, z, -y, z, which are exactly the DH axes z_0..z_6 at q = 0 (so q_DH = q_URDF,
// same zero and same sense). DH frame i is also rigidly attached to link k = i, at q = 0 with its
// origin at height 0.3105, 0.3105, 0.7105, 0.7105, 1.1005, 1.1005, 1.1785 m and its rotation
// R_i = RotX(pi/2), I, RotX(-pi/2), I, RotX(pi/2), I, I relative to the base. Hence, for every link,
// com_DH = R_i^T (com_URDF + (0, 0, h_k) - o_i) and I_DH = R_i^T I_URDF R_i (evaluated at q = 0,
// valid for all q because both frames are fixed in the same link). The rotations about x by
// +-pi/2 swap the y and z inertia entries of links 1-5, and the products of inertia stay zero.
//
// The palm (this example's choice, not part of the source): a 0.3 kg aluminium-like square plate,
// 8 x 8 cm, 2 cm thick, bolted centred on the flange; its contact surface lies 0.02 m beyond the
// flange along z_7 and its outward normal is +z_7. It is rigidly fixed to link 7, so the
// simulation and the models lump it into link 7 (arm_links()).
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstddef>

namespace box_example {

inline constexpr double lwr4_pi = 3.14159265358979323846;

/// One link of the LWR 4 in the standard DH convention above.
struct Lwr4Link {
    double d = 0.0;      ///< DH offset along z_{i-1} [m]
    double alpha = 0.0;  ///< DH twist about x_i [rad]
    double a = 0.0;      ///< DH length along x_i [m]
    double mass = 0.0;   ///< [kg]
    Eigen::Vector3d com = Eigen::Vector3d::Zero();        ///< centre of mass in DH frame i [m]
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();    ///< about the com, axes of frame i [kg m^2]
};

/// The diagonal inertia matrix diag(ixx, iyy, izz) [kg m^2].
inline Eigen::Matrix3d lwr4_diag_inertia(double ixx, double iyy, double izz)
{
    return Eigen::Vector3d(ixx, iyy, izz).asDiagonal();
}

/// The seven links of the bare LWR 4 (link 7 = the flange only, without the palm): DH
/// parameters and the CentroEPiaggio inertial values moved into the DH frames (see the top of
/// this file).
inline std::array<Lwr4Link, 7> lwr4_links()
{
    constexpr double pi = lwr4_pi;
    // The source's cuboid inertia entries (kg m^2), about the com in URDF link axes.
    constexpr double m_link = 2.35;  // links 1-5
    const double big = m_link * (0.26 * 0.26 + 0.12 * 0.12) / 12.0;      // URDF ixx, links 1-4
    const double small = m_link * (0.06 * 0.06 + 0.12 * 0.12) / 12.0;    // URDF iyy, links 1-5
    const double mid = m_link * (0.06 * 0.06 + 0.26 * 0.26) / 12.0;      // URDF izz, links 1-4
    const double big5 = m_link * (0.248 * 0.248 + 0.12 * 0.12) / 12.0;   // URDF ixx, link 5
    const double mid5 = m_link * (0.06 * 0.06 + 0.248 * 0.248) / 12.0;   // URDF izz, link 5
    const double cube6 = 1.1 * (0.125 * 0.125 + 0.125 * 0.125) / 12.0;   // link 6, all axes
    const double cube7 = 0.25 * (0.1 * 0.1 + 0.1 * 0.1) / 12.0;          // link 7, all axes

    std::array<Lwr4Link, 7> links;
    // {d, alpha, a, mass, com (DH frame i), inertia about the com (DH axes)}. Links 1, 3, 5:
    // R_i = RotX(+-pi/2) swaps the URDF's y and z entries; links 2, 4, 6, 7: R_i = I.
    links[0] = {0.3105, pi / 2, 0.0, m_link, {0.0, -0.0705, 0.06}, lwr4_diag_inertia(big, mid, small)};
    links[1] = {0.0, -pi / 2, 0.0, m_link, {0.0, 0.06, 0.07}, lwr4_diag_inertia(big, small, mid)};
    links[2] = {0.40, -pi / 2, 0.0, m_link, {0.0, 0.07, 0.06}, lwr4_diag_inertia(big, mid, small)};
    links[3] = {0.0, pi / 2, 0.0, m_link, {0.0, -0.06, 0.07}, lwr4_diag_inertia(big, small, mid)};
    links[4] = {0.39, pi / 2, 0.0, m_link, {0.0, -0.066, 0.0}, lwr4_diag_inertia(big5, mid5, small)};
    links[5] = {0.0, -pi / 2, 0.0, 1.1, {0.0, 0.0, 0.0625}, lwr4_diag_inertia(cube6, cube6, cube6)};
    links[6] = {0.078, 0.0, 0.0, 0.25, {0.0, 0.0, 0.0}, lwr4_diag_inertia(cube7, cube7, cube7)};
    return links;
}

/// Joint torque limits [N m] (LWR 4 data sheet; also the source's effort limits).
inline Eigen::Matrix<double, 7, 1> torque_limits()
{
    return (Eigen::Matrix<double, 7, 1>() << 176.0, 176.0, 100.0, 100.0, 100.0, 38.0, 38.0).finished();
}

/// Symmetric joint position limits [rad]: +-170 deg for joints 1, 3, 5, 7 and +-120 deg for
/// joints 2, 4, 6 (the source's limits; the simulation does not enforce them).
inline Eigen::Matrix<double, 7, 1> joint_position_limits()
{
    constexpr double deg = lwr4_pi / 180.0;
    return (Eigen::Matrix<double, 7, 1>() << 170.0, 120.0, 170.0, 120.0, 170.0, 120.0, 170.0).finished() *
           deg;
}

/// The palm: a uniform square plate fixed centred on the flange (frame 7).
struct Palm {
    double mass = 0.3;                                      ///< [kg], this example's choice
    Eigen::Vector3d half_size{0.04, 0.04, 0.01};            ///< plate half extents in frame 7 [m]
    Eigen::Vector3d centre{0.0, 0.0, 0.01};                 ///< plate centre = its com, frame 7 [m]
    Eigen::Vector3d contact_point{0.0, 0.0, 0.02};          ///< centre of the contact surface, frame 7
    Eigen::Vector3d normal{0.0, 0.0, 1.0};                  ///< outward normal (into the box), frame 7

    /// Inertia about the plate's com, axes of frame 7 [kg m^2].
    Eigen::Matrix3d inertia() const
    {
        const Eigen::Vector3d s = 2.0 * half_size;
        return lwr4_diag_inertia(mass * (s.y() * s.y() + s.z() * s.z()) / 12.0,
                                 mass * (s.x() * s.x() + s.z() * s.z()) / 12.0,
                                 mass * (s.x() * s.x() + s.y() * s.y()) / 12.0);
    }
};

inline Palm palm() { return Palm{}; }

/// The arm as simulated: lwr4_links() with the palm lumped into link 7 (combined mass, com and
/// inertia about the combined com by the parallel-axis theorem).
inline std::array<Lwr4Link, 7> arm_links()
{
    std::array<Lwr4Link, 7> links = lwr4_links();
    const Palm p = palm();
    Lwr4Link& l7 = links[6];
    const double m = l7.mass + p.mass;
    const Eigen::Vector3d c = (l7.mass * l7.com + p.mass * p.centre) / m;
    const auto shift = [](double mass, const Eigen::Vector3d& r) -> Eigen::Matrix3d {
        return mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    };
    l7.inertia = l7.inertia + shift(l7.mass, l7.com - c) + p.inertia() + shift(p.mass, p.centre - c);
    l7.com = c;
    l7.mass = m;
    return links;
}

/// The homogeneous DH transform T_{i-1,i}(q) of one link.
inline Eigen::Isometry3d dh_transform(const Lwr4Link& link, double q)
{
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.rotate(Eigen::AngleAxisd(q, Eigen::Vector3d::UnitZ()));
    t.translate(Eigen::Vector3d(link.a, 0.0, link.d));
    t.rotate(Eigen::AngleAxisd(link.alpha, Eigen::Vector3d::UnitX()));
    return t;
}

/// Which arm. The left arm is on the torso's +y side, the right arm on its -y side.
enum class Side { left = 0, right = 1 };

/// The box and its hold pose.
struct BoxSpec {
    Eigen::Vector3d size{0.20, 0.30, 0.40};     ///< full extents x (depth), y (between palms), z [m]
    double mass = 0.7;                          ///< [kg], uniform
    Eigen::Vector3d hold_centre{0.40, 0.0, 1.30};  ///< box centre in the hold pose, world [m]
    // Hold orientation: axis-aligned with the world (identity).
};

inline BoxSpec box_spec() { return BoxSpec{}; }

/// Pose of the box in the hold configuration (world): centre box_spec().hold_centre, axes aligned
/// with the world axes.
inline Eigen::Isometry3d box_hold_pose()
{
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translate(box_spec().hold_centre);
    return t;
}

/// Placement of an arm's base (DH frame 0) on the torso, world frame. The torso is a fixed
/// block 0.24 m deep and 0.5 m wide standing at the world origin; each arm is mounted on one of
/// its side faces at y = +-0.25 m, height 1.1 m, with its first joint axis horizontal and
/// pointing outward (a humanoid-like shoulder): left base = Trans(0, 0.25, 1.1) RotX(-pi/2)
/// (z_0 = +y, x_0 = +x, y_0 = -z), right base = Trans(0, -0.25, 1.1) RotX(+pi/2) (z_0 = -y,
/// x_0 = +x, y_0 = +z). The right base is the mirror image of the left one through the world's
/// x-z plane, so the mirror of a left configuration q is (-q1, q2, -q3, q4, -q5, q6, -q7).
inline Eigen::Isometry3d base_transform(Side side)
{
    const double s = side == Side::left ? 1.0 : -1.0;
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translate(Eigen::Vector3d(0.0, s * 0.25, 1.1));
    t.rotate(Eigen::AngleAxisd(-s * lwr4_pi / 2.0, Eigen::Vector3d::UnitX()));
    return t;
}

/// World pose of the flange (frame 7) for the joint angles q of one arm (arm_links() kinematics).
inline Eigen::Isometry3d flange_pose(Side side, const Eigen::Matrix<double, 7, 1>& q)
{
    const std::array<Lwr4Link, 7> links = arm_links();
    Eigen::Isometry3d t = base_transform(side);
    for (std::size_t i = 0; i < links.size(); ++i) {
        t = t * dh_transform(links[i], q[static_cast<Eigen::Index>(i)]);
    }
    return t;
}

/// World pose of the palm frame: origin at the palm's contact point, z = the palm's outward
/// normal (into the box), axes parallel to frame 7 (the MJCF sites left_palm / right_palm).
inline Eigen::Isometry3d palm_pose(Side side, const Eigen::Matrix<double, 7, 1>& q)
{
    return flange_pose(side, q) * Eigen::Translation3d(palm().contact_point);
}

/// The hold configuration of one arm [rad]: its palm's contact point exactly at the centre of its
/// box face (y = +-0.15 m from the box centre in box_hold_pose()), the palm normal into the box
/// (-y for the left arm, +y for the right arm), and the palm frame's x axis along world -x
/// (left palm frame: x = -x_w, y = -z_w, z = -y_w; right: x = -x_w, y = +z_w, z = +y_w).
///
/// Found once by a numerical IK (damped least squares on the 6 palm pose constraints, position
/// and orientation, with a null-space gradient that keeps the joints near the middle of their
/// ranges and the elbow out, then Newton to machine precision). In degrees the left arm is
/// (-27.86, -79.39, 1.48, 92.65, -10.42, -8.09, -17.26): joint usage at most 77 % of the range
/// (joint 4), elbow bent 93 deg and out (elbow at (0.35, +0.63, 1.28) m), smallest singular value
/// of the 6 x 7 palm Jacobian 0.22. The right arm is its mirror image. Gravity torques plus a
/// 100 N squeeze (and half the box's weight) per palm use at most 22 % of the torque limits (see
/// test_lwr4_kdl).
///
/// The hold centre (0.40, 0, 1.30) m was chosen for the experiments' workspace: box centre from
/// 0.15 m above to 0.55 m below the hold, and on the circle y = -0.12 + 0.12 cos t,
/// z = 1.30 + 0.12 sin t. Following the box from q_hold with the same IK, both arms keep the
/// smallest singular value of the palm Jacobian >= 0.13 (left arm at y = -0.24 m; right arm 0.20
/// at 0.55 m below) and the joints within 96 % of their limits (left joint 2 when the box is at
/// y = -0.24 m, a geometric bound: about 95 % for any hold centre on y = 0; right joint 4 95 %),
/// with every link origin at x > 0.15 m or |y| > 0.3 m (clear of the torso). The former centre
/// (0.55, 0, 1.0) stretched the arms into the elbow singularity about 0.37 m below the hold.
inline Eigen::Matrix<double, 7, 1> q_hold(Side side)
{
    Eigen::Matrix<double, 7, 1> q;
    q << -0.48620957795559466, -1.3856885482973313, 0.025900310789281636, 1.6171069490619145,
        -0.18193273702700685, -0.14115746062910167, -0.30127923909952653;
    if (side == Side::right) {
        for (Eigen::Index i = 0; i < 7; i += 2) {
            q[i] = -q[i];  // joints 1, 3, 5, 7
        }
    }
    return q;
}

/// The hold configuration of both arms, left (MuJoCo qpos 0-6) then right (qpos 7-13).
inline Eigen::Matrix<double, 14, 1> q_hold()
{
    Eigen::Matrix<double, 14, 1> q;
    q << q_hold(Side::left), q_hold(Side::right);
    return q;
}

}  // namespace box_example
