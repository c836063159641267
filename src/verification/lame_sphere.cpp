#include "verification/lame_sphere.hpp"

#include <cmath>

namespace hs {
namespace {

// Linear in s: u(X; s) = s u(X).
class LameSphere : public ExactSolution {
 public:
  LameSphere(double a, double b, double p, double E, double nu)
      : a_(a), b_(b), p_(p), E_(E), nu_(nu) {}
  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double r = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    const double ur = s * lame_sphere_radial_displacement(r, a_, b_, p_, E_, nu_);
    return {ur * X[0] / r, ur * X[1] / r, ur * X[2] / r};
  }

 private:
  double a_, b_, p_, E_, nu_;
};

void check(const ExactParameters& p) {
  p.positive("a");
  p.greater_than("b", "a");
}

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const ExactMaterial& m = only_material(setting, "lame_sphere");
  return std::make_unique<LameSphere>(p["a"], p["b"], p["p"], m.E, m.nu);
}

}  // namespace

double lame_sphere_radial_displacement(double r, double a, double b, double p, double E,
                                       double nu) {
  const double a3 = a * a * a, b3 = b * b * b;
  return p * a3 / (E * (b3 - a3)) * ((1 - 2 * nu) * r + (1 + nu) * b3 / (2 * r * r));
}

ExactSolutionType lame_sphere_type() { return {"lame_sphere", {"a", "b", "p"}, check, make}; }

}  // namespace hs
