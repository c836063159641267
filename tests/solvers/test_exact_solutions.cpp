// The closed-form references of src/verification/ against independent numbers: published
// values (verification.md tables), the equations they solve checked by finite differences
// (equilibrium, boundary tractions, incompressibility, beam boundary conditions), and the
// registry's checks of names and parameters.
#include <gtest/gtest.h>

#include <cmath>

#include "fem/quadrature.hpp"
#include "verification/cantilever_gravity.hpp"
#include "verification/lame_sphere.hpp"
#include "verification/neo_hookean_sphere.hpp"
#include "verification/registry.hpp"
#include "verification/stretched_block.hpp"

namespace hs {
namespace {

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;

ExactMaterial material(const std::string& group, double E, double nu, double density = 0,
                       const std::string& model = "linear_elastic") {
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  return {group, E, nu, mu, lambda, density, model};
}

std::unique_ptr<const ExactSolution> make(const std::string& name,
                                          const ExactParameterMap& parameters,
                                          const ExactSetting& setting) {
  return make_exact_solution(exact_solution_type(name), parameters, setting);
}

// grad u (du_i / dX_j) at X by central differences.
Mat3 gradient(const ExactSolution& u, const Vec3& X, double s = 1, double h = 1e-5) {
  Mat3 G{};
  for (int j = 0; j < 3; ++j) {
    Vec3 p = X, m = X;
    p[j] += h;
    m[j] -= h;
    const Vec3 up = u.displacement(p, s), um = u.displacement(m, s);
    for (int i = 0; i < 3; ++i) G[i][j] = (up[i] - um[i]) / (2 * h);
  }
  return G;
}

// Linear elastic stress from the displacement gradient.
Mat3 stress(const ExactSolution& u, const Vec3& X, double mu, double lambda, double h = 1e-5) {
  const Mat3 G = gradient(u, X, 1, h);
  const double tr = G[0][0] + G[1][1] + G[2][2];
  Mat3 S{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S[i][j] = mu * (G[i][j] + G[j][i]) + (i == j ? lambda * tr : 0);
  return S;
}

Vec3 traction(const Mat3& S, const Vec3& n) {
  Vec3 t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i] += S[i][j] * n[j];
  return t;
}

TEST(ExactSolutions, ElasticaMatchesPublishedTable) {
  // Uniform load, v/L at beta = q L^3 / (E I) (inextensible elastica).
  const double beta[] = {1, 2, 4, 8, 16};
  const double v[] = {0.12347, 0.23851, 0.42516, 0.64063, 0.79702};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(elastica_uniform_load(beta[i]), v[i], 2e-5) << beta[i];
}

TEST(ExactSolutions, ElasticaTendsToEulerBernoulliAtSmallLoad) {
  // Linear theory: v/L = beta / 8.
  EXPECT_NEAR(elastica_uniform_load(1e-3) / (1e-3 / 8), 1.0, 1e-5);
}

TEST(ExactSolutions, NeoHookeanSpherePressureCurve) {
  // A/B = 0.5: published points and the peak P/mu = 0.816424 at inner stretch 1.8281.
  EXPECT_NEAR(neo_hookean_sphere_pressure(1.1, 1, 2), 0.287155, 1e-6);
  EXPECT_NEAR(neo_hookean_sphere_pressure(1.2, 1, 2), 0.480160, 1e-6);
  EXPECT_NEAR(neo_hookean_sphere_pressure(1.5, 1, 2), 0.755433, 1e-6);
  EXPECT_NEAR(neo_hookean_sphere_pressure(1.8281, 1, 2), 0.816424, 1e-6);
  EXPECT_LT(neo_hookean_sphere_pressure(1.80, 1, 2), 0.816424);
  EXPECT_LT(neo_hookean_sphere_pressure(1.86, 1, 2), 0.816424);
}

TEST(ExactSolutions, LameSphereRadialStressAtTheSurfaces) {
  // sigma_rr = (lambda + 2 mu) u_r' + 2 lambda u_r / r must be -p at r = a and 0 at r = b.
  const double a = 1, b = 2, p = 3, E = 7, nu = 0.3;
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  auto srr = [&](double r) {
    const double h = 1e-6;
    const double u = lame_sphere_radial_displacement(r, a, b, p, E, nu);
    const double du = (lame_sphere_radial_displacement(r + h, a, b, p, E, nu) -
                       lame_sphere_radial_displacement(r - h, a, b, p, E, nu)) /
                      (2 * h);
    return (lambda + 2 * mu) * du + 2 * lambda * u / r;
  };
  EXPECT_NEAR(srr(a), -p, 1e-6);
  EXPECT_NEAR(srr(b), 0, 1e-6);
}

TEST(ExactSolutions, LameSphereIn3DIsInEquilibriumWithItsTractions) {
  // The registry's 3D field: traction sigma n = -p n on r = a, 0 on r = b (any direction n),
  // and div sigma = 0 inside, all by finite differences of the displacement.
  const double a = 1, b = 2, p = 3, E = 7, nu = 0.3;
  const ExactMaterial m = material("body", E, nu);
  const auto u = make("lame_sphere", {{"a", a}, {"b", b}, {"p", p}}, {{m}, {0, 0, 0}});
  const double len = std::sqrt(1.0 + 4.0 + 9.0);
  const Vec3 n = {1 / len, 2 / len, 3 / len};
  for (double r : {a, b}) {
    const Vec3 t = traction(stress(*u, {r * n[0], r * n[1], r * n[2]}, m.mu, m.lambda), n);
    const double expected = r == a ? -p : 0.0;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(t[i], expected * n[i], 1e-6) << "r = " << r;
  }
  const Vec3 X = {0.9, 0.6, 0.7};  // |X| = 1.29
  const double H = 1e-3;
  for (int i = 0; i < 3; ++i) {
    double div = 0;
    for (int j = 0; j < 3; ++j) {
      Vec3 P = X, M = X;
      P[j] += H;
      M[j] -= H;
      div += (stress(*u, P, m.mu, m.lambda)[i][j] - stress(*u, M, m.mu, m.lambda)[i][j]) / (2 * H);
    }
    EXPECT_NEAR(div, 0, 1e-5 * p) << "component " << i;
  }
  // Linear in the load factor.
  const Vec3 full = u->displacement(X, 1), half = u->displacement(X, 0.5);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(half[i], full[i] / 2);
}

TEST(ExactSolutions, HydrostaticBlockStressIsThePressureOfTheColumnAbove) {
  // sigma = -rho g (H - z) I, whatever x and y.
  const double H = 1.5, rho = 1000, g = 9.81;
  const ExactMaterial m = material("body", 1e6, 0.3, rho);
  const auto u = make("hydrostatic_block", {{"H", H}}, {{m}, {0, 0, -g}});
  for (const Vec3& X : {Vec3{0.3, -0.2, 0.4}, Vec3{-1.0, 0.5, 1.2}}) {
    const Mat3 S = stress(*u, X, m.mu, m.lambda);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(S[i][j], i == j ? -rho * g * (H - X[2]) : 0.0, 1e-4) << i << j;
  }
}

TEST(ExactSolutions, BimaterialBarCarriesTheTractionThroughBothMaterials) {
  const double L1 = 1, t = 2, E1 = 1e3, E2 = 10;
  const ExactSetting setting = {{material("soft", E2, 0), material("stiff", E1, 0)}, {0, 0, 0}};
  const auto u = make("bimaterial_bar", {{"L1", L1}, {"t", t}}, setting);
  EXPECT_NEAR(E1 * gradient(*u, {0.5, 0.1, 0.1})[0][0], t, 1e-6);
  EXPECT_NEAR(E2 * gradient(*u, {1.5, 0.1, 0.1})[0][0], t, 1e-6);
  const double h = 1e-9;  // continuous at the interface
  EXPECT_NEAR(u->displacement({L1 - h, 0, 0}, 1)[0], u->displacement({L1 + h, 0, 0}, 1)[0], 1e-6);
  EXPECT_EQ(u->displacement({0, 0, 0}, 1)[0], 0.0);
}

TEST(ExactSolutions, NeoHookeanSphereIsIncompressibleAndReachesItsStretch) {
  const double A = 1, B = 2, stretch = 1.7;
  const auto u = make("neo_hookean_sphere", {{"A", A}, {"B", B}, {"stretch", stretch}},
                      {{material("body", 3, 0.3)}, {0, 0, 0}});
  for (double s : {0.5, 1.0}) {
    const Mat3 G = gradient(*u, {0.8, 0.9, 0.5}, s, 1e-6);
    Mat3 F = G;
    for (int i = 0; i < 3; ++i) F[i][i] += 1;
    const double J = F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
                     F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
                     F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
    EXPECT_NEAR(J, 1, 1e-8) << "s = " << s;
  }
  // The inner surface at radius stretch A at full load, 1 + (stretch - 1) / 2 halfway.
  EXPECT_NEAR(A + u->displacement({A, 0, 0}, 1)[0], stretch * A, 1e-12);
  EXPECT_NEAR(A + u->displacement({0, A, 0}, 0.5)[1], (1 + (stretch - 1) / 2) * A, 1e-12);
  // Its pressure from a radial reaction that is exactly the curve's gives no error.
  const double la = stretch, mu = material("body", 3, 0.3).mu;
  const double radial = neo_hookean_sphere_pressure(la, A, B) * mu * M_PI * la * la * A * A / 2;
  ASSERT_EQ(u->measures().size(), 1u);
  EXPECT_EQ(u->measures()[0].group, "inner");
  EXPECT_NEAR(u->verification({radial}, 1)["pressure_relative_error"].get<double>(), 0, 1e-14);
}

double determinant(const Mat3& F) {
  return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
         F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
         F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
}

TEST(ExactSolutions, TwistedBlockIsIsochoricAtRestOnItsFacesAndLoadedInside) {
  const double H = 2, mu = 1;  // E = 3 at nu = 0.5
  const auto u = make("twisted_block", {{"H", H}, {"twist", 0.6}, {"q", 1}},
                      {{material("body", 3, 0.5, 0, "neo_hookean")}, {0, 0, 0}});
  // det F = 1 by differences of the displacement, inside and outside the inscribed cylinder.
  for (const Vec3& X :
       {Vec3{1.0, 1.0, 0.7}, Vec3{0.6, 1.3, 1.1}, Vec3{1.4, 0.5, 1.6}, Vec3{0.1, 0.1, 1.0}}) {
    Mat3 F = gradient(*u, X, 1, 1e-6);
    for (int i = 0; i < 3; ++i) F[i][i] += 1;
    EXPECT_NEAR(determinant(F), 1, 1e-8) << X[0] << " " << X[1] << " " << X[2];
  }
  EXPECT_GT(std::abs(u->displacement({1.3, 1.0, 1.0}, 1)[1]), 0.1);  // it does twist
  // On every face: no displacement, F = I, and no stress (the mean stress is 0).
  for (const Vec3& X : {Vec3{0, 1.0, 0.8}, Vec3{H, 0.7, 1.2}, Vec3{1.1, 0, 0.5}, Vec3{0.9, H, 1.5},
                        Vec3{1.0, 1.2, 0}, Vec3{0.8, 1.1, H}}) {
    const Mat3 G = gradient(*u, X, 1, 1e-6);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(u->displacement(X, 1)[i], 0, 1e-15);
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(G[i][j], 0, 1e-9);
    }
    EXPECT_NEAR(u->pressure(X), 0, 1e-12 * mu);
  }
  // Every face free of traction: the body force's resultant int B dV = -int P N dA vanishes
  // (a tensor Gauss rule, 16 points a direction), while B itself is of order mu / H.
  std::vector<double> xi, w;
  gauss_jacobi(16, 0, xi, w);
  Vec3 resultant{}, magnitude{};
  for (size_t i = 0; i < xi.size(); ++i)
    for (size_t j = 0; j < xi.size(); ++j)
      for (size_t k = 0; k < xi.size(); ++k) {
        const Vec3 B = u->body_force({H * xi[i], H * xi[j], H * xi[k]});
        for (int c = 0; c < 3; ++c) {
          resultant[c] += w[i] * w[j] * w[k] * H * H * H * B[c];
          magnitude[c] += w[i] * w[j] * w[k] * H * H * H * std::abs(B[c]);
        }
      }
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(magnitude[c], 0.1 * mu * H * H) << c;
    EXPECT_LT(std::abs(resultant[c]), 1e-6 * magnitude[c]) << c;
  }
}

TEST(ExactSolutions, StretchedBlockIsIsochoricAndCarriesItsTraction) {
  // mu (l - 1/l^2) = t: l = 1 at rest, the golden-ratio root at t = mu (l^3 - l^2 - 1 = 0 is
  // solved by 1.465571...), below 1 under a push.
  EXPECT_EQ(incompressible_uniaxial_stretch(0), 1.0);
  EXPECT_NEAR(incompressible_uniaxial_stretch(1), 1.4655712318767680, 1e-14);
  EXPECT_LT(incompressible_uniaxial_stretch(-0.5), 1.0);
  const double mu = 2, t = 3;  // E = 6 at nu = 0.5
  const auto u = make("stretched_block", {{"t", t}},
                      {{material("body", 6, 0.5, 0, "neo_hookean")}, {0, 0, 0}});
  for (double s : {0.5, 1.0}) {
    Mat3 F = gradient(*u, {0.3, 0.7, 0.4}, s);
    for (int i = 0; i < 3; ++i) F[i][i] += 1;
    EXPECT_NEAR(determinant(F), 1, 1e-9) << s;
    // The sides free, sigma_xx = mu (F_xx^2 - 1) + q = 0, gives q; then P_zz =
    // mu (F_zz - 1 / F_zz) + q / F_zz is the traction s t.
    const double q = -mu * (F[0][0] * F[0][0] - 1);
    EXPECT_NEAR(mu * (F[2][2] - 1 / F[2][2]) + q / F[2][2], s * t, 1e-8) << s;
  }
  // The pressure -sigma_zz / 3, sigma_zz = P_zz F_zz at full load.
  const double l = incompressible_uniaxial_stretch(t / mu);
  EXPECT_NEAR(u->pressure({0.1, 0.2, 0.3}), -t * l / 3, 1e-12);
  EXPECT_EQ(u->pressure({0.1, 0.2, 0.3}), u->pressure({0.9, 0.5, 0.8}));
}

TEST(ExactSolutions, CantileverMeetsTheBeamBoundaryConditions) {
  // Euler-Bernoulli: w(0) = w'(0) = 0 at the clamp, no moment (w'') and no shear (w''') at the
  // free end, and the tip deflection q L^4 / (8 E I).
  const double L = 2, h = 0.1, E = 1e9, rho = 1000, g = 9.81;
  const auto u = make("cantilever_gravity", {{"L", L}, {"h", h}},
                      {{material("beam", E, 0.3, rho)}, {0, 0, -g}});
  auto w = [&](double x) { return u->displacement({x, 0.01, -0.02}, 1)[2]; };
  const double d = 1e-3;
  const double tip = cantilever_tip_deflection(rho, g, L, h, E);
  EXPECT_EQ(w(0), 0.0);
  EXPECT_NEAR((w(d) - w(-d)) / (2 * d), 0, 1e-6 * tip);
  EXPECT_NEAR((w(L + d) - 2 * w(L) + w(L - d)) / (d * d), 0, 1e-6 * tip);
  EXPECT_NEAR((w(L + 2 * d) - 2 * w(L + d) + 2 * w(L - d) - w(L - 2 * d)) / (2 * d * d * d), 0,
              1e-3 * tip);
  const double q = rho * g * h * h, I = std::pow(h, 4) / 12;
  EXPECT_NEAR(-w(L), q * std::pow(L, 4) / (8 * E * I), 1e-12 * tip);
  EXPECT_NEAR(tip, q * std::pow(L, 4) / (8 * E * I), 1e-12 * tip);
  // beta = q L^3 / (E I) = 0.0942: compared against Euler-Bernoulli, by the mean tip
  // deflection (the measure is the mean u_z over the group `tip`).
  ASSERT_EQ(u->measures().size(), 1u);
  EXPECT_EQ(u->measures()[0].group, "tip");
  const auto v = u->verification({-1.01 * tip}, 1);
  EXPECT_EQ(v["reference"], "euler_bernoulli");
  EXPECT_NEAR(v["beta"].get<double>(), q * L * L * L / (E * I), 1e-12);
  EXPECT_NEAR(v["tip_relative_error"].get<double>(), 0.01, 1e-12);
  // A soft beam (beta = 4) is compared against the elastica.
  const auto soft = make("cantilever_gravity", {{"L", L}, {"h", h}},
                         {{material("beam", q * L * L * L / (4 * I), 0.3, rho)}, {0, 0, -g}});
  const auto vs = soft->verification({-0.42516 * L}, 1);
  EXPECT_EQ(vs["reference"], "elastica");
  EXPECT_NEAR(vs["tip_relative_error"].get<double>(), 0, 1e-4);
}

// The message of the ExactInputError `f` raises, after checking its key.
template <class F>
std::string error_of(F f, const std::string& key) {
  try {
    f();
  } catch (const ExactInputError& e) {
    EXPECT_EQ(e.key(), key);
    return e.what();
  }
  ADD_FAILURE() << "no ExactInputError for " << key;
  return "";
}

TEST(ExactRegistry, UnknownNameListsTheNames) {
  const std::string message = error_of([] { exact_solution_type("sphere"); }, "exact.type");
  EXPECT_NE(message.find("unknown exact solution 'sphere'"), std::string::npos) << message;
  for (const char* name :
       {"lame_sphere", "cantilever_gravity", "hydrostatic_block", "neo_hookean_sphere",
        "bimaterial_bar", "twisted_block", "stretched_block"})
    EXPECT_NE(message.find(name), std::string::npos) << name << " in " << message;
  EXPECT_EQ(exact_solution_names().size(), 7u);
}

TEST(ExactRegistry, ParametersAreCheckedByNameAndValue) {
  const ExactSolutionType& lame = exact_solution_type("lame_sphere");
  EXPECT_EQ(lame.parameters, (std::vector<std::string>{"a", "b", "p"}));
  EXPECT_NE(error_of(
                [&] {
                  check_exact_parameters(lame, {{"a", 1}, {"b", 2}});
                },
                "exact.parameters.p")
                .find("required by exact solution 'lame_sphere' (takes a, b, p)"),
            std::string::npos);
  EXPECT_NE(error_of(
                [&] {
                  check_exact_parameters(lame, {{"a", 1}, {"b", 2}, {"p", 1}, {"c", 0}});
                },
                "exact.parameters.c")
                .find("unknown to exact solution 'lame_sphere'"),
            std::string::npos);
  EXPECT_NE(error_of(
                [&] {
                  check_exact_parameters(lame, {{"a", 0}, {"b", 2}, {"p", 1}});
                },
                "exact.parameters.a")
                .find("must be > 0, got 0"),
            std::string::npos);
  EXPECT_NE(error_of(
                [&] {
                  check_exact_parameters(lame, {{"a", 2}, {"b", 2}, {"p", 1}});
                },
                "exact.parameters.b")
                .find("must be > a = 2, got 2"),
            std::string::npos);
  check_exact_parameters(lame, {{"a", 1}, {"b", 2}, {"p", -1}});  // any pressure
  const ExactSetting two = {{material("a", 1, 0), material("b", 1, 0)}, {0, 0, 0}};
  EXPECT_NE(error_of(
                [&] {
                  make("lame_sphere", {{"a", 1}, {"b", 2}, {"p", 1}}, two);
                },
                "materials")
                .find("needs exactly one material"),
            std::string::npos);
  EXPECT_NE(error_of(
                [&] {
                  make("bimaterial_bar", {{"L1", 1}, {"t", 1}}, two);
                },
                "materials")
                .find("needs a material for group 'stiff'"),
            std::string::npos);
}

TEST(ExactReference, ParametersThatPassTheirChecksButOverflowAreFound) {
  const ExactSetting steel = {{material("body", 2e11, 0.3, 7800)}, {0, 0, -9.81}};
  const std::vector<double> nodes = {1, 0, 0, 0, 1.5, 0, 0, 0, 2};  // in the sphere's wall
  EXPECT_EQ(
      non_finite_reference(*make("lame_sphere", {{"a", 1}, {"b", 2}, {"p", 1}}, steel), nodes), "");
  // b^3 overflows: the displacement is 0 * inf at every node.
  EXPECT_EQ(
      non_finite_reference(*make("lame_sphere", {{"a", 1}, {"b", 1e308}, {"p", 1}}, steel), nodes),
      "its displacement at the node (1, 0, 0) is not finite");
  // A beam of length 1e-308 deflects by 0 under its weight: the relative error is 0 / 0.
  const std::vector<double> beam = {0, 0, 0, 1e-308, 0, 0};
  EXPECT_EQ(non_finite_reference(*make("cantilever_gravity", {{"L", 1}, {"h", 0.1}}, steel), beam),
            "");
  EXPECT_EQ(
      non_finite_reference(*make("cantilever_gravity", {{"L", 1e-308}, {"h", 0.1}}, steel), beam),
      "its verification quantity tip_relative_error is not finite");
  // An inner stretch of 1 asks for no pressure: the relative error of the pressure is 0 / 0.
  const ExactSetting rubber = {{material("body", 1e6, 0.45)}, {0, 0, 0}};
  EXPECT_EQ(non_finite_reference(
                *make("neo_hookean_sphere", {{"A", 1}, {"B", 2}, {"stretch", 1}}, rubber), nodes),
            "its verification quantity pressure_relative_error is not finite");
  // A stretch through the centre is a reference all the same (the run reports the inversion).
  EXPECT_EQ(
      non_finite_reference(
          *make("neo_hookean_sphere", {{"A", 1}, {"B", 2}, {"stretch", -0.5}}, rubber), nodes),
      "");
}

TEST(ExactRegistry, TwistedBlockNeedsAnIncompressibleNeoHookeanBody) {
  const ExactParameterMap p = {{"H", 1}, {"twist", 0.5}, {"q", 1}};
  EXPECT_NE(error_of(
                [&] {
                  make("twisted_block", p, {{material("body", 3, 0.4999, 0, "neo_hookean")}, {}});
                },
                "materials")
                .find("exactly incompressible: it needs nu = 0.5"),
            std::string::npos);
  EXPECT_NE(error_of(
                [&] {
                  make("twisted_block", p, {{material("body", 3, 0.5, 0, "mooney_rivlin")}, {}});
                },
                "materials")
                .find("a solution of the neo_hookean law, got 'mooney_rivlin'"),
            std::string::npos);
}

}  // namespace
}  // namespace hs
