#include "verification/cantilever_gravity.hpp"

#include <cmath>

namespace hs {
namespace {

// Euler-Bernoulli: w(x) = q x^2 (6 L^2 - 4 L x + x^2) / (24 E I), q = rho g h^2, I = h^4 / 12,
// for the axis; the tip deflection is compared against Euler-Bernoulli (beta < 0.5) or the
// elastica (larger beta), beta = q L^3 / (E I) at full load.
class Cantilever : public ExactSolution {
 public:
  Cantilever(double L, double h, double E, double density, double g)
      : L_(L), h_(h), E_(E), density_(density), g_(g) {
    const double I = std::pow(h, 4) / 12;
    q_over_EI_ = density * g * h * h / (E * I);
  }

  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double x = X[0];
    return {0, 0, -s * q_over_EI_ * x * x * (6 * L_ * L_ - 4 * L_ * x + x * x) / 24};
  }

  std::vector<MeasureRequest> measures() const override {
    return {{Measure::mean_displacement_z, "tip"}};
  }

  nlohmann::json verification(const std::vector<double>& measured, double) const override {
    const double beta = 12 * density_ * g_ * L_ * L_ * L_ / (E_ * h_ * h_);
    const double tip = -measured.at(0);
    const bool small = beta < 0.5;
    const double reference = small ? cantilever_tip_deflection(density_, g_, L_, h_, E_)
                                   : L_ * elastica_uniform_load(beta);
    nlohmann::json out;
    out["beta"] = beta;
    out["tip_deflection"] = tip;
    out["tip_reference"] = reference;
    out["reference"] = small ? "euler_bernoulli" : "elastica";
    out["tip_relative_error"] = (tip - reference) / reference;
    return out;
  }

 private:
  double L_, h_, E_, density_, g_, q_over_EI_;
};

void check(const ExactParameters& p) {
  p.positive("L");
  p.positive("h");
}

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const ExactMaterial& m = only_material(setting, "cantilever_gravity");
  // Without a load the reference deflection is 0 and the relative error 0/0: refused before
  // the run rather than failing at its end with a NaN summary.json cannot hold.
  if (setting.gravity[2] == 0)
    throw ExactInputError("loads.gravity",
                          "the cantilever_gravity solution needs a gravity component along z");
  if (m.density == 0)
    throw ExactInputError("materials[0].density",
                          "the cantilever_gravity solution needs a density above 0");
  return std::make_unique<Cantilever>(p["L"], p["h"], m.E, m.density, std::abs(setting.gravity[2]));
}

}  // namespace

double cantilever_tip_deflection(double rho, double g, double L, double h, double E) {
  return 3 * rho * g * std::pow(L, 4) / (2 * E * h * h);
}

double elastica_uniform_load(double beta) {
  // EI theta'(s) = M(s) = int_s^L q (x(r) - x(s)) dr gives, with t = s/L,
  //   theta'' = -beta (1 - t) cos(theta),  theta(0) = 0,  theta'(1) = 0,  v/L = int_0^1 sin(theta).
  // Shooting on theta'(0) with classical RK4 and bisection: an independent check of the table.
  auto shoot = [beta](double k0, double* v) {
    const int n = 4000;
    const double h = 1.0 / n;
    double th = 0, w = k0, y = 0;
    auto f = [beta](double t, double th_, double w_, double& dth, double& dw, double& dy) {
      dth = w_;
      dw = -beta * (1 - t) * std::cos(th_);
      dy = std::sin(th_);
    };
    for (int i = 0; i < n; ++i) {
      const double t = i * h;
      double a1, b1, c1, a2, b2, c2, a3, b3, c3, a4, b4, c4;
      f(t, th, w, a1, b1, c1);
      f(t + h / 2, th + h / 2 * a1, w + h / 2 * b1, a2, b2, c2);
      f(t + h / 2, th + h / 2 * a2, w + h / 2 * b2, a3, b3, c3);
      f(t + h, th + h * a3, w + h * b3, a4, b4, c4);
      th += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
      w += h / 6 * (b1 + 2 * b2 + 2 * b3 + b4);
      y += h / 6 * (c1 + 2 * c2 + 2 * c3 + c4);
    }
    *v = y;
    return w;  // theta'(1), to be driven to zero
  };
  // theta (downward inclination) grows from the clamp: theta'(0) = beta int (1 - t) cos(theta)
  // lies in [0, beta], where theta'(1) changes sign.
  double lo = 0, hi = beta, v = 0;
  for (int it = 0; it < 100; ++it) {
    const double mid = (lo + hi) / 2;
    if (shoot(mid, &v) > 0)
      hi = mid;
    else
      lo = mid;
  }
  shoot((lo + hi) / 2, &v);
  return std::abs(v);
}

ExactSolutionType cantilever_gravity_type() {
  return {"cantilever_gravity", {"L", "h"}, check, make};
}

}  // namespace hs
