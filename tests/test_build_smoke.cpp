// Build smoke test: the toolchain, Eigen and GoogleTest are wired up.
#include <Eigen/Core>
#include <gtest/gtest.h>

TEST(BuildSmoke, IdentityTraceIsThree)
{
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  EXPECT_DOUBLE_EQ(identity.trace(), 3.0);
}
