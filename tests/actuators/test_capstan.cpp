// The capstan cable's forces against independent references: the frictionless cable's
// -dL/dp by finite differences of the length, the capstan equation's tension ratio around a
// known wrap, the balance of the forces with the motor's pull, and the Jacobian against
// central finite differences of the forces.
#include <gtest/gtest.h>

#include <cmath>

#include "actuators/capstan.hpp"

namespace {

using Path = std::vector<std::array<double, 3>>;
constexpr double kPi = 3.14159265358979323846;

double length(const Path& p) {
  double L = 0;
  for (size_t k = 0; k + 1 < p.size(); ++k)
    L += std::hypot(p[k + 1][0] - p[k][0], p[k + 1][1] - p[k][1], p[k + 1][2] - p[k][2]);
  return L;
}

// A bent path through space, no two segments parallel.
const Path kPath = {
    {0, 0, 0}, {0.03, 0.004, -0.002}, {0.05, 0.02, 0.003}, {0.06, 0.045, 0.01}, {0.09, 0.05, 0.0}};

TEST(Capstan, WithoutFrictionTheForcesAreMinusTheLengthGradient) {
  const hs::CapstanForces f = hs::capstan_forces(kPath, 0.0, false);
  const double h = 1e-6;
  for (size_t i = 0; i < kPath.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      Path plus = kPath, minus = kPath;
      plus[i][a] += h;
      minus[i][a] -= h;
      const double dL = (length(plus) - length(minus)) / (2 * h);
      EXPECT_NEAR(f.force[i][a], -dL, 1e-8) << "point " << i << " component " << a;
    }
  for (double tau : f.tension) EXPECT_EQ(tau, 1.0);
}

TEST(Capstan, TensionFallsByTheCapstanRatioAroundAWrap) {
  // A cable wound a quarter turn around a post in 16 equal turns (a regular polygon), then
  // straight on to the motor: the far end carries exp(-mu pi/2) of the motor's tension.
  const double mu = 0.3, r = 0.01;
  const int turns = 16;
  Path p = {{r, -0.05, 0}};  // a straight lead-in, tangent to the post
  for (int i = 0; i <= turns; ++i) {
    const double phi = 0.5 * kPi * i / turns;
    p.push_back({r * std::cos(phi), r * std::sin(phi), 0});
  }
  p.push_back({-0.05, r, 0});  // tangent lead-out to the motor
  const hs::CapstanForces f = hs::capstan_forces(p, mu, false);
  EXPECT_NEAR(f.tension.front(), std::exp(-mu * 0.5 * kPi), 1e-12);
  EXPECT_EQ(f.tension.back(), 1.0);
  // Each segment's tension ratio to the next is exp(-mu theta) at the point between them.
  for (size_t k = 1; k + 1 < f.tension.size(); ++k) EXPECT_LE(f.tension[k - 1], f.tension[k]);
}

TEST(Capstan, ForcesOnTheBodyBalanceTheMotorsPull) {
  // Internal segments act on both their ends: the resultant on all points but the motor's is
  // the motor's pull, tension 1 along the last segment; every moment about the motor's point
  // balances likewise.
  for (double mu : {0.0, 0.2, 0.7}) {
    const hs::CapstanForces f = hs::capstan_forces(kPath, mu, false);
    const auto& q = kPath.back();
    const auto& r = kPath[kPath.size() - 2];
    const double l = std::hypot(q[0] - r[0], q[1] - r[1], q[2] - r[2]);
    double resultant[3] = {0, 0, 0}, moment[3] = {0, 0, 0};
    for (size_t i = 0; i + 1 < kPath.size(); ++i) {
      const auto& F = f.force[i];
      const double x[3] = {kPath[i][0] - q[0], kPath[i][1] - q[1], kPath[i][2] - q[2]};
      for (int a = 0; a < 3; ++a) resultant[a] += F[a];
      moment[0] += x[1] * F[2] - x[2] * F[1];
      moment[1] += x[2] * F[0] - x[0] * F[2];
      moment[2] += x[0] * F[1] - x[1] * F[0];
    }
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(resultant[a], (q[a] - r[a]) / l, 1e-14) << "mu " << mu;
      EXPECT_NEAR(moment[a], 0.0, 1e-15) << "mu " << mu;
    }
  }
}

TEST(Capstan, JacobianMatchesFiniteDifferencesOfTheForces) {
  for (double mu : {0.0, 0.3}) {
    const hs::CapstanForces f = hs::capstan_forces(kPath, mu, true);
    const size_t dim = 3 * kPath.size();
    const double h = 1e-7;
    double worst = 0, scale = 0;
    for (size_t m = 0; m < kPath.size(); ++m)
      for (int b = 0; b < 3; ++b) {
        Path plus = kPath, minus = kPath;
        plus[m][b] += h;
        minus[m][b] -= h;
        const auto fp = hs::capstan_forces(plus, mu, false).force;
        const auto fm = hs::capstan_forces(minus, mu, false).force;
        for (size_t i = 0; i < kPath.size(); ++i)
          for (int a = 0; a < 3; ++a) {
            const double fd = (fp[i][a] - fm[i][a]) / (2 * h);
            const double exact = f.jacobian[(3 * i + a) * dim + 3 * m + b];
            worst = std::max(worst, std::abs(fd - exact));
            scale = std::max(scale, std::abs(exact));
          }
      }
    EXPECT_LT(worst, 1e-6 * scale) << "mu " << mu;
    EXPECT_GT(scale, 10.0);  // 1/l of the shortest segment: the test sees real entries
  }
}

TEST(Capstan, FrictionMakesTheJacobianUnsymmetric) {
  const hs::CapstanForces f0 = hs::capstan_forces(kPath, 0.0, true);
  const hs::CapstanForces f1 = hs::capstan_forces(kPath, 0.3, true);
  const size_t dim = 3 * kPath.size();
  double asym0 = 0, asym1 = 0;
  for (size_t r = 0; r < dim; ++r)
    for (size_t c = 0; c < dim; ++c) {
      asym0 = std::max(asym0, std::abs(f0.jacobian[r * dim + c] - f0.jacobian[c * dim + r]));
      asym1 = std::max(asym1, std::abs(f1.jacobian[r * dim + c] - f1.jacobian[c * dim + r]));
    }
  EXPECT_LT(asym0, 1e-12);  // a gradient's Jacobian, the frictionless cable's stiffness
  EXPECT_GT(asym1, 1e-2);
}

}  // namespace
