/// \file
/// \brief The Orocos KDL adapter: fills a ControllerInput (M, h, J, Jdot qdot, q, qdot of K arms,
/// docs/control.md, "Inputs") from a KDL::Tree and the names of the K contact segments, from K
/// KDL::Chains, or (coopdyn/adapters/kdl_urdf.hpp) from a URDF file. docs/adapters.md, "KDL".
///
/// Conventions, the same as the MuJoCo adapter's (docs/adapters.md, "Conventions"):
/// - the tree's root frame is the world frame {w}; gravity is (0, 0, -9.81) m/s^2 there unless set;
/// - q is ordered as the tree numbers its joints (TreeElement::q_nr, joint_names()): arm by arm for
///   the chain constructor; a joint shared by several arms (a torso) appears once;
/// - rows 6i..6i+5 of J map qdot to the twist [v; w] of contact i's ORIGIN (the tip segment's frame),
///   in {w}; those rows of Jdot qdot are that point's classical acceleration [a; alpha] at qdd = 0;
/// - M is the joint-space inertia, h = C(q, qdot) qdot + g(q).
///
/// Who computes what, and why:
/// - M and h: a composite-rigid-body algorithm and a recursive Newton-Euler pass at qdd = 0 over the
///   tree, written here on KDL's spatial algebra (Frame, Twist, Wrench, RigidBodyInertia) in world
///   coordinates, on the tree flattened once at construction. KDL 1.5 has a joint-space inertia
///   solver for chains only (ChainDynParam), which cannot hold a joint shared by two arms; M from
///   Q calls of its tree RNEA (TreeIdSolver_RNE) with unit accelerations would cost 116 us for
///   Q = 13, and that solver looks every segment up by name in std::maps (8 us per call against
///   about 2 us here; benchmarks/adapters/bench_kdl_adapter.cpp). KDL's TreeIdSolver_RNE is the
///   tests' reference for both.
/// - J, Jdot qdot: KDL's ChainJntToJacSolver and ChainJntToJacDotSolver (hybrid representation:
///   base-frame axes, reference point at the tip, whose linear part is the classical acceleration
///   of the tip's origin), one per arm on the chain from the root to its tip, scattered into the
///   tree's joint order.
///
/// read() is the per-tick call: everything it uses is sized at construction. What KDL allocates
/// inside it is measured by tests/adapters/test_kdl_adapter.cpp and written in docs/adapters.md.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/errors.hpp"

#include <kdl/chain.hpp>
#include <kdl/chainjnttojacdotsolver.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntarrayvel.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/tree.hpp>

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace coopdyn {

namespace kdl_detail {

/// One segment of the tree, flattened in an order where every parent precedes its children.
struct FlatSegment {
    KDL::Segment segment;
    int parent = -1;  ///< index in the flat list, -1 for a child of the root
    int joint = -1;   ///< q index of its joint, -1 for a fixed joint
};

/// The tree's segments below the root, parents first (depth first, in the tree's child order).
inline std::vector<FlatSegment> flatten(const KDL::Tree& tree)
{
    std::vector<FlatSegment> flat;
    std::vector<std::pair<KDL::SegmentMap::const_iterator, int>> stack;
    for (const auto& child : GetTreeElementChildren(tree.getRootSegment()->second)) {
        stack.emplace_back(child, -1);
    }
    while (!stack.empty()) {
        const auto [element, parent] = stack.back();
        stack.pop_back();
        const KDL::Segment& segment = GetTreeElementSegment(element->second);
        const bool moves = segment.getJoint().getType() != KDL::Joint::None;
        flat.push_back({segment, parent, moves ? static_cast<int>(GetTreeElementQNr(element->second)) : -1});
        const int index = static_cast<int>(flat.size()) - 1;
        for (const auto& child : GetTreeElementChildren(element->second)) {
            stack.emplace_back(child, index);
        }
    }
    return flat;
}

/// Twist per unit joint rate of a joint in {w}, reference point the world origin, from the pose of
/// its segment's base frame. KDL's Joint::twist gives it in the base frame's axes about the joint's
/// origin, with the joint's scale; the axis and origin are constant in that frame (the motion is
/// about them), so only the change of axes and of reference point remain: v_O = v_p + p x w.
inline KDL::Twist joint_twist(const KDL::Joint& joint, const KDL::Frame& base) noexcept
{
    const KDL::Twist local = base.M * joint.twist(1.0);
    return KDL::Twist(local.vel + (base * joint.JointOrigin()) * local.rot, local.rot);
}

inline KDL::Vector to_kdl(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

// KDL's JntArray and Jacobian allocate their Eigen storage inside liborocos-kdl, aligned for the
// instruction set the library was built for (Debian: 16 bytes). Code built here with wider
// vectors (-march=native: AVX, 32 bytes) would read that storage with aligned loads and fault
// (measured: a segmentation fault in the benchmark). Everything here reaches it through these
// unaligned views.
inline Eigen::Map<Eigen::VectorXd, Eigen::Unaligned> view(KDL::JntArray& a) noexcept
{
    return {a.data.data(), a.data.size()};
}
inline Eigen::Map<const Eigen::VectorXd, Eigen::Unaligned> view(const KDL::JntArray& a) noexcept
{
    return {a.data.data(), a.data.size()};
}
inline Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic>, Eigen::Unaligned> view(const KDL::Jacobian& j) noexcept
{
    return {j.data.data(), 6, j.data.cols()};
}

}  // namespace kdl_detail

/// \brief K arms (possibly sharing joints) described by KDL, read into a ControllerInput<double,
/// K, Q> each tick. Movable (the KDL tree and solvers live on the heap, so the solvers' references
/// stay valid), not copyable.
template <int ArmsAtCompileTime = Eigen::Dynamic, int JointsAtCompileTime = Eigen::Dynamic>
class KdlArms {
public:
    static constexpr int Arms = ArmsAtCompileTime;
    static constexpr int Joints = JointsAtCompileTime;
    using Input = ControllerInput<double, Arms, Joints>;

    /// The arms of \p tree whose contact frames are the segments named \p tip_segments (one per
    /// arm). Throws InvalidModel when a name is missing, when their number is not K or the tree's
    /// joint count is not Q (fixed sizes), or when the tree has no joint.
    KdlArms(const KDL::Tree& tree, const std::vector<std::string>& tip_segments,
            const Eigen::Vector3d& gravity = Eigen::Vector3d(0.0, 0.0, -9.81))
        : state_(std::make_unique<State>(tree, gravity))
    {
        build(tip_segments);
    }

    /// K independent arms: chain i is mounted at \p bases[i] in {w} (identity when \p bases is
    /// empty), its tip is contact i, and its joints are q's next block (arm by arm). The segments
    /// are renamed "arm<i>/<j>" in tree() so that equal chains can be used twice.
    explicit KdlArms(const std::vector<KDL::Chain>& chains, const std::vector<KDL::Frame>& bases = {},
                     const Eigen::Vector3d& gravity = Eigen::Vector3d(0.0, 0.0, -9.81))
        : KdlArms(tree_from_chains(chains, bases), tip_names(chains), gravity)
    {
    }

    Index arms() const noexcept { return static_cast<Index>(state_->arms.size()); }
    Index joints() const noexcept { return static_cast<Index>(state_->joint_names.size()); }
    /// The joints' names (KDL segment names of the moving segments) in q's order.
    const std::vector<std::string>& joint_names() const noexcept { return state_->joint_names; }
    const KDL::Tree& tree() const noexcept { return state_->tree; }
    /// The chain from the root to contact \p arm's segment (its joints are a subset of q's).
    const KDL::Chain& chain(Index arm) const { return state_->arms[static_cast<std::size_t>(arm)]->chain; }
    /// Pose of contact \p arm in {w} at the last read(), identity before one (its z axis is the
    /// palm's outward normal for the shipped robots, docs/adapters.md "Shipped robots").
    Eigen::Isometry3d contact_pose(Index arm) const;

    /// Fills input.inertia, bias, jacobian, jacobian_rate_qdot, positions, velocities and the
    /// contacts' poses (contact_positions, contact_orientations, contact_poses_filled) at (q,
    /// qdot); leaves the rest of \p input alone. \p input must have been built with arms() and
    /// joints(). Returns false when a KDL solver reported an error (input is then partly filled).
    bool read(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& qdot,
              Input& input) noexcept;

private:
    struct Arm {
        Arm(KDL::Chain chain_in, std::vector<int> columns_in, int segment_in)
            : chain(std::move(chain_in)),
              columns(std::move(columns_in)),
              segment(segment_in),
              jacobian_solver(chain),
              rate_solver(chain),
              joints(chain.getNrOfJoints()),
              jacobian(chain.getNrOfJoints())
        {
            rate_solver.setRepresentation(KDL::ChainJntToJacDotSolver::HYBRID);
        }
        KDL::Chain chain;          // solvers below hold a reference to it: Arm is never moved
        std::vector<int> columns;  // chain joint j is q[columns[j]]
        int segment;               // the tip's index in State::flat
        KDL::ChainJntToJacSolver jacobian_solver;
        KDL::ChainJntToJacDotSolver rate_solver;
        KDL::JntArrayVel joints;
        KDL::Jacobian jacobian;
        KDL::Twist rate;
    };
    struct State {
        State(const KDL::Tree& tree_in, const Eigen::Vector3d& gravity)
            : tree(tree_in),
              flat(kdl_detail::flatten(tree)),
              gravity_acceleration(-kdl_detail::to_kdl(gravity), KDL::Vector::Zero()),
              q(tree.getNrOfJoints()),
              qdot(tree.getNrOfJoints()),
              poses(flat.size()),
              twists(flat.size()),
              velocities(flat.size()),
              accelerations(flat.size()),
              forces(flat.size()),
              composite(flat.size())
        {
        }
        KDL::Tree tree;
        std::vector<kdl_detail::FlatSegment> flat;
        KDL::Twist gravity_acceleration;  // the root's, -g: gravity enters as the base accelerating up
        KDL::JntArray q, qdot;
        // Per flat segment, all in {w} about the world origin:
        std::vector<KDL::Frame> poses;                 // tip frames
        std::vector<KDL::Twist> twists;                // joint unit twists S
        std::vector<KDL::Twist> velocities;            // spatial velocities v
        std::vector<KDL::Twist> accelerations;         // spatial accelerations at qdd = 0, with -g
        std::vector<KDL::Wrench> forces;               // subtree forces of the RNEA
        std::vector<KDL::RigidBodyInertia> composite;  // subtree inertias
        std::vector<std::string> joint_names;
        std::vector<std::unique_ptr<Arm>> arms;
    };

    static KDL::Tree tree_from_chains(const std::vector<KDL::Chain>& chains, const std::vector<KDL::Frame>& bases);
    static std::vector<std::string> tip_names(const std::vector<KDL::Chain>& chains);
    void build(const std::vector<std::string>& tip_segments);
    void forward_pass() noexcept;
    void update_bias(Input& input) noexcept;
    void update_inertia(Input& input) noexcept;

    std::unique_ptr<State> state_;
};

template <int Arms, int Joints>
KDL::Tree KdlArms<Arms, Joints>::tree_from_chains(const std::vector<KDL::Chain>& chains,
                                                  const std::vector<KDL::Frame>& bases)
{
    if (!bases.empty() && bases.size() != chains.size()) {
        throw InvalidModel("kdl adapter", "bases", no_arm,
                           "must be empty or have one frame per chain (" + std::to_string(chains.size()) +
                               "), got " + std::to_string(bases.size()));
    }
    KDL::Tree tree("world");
    for (std::size_t i = 0; i < chains.size(); ++i) {
        const std::string prefix = "arm" + std::to_string(i) + "/";
        std::string parent = prefix + "base";
        tree.addSegment(KDL::Segment(parent, KDL::Joint(KDL::Joint::None),
                                     bases.empty() ? KDL::Frame::Identity() : bases[i]),
                        "world");
        for (unsigned int j = 0; j < chains[i].getNrOfSegments(); ++j) {
            const KDL::Segment& s = chains[i].getSegment(j);
            const std::string name = prefix + std::to_string(j);
            tree.addSegment(KDL::Segment(name, s.getJoint(), s.getFrameToTip(), s.getInertia()), parent);
            parent = name;
        }
    }
    return tree;
}

template <int Arms, int Joints>
std::vector<std::string> KdlArms<Arms, Joints>::tip_names(const std::vector<KDL::Chain>& chains)
{
    std::vector<std::string> names;
    for (std::size_t i = 0; i < chains.size(); ++i) {
        const unsigned int n = chains[i].getNrOfSegments();
        names.push_back("arm" + std::to_string(i) + "/" + (n == 0 ? "base" : std::to_string(n - 1)));
    }
    return names;
}

template <int Arms, int Joints>
void KdlArms<Arms, Joints>::build(const std::vector<std::string>& tip_segments)
{
    State& s = *state_;
    const auto k = static_cast<Index>(tip_segments.size());
    const auto q = static_cast<Index>(s.tree.getNrOfJoints());
    if (k == 0 || (Arms != Eigen::Dynamic && k != Arms)) {
        throw InvalidModel("kdl adapter", "tip_segments", no_arm,
                           "must name one segment per arm (K = " + std::to_string(Arms) + "), got " +
                               std::to_string(k));
    }
    if (q == 0 || (Joints != Eigen::Dynamic && q != Joints)) {
        throw InvalidModel("kdl adapter", "tree", no_arm,
                           "must have Q = " + std::to_string(Joints) + " joints, has " + std::to_string(q));
    }
    s.joint_names.assign(static_cast<std::size_t>(q), std::string());
    for (const kdl_detail::FlatSegment& f : s.flat) {
        if (f.joint >= 0) {
            s.joint_names[static_cast<std::size_t>(f.joint)] = f.segment.getName();
        }
    }
    const std::string root = s.tree.getRootSegment()->first;
    for (Index i = 0; i < k; ++i) {
        const std::string& tip = tip_segments[static_cast<std::size_t>(i)];
        KDL::Chain chain;
        if (tip == root || s.tree.getSegment(tip) == s.tree.getSegments().end() ||
            !s.tree.getChain(root, tip, chain)) {
            throw InvalidModel("kdl adapter", "tip_segments", i,
                               "names no segment below the root '" + root + "': '" + tip + "'");
        }
        std::vector<int> columns;
        for (unsigned int j = 0; j < chain.getNrOfSegments(); ++j) {
            const auto element = s.tree.getSegment(chain.getSegment(j).getName());
            if (chain.getSegment(j).getJoint().getType() != KDL::Joint::None) {
                columns.push_back(static_cast<int>(GetTreeElementQNr(element->second)));
            }
        }
        int index = 0;
        while (s.flat[static_cast<std::size_t>(index)].segment.getName() != tip) {
            ++index;
        }
        s.arms.push_back(std::make_unique<Arm>(std::move(chain), std::move(columns), index));
    }
}

template <int Arms, int Joints>
Eigen::Isometry3d KdlArms<Arms, Joints>::contact_pose(Index arm) const
{
    const KDL::Frame& f = state_->poses[static_cast<std::size_t>(state_->arms[static_cast<std::size_t>(arm)]->segment)];
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
        pose.translation()[r] = f.p(r);
        for (int c = 0; c < 3; ++c) {
            pose.linear()(r, c) = f.M(r, c);
        }
    }
    return pose;
}

/// Outward pass in {w}: each segment's pose, its joint's unit twist S, its spatial velocity
/// v = v_parent + S qdot and acceleration at qdd = 0, a = a_parent + v x (S qdot) (S moves with the
/// body carrying it: dS/dt = v_parent x S, and S x S = 0), starting from -g at the root; and its
/// inertia in {w}, the start of both inward passes.
template <int Arms, int Joints>
void KdlArms<Arms, Joints>::forward_pass() noexcept
{
    State& s = *state_;
    for (std::size_t i = 0; i < s.flat.size(); ++i) {
        const kdl_detail::FlatSegment& f = s.flat[i];
        const bool root = f.parent < 0;
        const auto p = static_cast<std::size_t>(root ? 0 : f.parent);
        const KDL::Frame base = root ? KDL::Frame::Identity() : s.poses[p];
        const double q = f.joint < 0 ? 0.0 : s.q(static_cast<unsigned int>(f.joint));
        const double qdot = f.joint < 0 ? 0.0 : s.qdot(static_cast<unsigned int>(f.joint));
        s.twists[i] = kdl_detail::joint_twist(f.segment.getJoint(), base);
        s.poses[i] = base * f.segment.pose(q);
        const KDL::Twist relative = s.twists[i] * qdot;
        s.velocities[i] = (root ? KDL::Twist::Zero() : s.velocities[p]) + relative;
        s.accelerations[i] = (root ? s.gravity_acceleration : s.accelerations[p]) + s.velocities[i] * relative;
        s.composite[i] = s.poses[i] * f.segment.getInertia();
    }
}

/// Inward RNEA pass: f = I a + v x* (I v) per body, summed over each subtree; h_k = S_k . f_k.
template <int Arms, int Joints>
void KdlArms<Arms, Joints>::update_bias(Input& input) noexcept
{
    State& s = *state_;
    for (std::size_t i = 0; i < s.flat.size(); ++i) {
        const KDL::RigidBodyInertia& inertia = s.composite[i];
        s.forces[i] = inertia * s.accelerations[i] + s.velocities[i] * (inertia * s.velocities[i]);
    }
    for (std::size_t i = s.flat.size(); i-- > 0;) {
        const kdl_detail::FlatSegment& f = s.flat[i];
        if (f.joint >= 0) {
            input.bias(f.joint) = KDL::dot(s.twists[i], s.forces[i]);
        }
        if (f.parent >= 0) {
            s.forces[static_cast<std::size_t>(f.parent)] += s.forces[i];
        }
    }
}

/// Composite-rigid-body algorithm: subtree inertias inward, then M(j, k) = S_j . (Ic_k S_k) for
/// every moving ancestor j of k (and k itself): the force that accelerating joint k alone needs,
/// felt by each joint that carries it. Runs after update_bias, which reads the body inertias.
template <int Arms, int Joints>
void KdlArms<Arms, Joints>::update_inertia(Input& input) noexcept
{
    State& s = *state_;
    const std::size_t n = s.flat.size();
    for (std::size_t i = n; i-- > 0;) {
        if (s.flat[i].parent >= 0) {
            const auto p = static_cast<std::size_t>(s.flat[i].parent);
            s.composite[p] = s.composite[p] + s.composite[i];
        }
    }
    input.inertia.setZero();
    for (std::size_t i = 0; i < n; ++i) {
        const int k = s.flat[i].joint;
        if (k < 0) {
            continue;
        }
        const KDL::Wrench force = s.composite[i] * s.twists[i];
        for (int a = static_cast<int>(i); a >= 0; a = s.flat[static_cast<std::size_t>(a)].parent) {
            const int j = s.flat[static_cast<std::size_t>(a)].joint;
            if (j >= 0) {
                input.inertia(j, k) = KDL::dot(s.twists[static_cast<std::size_t>(a)], force);
                input.inertia(k, j) = input.inertia(j, k);
            }
        }
    }
}

template <int Arms, int Joints>
bool KdlArms<Arms, Joints>::read(const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const Eigen::Ref<const Eigen::VectorXd>& qdot, Input& input) noexcept
{
    State& s = *state_;
    kdl_detail::view(s.q) = q;
    kdl_detail::view(s.qdot) = qdot;
    input.positions = q;
    input.velocities = qdot;
    forward_pass();
    update_bias(input);
    update_inertia(input);
    bool ok = true;
    for (std::size_t i = 0; i < s.arms.size(); ++i) {
        Arm& arm = *s.arms[i];
        for (std::size_t j = 0; j < arm.columns.size(); ++j) {
            arm.joints.q(static_cast<unsigned int>(j)) = s.q(static_cast<unsigned int>(arm.columns[j]));
            arm.joints.qdot(static_cast<unsigned int>(j)) = s.qdot(static_cast<unsigned int>(arm.columns[j]));
        }
        ok = arm.jacobian_solver.JntToJac(arm.joints.q, arm.jacobian) >= 0 && ok;
        ok = arm.rate_solver.JntToJacDot(arm.joints, arm.rate) >= 0 && ok;
        const auto row = static_cast<Index>(6 * i);
        input.jacobian.template middleRows<6>(row).setZero();
        for (std::size_t j = 0; j < arm.columns.size(); ++j) {
            input.jacobian.template middleRows<6>(row).col(arm.columns[j]) =
                kdl_detail::view(arm.jacobian).col(static_cast<Index>(j));
        }
        for (int r = 0; r < 3; ++r) {
            input.jacobian_rate_qdot(row + r) = arm.rate.vel(r);
            input.jacobian_rate_qdot(row + 3 + r) = arm.rate.rot(r);
        }
        // The contact's pose (the forward pass's tip frame): the controller's dropout prediction
        // and slip measurement (docs/control.md, "Faults: dropout, safe hold, slip, torque limits").
        const KDL::Frame& tip = s.poses[static_cast<std::size_t>(arm.segment)];
        double x = 0, y = 0, z = 0, w = 1;
        tip.M.GetQuaternion(x, y, z, w);
        const auto column = static_cast<Index>(i);
        input.contact_positions.col(column) << tip.p(0), tip.p(1), tip.p(2);
        input.contact_orientations.col(column) << x, y, z, w;
    }
    input.contact_poses_filled = true;
    return ok;
}

}  // namespace coopdyn
