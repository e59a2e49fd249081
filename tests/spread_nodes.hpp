// A structure's mass and mean stiffness spread evenly over n nodes up to the
// same height: more nodes than the kernels are unrolled for
// (modules/support/rocking/static_size.hpp), so that tests run the general
// loops. Include after importing a module that exports rocking::Structure.
#pragma once
#include <rocking/eigen.hpp>

inline void spread_over_nodes(rocking::Structure& st, Eigen::Index nodes) {
  const double height = st.heights[st.heights.size() - 1], mass = st.masses.sum(), EI = st.EI.mean();
  st.heights = Eigen::VectorXd::LinSpaced(nodes, height / static_cast<double>(nodes), height);
  st.masses = Eigen::VectorXd::Constant(nodes, mass / static_cast<double>(nodes));
  st.EI = Eigen::VectorXd::Constant(nodes, EI);
}
