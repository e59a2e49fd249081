// rocking.modal: the chimney's modal numbers (MODEL.md 8, the paper's Fig. 3
// and Table 1) and the structure of the linearised rocking phase.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <cmath>
import rocking.scene;
import rocking.beam;
import rocking.modal;

using namespace rocking;

TEST_CASE("the chimney reproduces MODEL.md 8 within 0.5 % and M_ref, V_ref within 1 %") {
  const Scene scene = load_default_scene();
  const ModalSummary m = modal_analysis(scene.structure, scene.damper);
  const double half_percent = 5e-3, one_percent = 1e-2;
  CHECK(m.fixed_base_hz.at(0) == doctest::Approx(2.176).epsilon(half_percent));
  CHECK(m.rocking_hz.at(0) == doctest::Approx(6.21).epsilon(half_percent));
  CHECK(m.rocking_p == doctest::Approx(0.650).epsilon(half_percent));
  CHECK(m.damper_pre_yield_hz == doctest::Approx(0.312).epsilon(half_percent));
  CHECK(m.damper_post_yield_p == doctest::Approx(0.40).epsilon(half_percent));
  CHECK(m.r_eq10 == doctest::Approx(0.938).epsilon(half_percent));
  CHECK(m.J_p == doctest::Approx(1.0006e8).epsilon(half_percent));
  CHECK(m.H_cg == doctest::Approx(15.02).epsilon(half_percent));
  CHECK(m.alpha_cg == doctest::Approx(0.2162).epsilon(half_percent));
  CHECK(m.reference.base_moment == doctest::Approx(9.26e6).epsilon(one_percent));
  CHECK(m.reference.base_shear == doctest::Approx(3.68e5).epsilon(one_percent));
}

TEST_CASE("the linearised rocking phase is symmetric with a positive-definite mass") {
  const Scene scene = load_default_scene();
  const LinearisedRocking lin = linearise_rocking(scene.structure, assemble(scene.structure), 0.0);
  CHECK((lin.stiffness - lin.stiffness.transpose()).norm() == 0.0);
  CHECK((lin.mass - lin.mass.transpose()).norm() == 0.0);
  CHECK(Eigen::LLT<Eigen::MatrixXd>(lin.mass).info() == Eigen::Success);
}

TEST_CASE("free rocking has exactly one unstable mode; an elastic damper stabilises it") {
  const Scene scene = load_default_scene();
  const StructuralMatrices sm = assemble(scene.structure);
  const RockingModes free_modes = rocking_modes(linearise_rocking(scene.structure, sm, 0.0));
  CHECK(free_modes.lambda[0] < 0);
  CHECK(free_modes.lambda[1] > 0);
  const double k_pre = pre_yield_rotational_stiffness(scene.damper, scene.structure.half_width);
  CHECK(rocking_modes(linearise_rocking(scene.structure, sm, k_pre)).lambda[0] > 0);
}

TEST_CASE("a very stiff structure rocks like a rigid body: p^2 = g sum(m H) / J_p") {
  Scene scene = load_default_scene({"structure.EI_scale=1e6"});
  const Structure& s = scene.structure;
  const ModalSummary m = modal_analysis(s, scene.damper);
  const double rigid_p = std::sqrt(gravity * s.masses.dot(s.heights) / pivot_inertia(s));
  CHECK(m.rocking_p == doctest::Approx(rigid_p).epsilon(1e-5));
}

TEST_CASE("modes of the rocking phase are orthogonal in its mass matrix") {
  const Scene scene = load_default_scene();
  const LinearisedRocking lin =
      linearise_rocking(scene.structure, assemble(scene.structure), 0.0);
  const RockingModes modes = rocking_modes(lin);
  const Eigen::MatrixXd P = modes.shapes;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(P.cols(), P.cols());
  CHECK((P.transpose() * lin.mass * P - I).norm() < 1e-10);
}
