// The QP with the contact forces among its unknowns (src/control/contact_actuation_qp.hpp),
// against references that do not share its pivoting: the contact LCP solved by enumerating
// every active set, and a force target met in closed form.
#include <gtest/gtest.h>

#include <random>

#include "control/contact_actuation_qp.hpp"

namespace {

// N candidates, n actuators: a random positive definite compliance (m/N), couplings to the
// actuators (m per unit), gaps of either sign and some held forces.
hs::ContactBlocks random_blocks(std::mt19937& rng, int N, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  hs::ContactBlocks k;
  Eigen::MatrixXd B(N, N);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) B(i, j) = u(rng);
  k.G_cc = 1e-3 * (B * B.transpose() + 0.5 * Eigen::MatrixXd::Identity(N, N));
  k.G_ca.resize(N, n);
  for (int i = 0; i < N; ++i)
    for (int a = 0; a < n; ++a) k.G_ca(i, a) = 1e-8 * u(rng);
  k.gap.resize(N);
  k.held.resize(N);
  for (int i = 0; i < N; ++i) {
    k.gap(i) = 1e-4 * u(rng);
    k.held(i) = u(rng) > 0 ? 0.05 * (1 + u(rng)) : 0;
  }
  k.growth_a = Eigen::MatrixXd::Zero(n, n);
  k.growth_c = Eigen::MatrixXd::Zero(n, N);
  k.gap_tolerance = 1e-12;
  return k;
}

// The LCP lambda >= 0, g = gap + G (lambda - held) >= 0, lambda g = 0 by enumeration of the
// 2^N active sets (G positive definite: exactly one solves it).
Eigen::VectorXd enumerated_lcp(const hs::ContactBlocks& k) {
  const int N = static_cast<int>(k.gap.size());
  const Eigen::VectorXd q = k.gap - k.G_cc * k.held;
  int found = 0;
  Eigen::VectorXd answer;
  for (int mask = 0; mask < (1 << N); ++mask) {
    std::vector<int> A;
    for (int c = 0; c < N; ++c)
      if (mask >> c & 1) A.push_back(c);
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(N);
    if (!A.empty()) {
      Eigen::MatrixXd G(A.size(), A.size());
      Eigen::VectorXd rhs(A.size());
      for (size_t i = 0; i < A.size(); ++i) {
        for (size_t j = 0; j < A.size(); ++j) G(i, j) = k.G_cc(A[i], A[j]);
        rhs(i) = -q(A[i]);
      }
      const Eigen::VectorXd l = G.ldlt().solve(rhs);
      for (size_t i = 0; i < A.size(); ++i) lambda(A[i]) = l(i);
    }
    const Eigen::VectorXd g = q + k.G_cc * lambda;
    if (lambda.minCoeff() >= -1e-14 && g.minCoeff() >= -1e-16) {
      ++found;
      answer = lambda;
    }
  }
  EXPECT_EQ(found, 1);
  return answer;
}

TEST(ContactActuationQp, WithTheActuationHeldTheForcesSolveTheContactProblem) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 40; ++trial) {
    const int N = 2 + trial % 7, n = 2;
    hs::ContactBlocks k = random_blocks(rng, N, n);
    k.W_a = Eigen::MatrixXd::Identity(n, n);
    k.W_c = Eigen::MatrixXd::Zero(n, N);
    k.delta = Eigen::VectorXd::Constant(n, 1.0);
    k.approach.assign(n, -1);
    k.approach_factor = Eigen::VectorXd::Zero(n);
    std::vector<hs::ActuatorConfig> bounds(n);
    for (auto& b : bounds) b.max_multiplier_step = 0;  // the actuation cannot move
    const std::vector<hs::ActuatorPosition> at(n, {1000, 1000, 0});
    const hs::ContactActuation s = hs::solve_contact_actuation_qp(k, bounds, at, 1e-3);
    ASSERT_TRUE(s.change.solved) << s.change.status;
    EXPECT_FALSE(s.cycled);
    EXPECT_EQ(s.change.dl.norm(), 0.0);
    const Eigen::VectorXd expected = enumerated_lcp(k);
    const Eigen::VectorXd got = k.held + s.dforce;
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-12 * (1 + expected.norm()))
        << "trial " << trial << ": " << got.transpose() << " against " << expected.transpose();
    EXPECT_GE(s.least_gap, -1e-15);
    EXPECT_GE(s.least_force, -1e-12);
    EXPECT_LT(s.worst_product, 1e-15);
  }
}

// One actuator moves one node towards a plane 0.1 mm away (1 m per unit of actuation); a
// spring of compliance c (m/N) holds it there once it touches. Asked for a force F on the
// plane, the answer is: the gap closed and pressed by c F, the force F exactly.
TEST(ContactActuationQp, AForceTargetClosesTheGapAndPressesWithTheForceAsked) {
  const double c = 2e-3, gap = 1e-4, F = 0.3;
  hs::ContactBlocks k;
  k.G_cc = Eigen::MatrixXd::Constant(1, 1, c);
  k.G_ca = Eigen::MatrixXd::Constant(1, 1, -1.0);  // actuation closes the gap
  k.gap = Eigen::VectorXd::Constant(1, gap);
  k.held = Eigen::VectorXd::Zero(1);
  // The force on the plane along -z, the candidate's normal +z: the row is minus the normal.
  k.W_a = Eigen::MatrixXd::Zero(1, 1);
  k.W_c = Eigen::MatrixXd::Constant(1, 1, -1.0);
  k.delta = Eigen::VectorXd::Constant(1, 0.0 - (-F));  // at 0 N, asked -F (along z)
  k.approach = {0};
  k.approach_factor = Eigen::VectorXd::Constant(1, F / gap * 1.0);
  k.growth_a = Eigen::MatrixXd::Zero(1, 1);
  k.growth_c = Eigen::MatrixXd::Zero(1, 1);
  k.gap_tolerance = 1e-12;
  const std::vector<hs::ActuatorConfig> bounds(1);
  const hs::ContactActuation s = hs::solve_contact_actuation_qp(k, bounds, {{0, 0, 0}}, 0.0);
  ASSERT_TRUE(s.change.solved) << s.change.status;
  EXPECT_EQ(s.touching, 1);
  EXPECT_NEAR(s.dforce(0), F, 1e-12);
  EXPECT_NEAR(s.change.dl(0), gap + c * F, 1e-15);
  EXPECT_NEAR(s.least_gap, 0.0, 1e-16);
  EXPECT_GE(s.passes, 2);  // the approach, then the force
}

TEST(ContactActuationQp, AnUnsolvedQpChangesNeitherTheActuationNorTheForces) {
  // The actuator stands at 1,000 Pa, its bound is 0 and it may not move this step: no
  // actuation satisfies both, so the QP proves infeasibility, and the answer keeps the held
  // forces (a correction that moved them with the actuation held would not be the QP's).
  std::mt19937 rng(5);
  hs::ContactBlocks k = random_blocks(rng, 3, 1);
  k.W_a = Eigen::MatrixXd::Identity(1, 1);
  k.W_c = Eigen::MatrixXd::Zero(1, 3);
  k.delta = Eigen::VectorXd::Constant(1, 1.0);
  k.approach.assign(1, -1);
  k.approach_factor = Eigen::VectorXd::Zero(1);
  std::vector<hs::ActuatorConfig> bounds(1);
  bounds[0].max_multiplier = 0;
  bounds[0].max_multiplier_step = 0;
  const hs::ContactActuation s = hs::solve_contact_actuation_qp(k, bounds, {{1000, 1000, 0}}, 0);
  EXPECT_FALSE(s.change.solved);
  EXPECT_EQ(s.change.dl.norm(), 0.0);
  EXPECT_EQ(s.dforce.norm(), 0.0);
}

}  // namespace
