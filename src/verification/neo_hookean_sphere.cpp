#include "verification/neo_hookean_sphere.hpp"

#include <cmath>

namespace hs {
namespace {

// Incompressible inflation: r^3 = R^3 + a^3 - A^3, the inner stretch a / A growing linearly in s.
class NeoHookeanSphere : public ExactSolution {
 public:
  NeoHookeanSphere(double A, double B, double stretch, double mu)
      : A_(A), B_(B), stretch_(stretch), mu_(mu) {}

  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double R = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    const double la = inner_stretch(s);
    const double r = std::cbrt(R * R * R + A_ * A_ * A_ * (la * la * la - 1));
    const double k = r / R - 1;
    return {k * X[0], k * X[1], k * X[2]};
  }

  std::vector<MeasureRequest> measures() const override {
    return {{Measure::radial_reaction, "inner"}};
  }

  // The inner pressure is the radial reaction on the inner surface over its current area
  // (one eighth of a sphere of radius la A).
  nlohmann::json verification(const std::vector<double>& measured, double s) const override {
    const double la = inner_stretch(s);
    const double area = M_PI * la * la * A_ * A_ / 2;
    const double p_over_mu = measured.at(0) / area / mu_;
    const double reference = neo_hookean_sphere_pressure(la, A_, B_);
    nlohmann::json out;
    out["inner_stretch"] = la;
    out["pressure_over_mu"] = p_over_mu;
    out["pressure_over_mu_reference"] = reference;
    out["pressure_relative_error"] = (p_over_mu - reference) / reference;
    return out;
  }

 private:
  double inner_stretch(double s) const { return 1 + s * (stretch_ - 1); }
  double A_, B_, stretch_, mu_;
};

// stretch is not bounded: a stretch below 0 pulls the inner surface through the centre,
// which the run must report as inverted elements (tests/solvers/mpi_test_stiff_cases).
void check(const ExactParameters& p) {
  p.positive("A");
  p.greater_than("B", "A");
}

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const ExactMaterial& m = only_material(setting, "neo_hookean_sphere");
  return std::make_unique<NeoHookeanSphere>(p["A"], p["B"], p["stretch"], m.mu);
}

}  // namespace

double neo_hookean_sphere_pressure(double la, double A, double B) {
  const double lb = std::cbrt(1 + (la * la * la - 1) * std::pow(A / B, 3));
  auto g = [](double l) { return 2 / l + 1 / (2 * l * l * l * l); };
  return g(lb) - g(la);
}

ExactSolutionType neo_hookean_sphere_type() {
  return {"neo_hookean_sphere", {"A", "B", "stretch"}, check, make};
}

}  // namespace hs
