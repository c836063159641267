// ECSW's non-negative least squares: a sparse positive solution recovered exactly, a stop at
// the tolerance with fewer columns, and the refusals.
#include <gtest/gtest.h>

#include <stdexcept>

#include "reduction/ecsw.hpp"

namespace hs {
namespace {

TEST(EcswWeights, RecoversASparsePositiveSolution) {
  std::srand(3);
  const Eigen::MatrixXd C = Eigen::MatrixXd::Random(60, 200);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(200);
  w(5) = 1.5;
  w(17) = 0.25;
  w(80) = 3;
  w(199) = 0.7;
  const Eigen::VectorXd b = C * w;
  const EcswWeights e = ecsw_weights(C, b, 1e-12);
  ASSERT_TRUE(e.converged);
  ASSERT_EQ(e.elements, (std::vector<int>{5, 17, 80, 199}));
  for (size_t i = 0; i < e.elements.size(); ++i) EXPECT_NEAR(e.weights[i], w(e.elements[i]), 1e-10);
  EXPECT_LE(e.relative_residual, 1e-12);
}

TEST(EcswWeights, StopsAtTheToleranceWithPositiveWeights) {
  // Columns of one sign, b their plain sum (all weights 1): the ECSW situation.
  std::srand(11);
  const Eigen::MatrixXd C = Eigen::MatrixXd::Random(30, 400).cwiseAbs();
  const Eigen::VectorXd b = C * Eigen::VectorXd::Ones(400);
  const EcswWeights coarse = ecsw_weights(C, b, 1e-1);
  const EcswWeights fine = ecsw_weights(C, b, 1e-3);
  ASSERT_TRUE(coarse.converged && fine.converged);
  for (const EcswWeights* e : {&coarse, &fine}) {
    Eigen::VectorXd w = Eigen::VectorXd::Zero(400);
    for (size_t i = 0; i < e->elements.size(); ++i) {
      EXPECT_GT(e->weights[i], 0);
      w(e->elements[i]) = e->weights[i];
    }
    EXPECT_NEAR((C * w - b).norm() / b.norm(), e->relative_residual, 1e-12);
  }
  EXPECT_LE(coarse.relative_residual, 1e-1);
  EXPECT_LE(fine.relative_residual, 1e-3);
  EXPECT_LT(coarse.elements.size(), fine.elements.size());
  EXPECT_LE(fine.elements.size(), 30u);  // a basic solution: at most one column per row
}

// Random positive columns: the residual falls slowly until about one element a row, and a
// tight tolerance stops the fit at the most elements it keeps, a quarter of the rows or 256.
TEST(EcswWeights, StopsAtTheMostElementsItKeepsAndWhenInterrupted) {
  std::srand(5);
  const Eigen::MatrixXd C = Eigen::MatrixXd::Random(400, 3000).cwiseAbs();
  const Eigen::VectorXd b = C * Eigen::VectorXd::Ones(3000);
  const EcswWeights e = ecsw_weights(C, b, 1e-9);
  EXPECT_FALSE(e.converged);
  EXPECT_FALSE(e.interrupted);
  EXPECT_EQ(e.elements.size(), 256u);
  EXPECT_NE(e.reason.find("stopped at 256 elements"), std::string::npos) << e.reason;
  Eigen::VectorXd w = Eigen::VectorXd::Zero(3000);
  for (size_t i = 0; i < e.elements.size(); ++i) {
    EXPECT_GT(e.weights[i], 0);
    w(e.elements[i]) = e.weights[i];
  }
  EXPECT_NEAR((C * w - b).norm() / b.norm(), e.relative_residual, 1e-12);
  EXPECT_GT(e.relative_residual, 1e-9);
  // 1,100 rows: a quarter of them.
  const Eigen::MatrixXd tall = Eigen::MatrixXd::Random(1100, 2000).cwiseAbs();
  EXPECT_EQ(ecsw_weights(tall, tall * Eigen::VectorXd::Ones(2000), 1e-9).elements.size(), 275u);

  int asked = 0;
  const EcswWeights stopped = ecsw_weights(C, b, 1e-9, [&] { return ++asked > 5; });
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_FALSE(stopped.converged);
  EXPECT_LE(stopped.elements.size(), 5u);
}

TEST(EcswWeights, RefusesWhatItCannotUse) {
  const Eigen::MatrixXd C = Eigen::MatrixXd::Ones(4, 3);
  EXPECT_THROW(ecsw_weights(C, Eigen::VectorXd::Ones(5), 1e-3), std::invalid_argument);
  EXPECT_THROW(ecsw_weights(C, Eigen::VectorXd::Ones(4), 0), std::invalid_argument);
  EXPECT_THROW(ecsw_weights(C, Eigen::VectorXd::Ones(4), 1), std::invalid_argument);
  EXPECT_TRUE(ecsw_weights(C, Eigen::VectorXd::Zero(4), 1e-3).elements.empty());
}

}  // namespace
}  // namespace hs
