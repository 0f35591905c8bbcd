// The compile-time baseline of docs/performance.md ("Compile time and CI"): a typical Eigen
// program with dense decompositions (LLT, JacobiSVD, Householder QR), compiled with the same
// command as the README's examples by scripts/compile-cost.
#include <Eigen/Dense>
#include <iostream>

int main()
{
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(8, 8);
    const Eigen::MatrixXd S = A * A.transpose() + Eigen::MatrixXd::Identity(8, 8);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(8);
    const Eigen::VectorXd x1 = S.llt().solve(b);
    const Eigen::VectorXd x2 = A.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(b);
    const Eigen::VectorXd x3 = A.householderQr().solve(b);
    std::cout << x1.norm() + x2.norm() + x3.norm() << '\n';
}
