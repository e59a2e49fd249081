// The one way the project includes Eigen. Include it in the global module
// fragment of every unit (interface or implementation) that does Eigen
// arithmetic, and in every test or app file, before any `import`.
//
// Why (TOOLCHAIN.md pitfalls 2 and 3): with clang-19, friend operators of an
// Eigen class template first instantiated inside a module purview are attached
// to that module and fail to link elsewhere (`2.0 * M`). Instantiating the
// types the project uses here, in the global fragment, attaches them to the
// global module instead.
#pragma once
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

namespace rocking::detail {
inline void instantiate_eigen_types() {
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(2, 2);
  Eigen::VectorXd v = Eigen::VectorXd::Ones(2);
  Eigen::Matrix4d m4 = Eigen::Matrix4d::Identity();
  Eigen::Vector4d v4 = Eigen::Vector4d::Ones();
  Eigen::MatrixXd scaled = 2.0 * m + m * 2.0 - m / 2.0;
  Eigen::VectorXd sv = 2.0 * v + v * 2.0 - v / 2.0 + m * v;
  Eigen::Matrix4d s4 = 2.0 * m4 + m4 * 2.0;
  Eigen::Vector4d t4 = 2.0 * v4 + m4 * v4;
  (void)scaled; (void)sv; (void)s4; (void)t4;
}
}  // namespace rocking::detail
