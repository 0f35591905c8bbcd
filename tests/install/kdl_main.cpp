// The installed KDL adapter compiles and links for a downstream project (tests/install).
#include <coopdyn/adapters/kdl_urdf.hpp>

#include <iostream>

int main(int argc, char** argv)
{
    if (argc < 3) {
        std::cerr << "usage: kdl_consumer <robot.urdf> <palm link>\n";
        return 1;
    }
    const auto arms = coopdyn::kdl_arms_from_urdf(argv[1], {argv[2]});
    std::cout << arms.joints() << " joints\n";
    return 0;
}
