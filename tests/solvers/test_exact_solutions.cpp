// The closed-form references themselves, against published values (verification.md tables)
// and against each other.
#include <gtest/gtest.h>

#include <cmath>

#include "solvers/exact_solution.hpp"

namespace {

TEST(ExactSolutions, ElasticaMatchesPublishedTable) {
  // Uniform load, v/L at beta = q L^3 / (E I) (inextensible elastica).
  const double beta[] = {1, 2, 4, 8, 16};
  const double v[] = {0.12347, 0.23851, 0.42516, 0.64063, 0.79702};
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(hs::elastica_uniform_load(beta[i]), v[i], 2e-5) << beta[i];
}

TEST(ExactSolutions, ElasticaTendsToEulerBernoulliAtSmallLoad) {
  // Linear theory: v/L = beta / 8.
  EXPECT_NEAR(hs::elastica_uniform_load(1e-3) / (1e-3 / 8), 1.0, 1e-5);
}

TEST(ExactSolutions, NeoHookeanSpherePressureCurve) {
  // A/B = 0.5: published points and the peak P/mu = 0.816424 at inner stretch 1.8281.
  EXPECT_NEAR(hs::neo_hookean_sphere_pressure(1.1, 1, 2), 0.287155, 1e-6);
  EXPECT_NEAR(hs::neo_hookean_sphere_pressure(1.2, 1, 2), 0.480160, 1e-6);
  EXPECT_NEAR(hs::neo_hookean_sphere_pressure(1.5, 1, 2), 0.755433, 1e-6);
  EXPECT_NEAR(hs::neo_hookean_sphere_pressure(1.8281, 1, 2), 0.816424, 1e-6);
  EXPECT_LT(hs::neo_hookean_sphere_pressure(1.80, 1, 2), 0.816424);
  EXPECT_LT(hs::neo_hookean_sphere_pressure(1.86, 1, 2), 0.816424);
}

TEST(ExactSolutions, LameSphereSatisfiesBoundaryTractions) {
  // sigma_rr = (lambda + 2 mu) u_r' + 2 lambda u_r / r must be -p at r = a and 0 at r = b.
  const double a = 1, b = 2, p = 3, E = 7, nu = 0.3;
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  auto srr = [&](double r) {
    const double h = 1e-6;
    const double u = hs::lame_sphere_radial_displacement(r, a, b, p, E, nu);
    const double du = (hs::lame_sphere_radial_displacement(r + h, a, b, p, E, nu) -
                       hs::lame_sphere_radial_displacement(r - h, a, b, p, E, nu)) /
                      (2 * h);
    return (lambda + 2 * mu) * du + 2 * lambda * u / r;
  };
  EXPECT_NEAR(srr(a), -p, 1e-6);
  EXPECT_NEAR(srr(b), 0, 1e-6);
}

TEST(ExactSolutions, EulerBernoulliTipDeflection) {
  // 3 rho g L^4 / (2 E h^2) = q L^4 / (8 E I) with q = rho g h^2, I = h^4 / 12.
  const double rho = 1000, g = 9.81, L = 1, h = 0.05, E = 1e9;
  const double q = rho * g * h * h, I = std::pow(h, 4) / 12;
  EXPECT_NEAR(hs::cantilever_tip_deflection(rho, g, L, h, E), q * std::pow(L, 4) / (8 * E * I),
              1e-15);
}

}  // namespace
