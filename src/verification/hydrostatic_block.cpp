#include "verification/hydrostatic_block.hpp"

#include <cmath>

namespace hs {
namespace {

// With bulk modulus K and c = rho g / (3K):
//   u = (-c (H - z) x, -c (H - z) y, -c (H z - z^2/2) - c (x^2 + y^2)/2).
// Quadratic: P2 elements reproduce it to round-off.
class HydrostaticBlock : public ExactSolution {
 public:
  HydrostaticBlock(double H, double c) : H_(H), c_(c) {}
  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double x = X[0], y = X[1], z = X[2], c = s * c_;
    return {-c * (H_ - z) * x, -c * (H_ - z) * y,
            -c * (H_ * z - z * z / 2) - c * (x * x + y * y) / 2};
  }

 private:
  double H_, c_;
};

void check(const ExactParameters& p) { p.positive("H"); }

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const ExactMaterial& m = only_material(setting, "hydrostatic_block");
  const auto& gravity = setting.gravity;
  const double g =
      std::sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
  const double K = m.lambda + 2 * m.mu / 3;
  return std::make_unique<HydrostaticBlock>(p["H"], m.density * g / (3 * K));
}

}  // namespace

ExactSolutionType hydrostatic_block_type() { return {"hydrostatic_block", {"H"}, check, make}; }

}  // namespace hs
