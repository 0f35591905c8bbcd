// Literal references and random inputs shared by the tests of coopdyn/spatial/ (tests/spatial/):
// the dense formulas written out independently of the library (S(a), the grasp map G(r) of (24)),
// seeded random vectors and rotations, rounding to a scalar type so that double references see
// exactly the numbers a float computation holds, and the error measures the tests print.
// The cooperative systems shared by the other tests and the benchmarks are in sample_systems.hpp.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>

namespace coopdyn_test {

/// Scientific notation with 3 significant digits, for recorded measurements.
inline std::string scientific(double value)
{
    std::ostringstream stream;
    stream << std::scientific << std::setprecision(2) << value;
    return stream.str();
}

/// Machine epsilon of Scalar, as a double.
template <typename Scalar> double epsilon() { return static_cast<double>(std::numeric_limits<Scalar>::epsilon()); }

/// x rounded to Scalar, back in double. Through a volatile: g++ 12.2 at -O2 folds some inlined
/// double -> float -> double round trips to the identity (its SLP vectoriser returns some lanes
/// of m.cast<float>().cast<double>() unrounded; fine with -fno-tree-slp-vectorize or clang).
template <typename Scalar> double round_to(double x)
{
    volatile Scalar rounded_value = static_cast<Scalar>(x);
    return static_cast<double>(rounded_value);
}

/// The matrix as Scalar, then back in double, entry by entry: the reference sees exactly what
/// Scalar holds.
template <typename Scalar, typename Derived> typename Derived::PlainObject rounded(const Eigen::MatrixBase<Derived>& m)
{
    typename Derived::PlainObject result;
    for (Eigen::Index k = 0; k < m.size(); ++k) {
        result(k) = round_to<Scalar>(m(k));
    }
    return result;
}

/// S(a) = [[0, -a_z, a_y], [a_z, 0, -a_x], [-a_y, a_x, 0]], written out.
inline Eigen::Matrix3d literal_skew(const Eigen::Vector3d& a)
{
    Eigen::Matrix3d s;
    s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    return s;
}

/// The grasp map of (24), G(r) = [[I3, 0], [S(r), I3]], written out.
inline Eigen::Matrix<double, 6, 6> literal_grasp_map(const Eigen::Vector3d& r)
{
    Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Identity();
    g.block<3, 3>(3, 0) = literal_skew(r);
    return g;
}

/// Uniform in [-scale, scale]^3.
inline Eigen::Vector3d random_vector(std::mt19937& rng, double scale = 1.0)
{
    std::uniform_real_distribution<double> uniform(-scale, scale);
    return Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
}

/// [linear; angular], each uniform in its own box.
inline Eigen::Matrix<double, 6, 1> random_six(std::mt19937& rng, double linear_scale, double angular_scale)
{
    Eigen::Matrix<double, 6, 1> result;
    result << random_vector(rng, linear_scale), random_vector(rng, angular_scale);
    return result;
}

/// A rotation matrix uniform on SO(3) (normalised Gaussian quaternion).
inline Eigen::Matrix3d random_rotation(std::mt19937& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    const Eigen::Vector4d coefficients(normal(rng), normal(rng), normal(rng), normal(rng));
    return Eigen::Quaterniond(coefficients.normalized()).toRotationMatrix();
}

/// max |a - b| / max |b| (or the absolute error when b is zero).
template <typename A, typename B> double relative_error(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b)
{
    const double scale = b.cwiseAbs().maxCoeff();
    return (a - b).cwiseAbs().maxCoeff() / (scale > 0.0 ? scale : 1.0);
}

}  // namespace coopdyn_test
