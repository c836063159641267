// The POD basis against a snapshot matrix built from known singular vectors and values.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "reduction/pod.hpp"

namespace hs {
namespace {

// S = U diag(sigma) V^T with orthonormal U (n x 4) and V (6 x 4) of a fixed seed.
Eigen::MatrixXd known_snapshots(const Eigen::VectorXd& sigma, Eigen::MatrixXd& U) {
  std::srand(7);
  U = Eigen::MatrixXd::Random(40, 4).householderQr().householderQ() *
      Eigen::MatrixXd::Identity(40, 4);
  const Eigen::MatrixXd V = Eigen::MatrixXd::Random(6, 4).householderQr().householderQ() *
                            Eigen::MatrixXd::Identity(6, 4);
  return U * sigma.asDiagonal() * V.transpose();
}

TEST(PodBasis, KeepsTheModesTheEnergyCriterionAsksFor) {
  Eigen::VectorXd sigma(4);
  sigma << 10, 1, 0.1, 0.01;
  Eigen::MatrixXd U;
  const Eigen::MatrixXd S = known_snapshots(sigma, U);
  const double total = sigma.squaredNorm();
  // Discarding modes 3 and 4 leaves (0.01 + 1e-4) / total: a tolerance just above keeps 2.
  const PodBasis pod = pod_basis(S, 1.01e-2 / total * 1.001, 10);
  ASSERT_EQ(pod.modes.cols(), 2);
  EXPECT_NEAR(pod.discarded_energy, (0.01 + 1e-4) / total, 1e-14);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(pod.singular_values(i), sigma(i), 1e-12);
  // The kept modes span U's first two columns (signs are free).
  const Eigen::MatrixXd overlap = U.leftCols(2).transpose() * pod.modes;
  EXPECT_NEAR(std::abs(overlap(0, 0)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(overlap(1, 1)), 1.0, 1e-12);
  EXPECT_NEAR((pod.modes.transpose() * pod.modes - Eigen::MatrixXd::Identity(2, 2)).norm(), 0,
              1e-13);
  // A tolerance just below that discarded energy needs the third mode.
  EXPECT_EQ(pod_basis(S, (0.01 + 1e-4) / total * 0.999, 10).modes.cols(), 3);
  // max_modes wins over the tolerance; a tiny tolerance keeps the four modes with energy.
  EXPECT_EQ(pod_basis(S, 0, 2).modes.cols(), 2);
  EXPECT_EQ(pod_basis(S, 1e-12, 10).modes.cols(), 4);
}

TEST(PodBasis, RefusesWhatItCannotUse) {
  Eigen::MatrixXd S = Eigen::MatrixXd::Ones(5, 3);
  EXPECT_THROW(pod_basis(Eigen::MatrixXd(), 1e-6, 4), std::invalid_argument);
  EXPECT_THROW(pod_basis(S, 1.0, 4), std::invalid_argument);
  EXPECT_THROW(pod_basis(S, 1e-6, 0), std::invalid_argument);
  S(2, 1) = std::nan("");
  EXPECT_THROW(pod_basis(S, 1e-6, 4), std::invalid_argument);
}

}  // namespace
}  // namespace hs
