// Deck-specific verification quantities (see error_norms.hpp).
#include <cmath>

#include "solvers/error_norms.hpp"

namespace hs {
namespace {

double parameter(const Config& c, const std::string& name) { return c.exact.parameters.at(name); }

// Cantilever: mean vertical deflection of the tip face against Euler-Bernoulli (beta < 0.5)
// or the inextensible elastica (larger beta).
void cantilever(const Config& c, const Problem& problem, Vec u, nlohmann::json& out) {
  const double L = parameter(c, "L"), h = parameter(c, "h");
  const auto& m = c.materials.at(0);
  const double g = std::abs(c.gravity[2]);
  const double beta = 12 * m.density * g * L * L * L / (m.E * h * h);
  const double count = problem.sum_over_group("tip", u, [](auto&, auto&) { return 1.0; });
  const double sum_w = problem.sum_over_group("tip", u, [](auto&, auto& v) { return v[2]; });
  const double tip = -sum_w / count;
  const bool small = beta < 0.5;
  const double reference =
      small ? cantilever_tip_deflection(m.density, g, L, h, m.E) : L * elastica_uniform_load(beta);
  out["beta"] = beta;
  out["tip_deflection"] = tip;
  out["tip_reference"] = reference;
  out["reference"] = small ? "euler_bernoulli" : "elastica";
  out["tip_relative_error"] = (tip - reference) / reference;
}

// Neo-Hookean sphere: the inner pressure is the radial reaction on the inner surface over
// its current area (one eighth of a sphere of radius la A).
void neo_hookean_sphere(const Config& c, Problem& problem, Vec u, double s, nlohmann::json& out) {
  const double A = parameter(c, "A"), B = parameter(c, "B");
  const double la = 1 + s * (parameter(c, "stretch") - 1);
  Vec f;
  HS_PETSC(VecDuplicate(u, &f));
  problem.internal_force(u, f);
  const double radial = problem.sum_over_group("inner", f, [](auto& X, auto& v) {
    const double R = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    return (v[0] * X[0] + v[1] * X[1] + v[2] * X[2]) / R;
  });
  HS_PETSC(VecDestroy(&f));
  const auto& m = c.materials.at(0);
  const double area = M_PI * la * la * A * A / 2;
  const double p_over_mu = radial / area / m.mu;
  const double reference = neo_hookean_sphere_pressure(la, A, B);
  out["inner_stretch"] = la;
  out["pressure_over_mu"] = p_over_mu;
  out["pressure_over_mu_reference"] = reference;
  out["pressure_relative_error"] = (p_over_mu - reference) / reference;
}

}  // namespace

nlohmann::json verification_quantities(const Config& config, Problem& problem, Vec u, double s) {
  nlohmann::json out;
  if (config.exact.type == "cantilever_gravity") cantilever(config, problem, u, out);
  if (config.exact.type == "neo_hookean_sphere") neo_hookean_sphere(config, problem, u, s, out);
  return out;
}

}  // namespace hs
