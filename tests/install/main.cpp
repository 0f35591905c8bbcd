// Downstream consumer of an installed coopdyn: the umbrella header and Eigen
// must be found through find_package(coopdyn CONFIG) alone.
#include <Eigen/Core>
#include <coopdyn/coopdyn.hpp>

int main()
{
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  return identity.trace() == 3.0 ? 0 : 1;
}
