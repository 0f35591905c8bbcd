/// \file
/// \brief KdlArms from a URDF file, through ROS's kdl_parser (Debian: libkdl-parser-dev; CMake
/// target coopdyn::kdl_urdf). A header of its own so that coopdyn/adapters/kdl.hpp needs KDL only.
/// docs/adapters.md, "KDL".
#pragma once

#include "coopdyn/adapters/kdl.hpp"
#include "coopdyn/errors.hpp"

#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace coopdyn {

/// The KDL tree of the URDF file at \p path (its root link is the world frame). Throws
/// InvalidModel when the file cannot be read or parsed.
///
/// The file is read here and parsed with kdl_parser::treeFromString: kdl_parser 1.14's
/// treeFromFile does not check that the file was parsed and dereferences a null root link for a
/// missing file (measured: a segmentation fault).
inline KDL::Tree kdl_tree_from_urdf(const std::string& path)
{
    std::ifstream file(path);
    if (!file) {
        throw InvalidModel("kdl adapter", "urdf_path", no_arm, "cannot be opened: '" + path + "'");
    }
    std::ostringstream text;
    text << file.rdbuf();
    KDL::Tree tree;
    if (!kdl_parser::treeFromString(text.str(), tree)) {
        throw InvalidModel("kdl adapter", "urdf_path", no_arm, "is not a valid URDF file: '" + path + "'");
    }
    return tree;
}

/// The arms of the URDF file at \p path whose contact frames are the links \p tip_links (e.g. each
/// shipped robot's "<robot>_palm"); q in the order kdl_parser numbers the joints (depth first
/// from the root, KdlArms::joint_names()).
template <int Arms = Eigen::Dynamic, int Joints = Eigen::Dynamic>
KdlArms<Arms, Joints> kdl_arms_from_urdf(const std::string& path, const std::vector<std::string>& tip_links,
                                         const Eigen::Vector3d& gravity = Eigen::Vector3d(0.0, 0.0, -9.81))
{
    return KdlArms<Arms, Joints>(kdl_tree_from_urdf(path), tip_links, gravity);
}

}  // namespace coopdyn
