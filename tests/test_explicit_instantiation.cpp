// Explicit instantiation of every class template for the supported scalars, arm counts and
// end-effector models, so that every member compiles, plus compile-time
// checks of the size helpers and of the fast-path selection traits.
#include <coopdyn/coopdyn.hpp>

#include <gtest/gtest.h>

#include <type_traits>

namespace coopdyn {

template struct Pose<double>;
template struct Pose<float>;
template struct RigidBodyState<double>;
template struct RigidBodyState<float>;
template struct RigidObject<double>;
template struct RigidObject<float>;
template struct ImpedanceEndEffector<double>;
template struct ImpedanceEndEffector<float>;
template struct ResolvedAccelerationEndEffector<double>;
template struct ResolvedAccelerationEndEffector<float>;

template class Model<double, 2, ImpedanceEndEffector>;
template class Model<double, Dynamic, ImpedanceEndEffector>;
template class Model<float, 3, ImpedanceEndEffector>;
template class Model<double, 2, ResolvedAccelerationEndEffector>;
template class Model<double, Dynamic, ResolvedAccelerationEndEffector>;

template struct Setpoints<double, 2>;
template struct Setpoints<double, Dynamic>;
template struct Disturbances<double, 2>;
template struct Disturbances<double, Dynamic>;

template struct Data<Model<double, 2, ImpedanceEndEffector>>;
template struct Data<Model<double, Dynamic, ImpedanceEndEffector>>;
template struct Data<Model<float, 3, ImpedanceEndEffector>>;
template struct Data<Model<double, 2, ResolvedAccelerationEndEffector>>;
template struct Data<Model<double, Dynamic, ResolvedAccelerationEndEffector>>;

template class Simulator<Model<double, 2, ImpedanceEndEffector>>;
template class Simulator<Model<double, Dynamic, ImpedanceEndEffector>>;
template class Simulator<Model<float, 3, ImpedanceEndEffector>>;
template class Simulator<Model<double, 2, ResolvedAccelerationEndEffector>>;

template class FixedLdlt<double, 3>;
template class FixedLdlt<double, 6>;
template class FixedLdlt<float, 6>;
template class FixedLlt<double, 14>;
template class FixedLlt<float, 6>;

}  // namespace coopdyn

namespace {

using coopdyn::Dynamic;

static_assert(coopdyn::full_stack_size(2) == 18);
static_assert(coopdyn::end_effector_stack_size(16) == 96);
static_assert(coopdyn::full_stack_size(Dynamic) == Dynamic);
static_assert(coopdyn::end_effector_stack_size(Dynamic) == Dynamic);
static_assert(coopdyn::ImpedanceEndEffector<double>::has_block_diagonal_inertia);
static_assert(!coopdyn::ResolvedAccelerationEndEffector<double>::has_block_diagonal_inertia);
static_assert(std::is_same_v<decltype(std::declval<coopdyn::Data<coopdyn::ImpedanceModel2>&>().wrenches),
                             Eigen::Matrix<double, 18, 1>>,
              "fixed N gives fixed-size Data buffers");
static_assert(std::is_same_v<coopdyn::FullStackVector<double, Dynamic>, Eigen::VectorXd>);

TEST(ExplicitInstantiation, FixedSizeKernelResultTypes)
{
    const Eigen::Matrix<double, 3, 4> r = Eigen::Matrix<double, 3, 4>::Random();
    using GraspMatrix = decltype(coopdyn::grasp_matrix(r));
    using ConstraintMatrix = decltype(coopdyn::constraint_matrix(r));
    static_assert(GraspMatrix::RowsAtCompileTime == 6 && GraspMatrix::ColsAtCompileTime == 24);
    static_assert(ConstraintMatrix::RowsAtCompileTime == 24 && ConstraintMatrix::ColsAtCompileTime == 30);
    EXPECT_EQ(coopdyn::grasp_matrix(r).cols(), 24);
    EXPECT_EQ(coopdyn::constraint_matrix(r).rows(), 24);
}

}  // namespace
