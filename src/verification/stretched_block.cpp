// Held on the planes x = 0, y = 0, z = 0 (each in its normal), pulled along z by the dead
// traction s t on the top: x = (X / sqrt(l), Y / sqrt(l), l Z), l the stretch at load factor s.
// The incompressible neo-Hookean stress sigma = mu (b - I) + q I with the sides free
// (sigma_xx = 0) has q = mu (1 - 1 / l) and sigma_zz = mu (l^2 - 1 / l); the first
// Piola-Kirchhoff P_zz = sigma_zz / l = mu (l - 1 / l^2) = s t fixes l. The mean stress
// -tr(sigma)/3 = -sigma_zz / 3 is the same in every element: an element whose pressure field
// has modes of its own shows them here (docs/verification.md).
#include "verification/stretched_block.hpp"

#include <algorithm>
#include <cmath>

namespace hs {
namespace {

class StretchedBlock : public ExactSolution {
 public:
  StretchedBlock(double t, double mu) : t_(t), mu_(mu) {}

  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double l = incompressible_uniaxial_stretch(s * t_ / mu_), lateral = 1 / std::sqrt(l);
    return {(lateral - 1) * X[0], (lateral - 1) * X[1], (l - 1) * X[2]};
  }

  bool has_pressure() const override { return true; }
  double pressure(const std::array<double, 3>& /*X*/) const override {
    const double l = incompressible_uniaxial_stretch(t_ / mu_);
    return -mu_ * (l * l - 1 / l) / 3;
  }

 private:
  double t_, mu_;
};

void check(const ExactParameters&) {}  // any traction: a push compresses the block

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const ExactMaterial& m = only_incompressible_neo_hookean(setting, "stretched_block");
  return std::make_unique<StretchedBlock>(p["t"], m.mu);
}

}  // namespace

double incompressible_uniaxial_stretch(double t_over_mu) {
  // f(l) = l - 1/l^2 - t/mu increases from -inf at l = 0 to +inf: Newton kept inside the
  // bracket of the root, bisecting where a step would leave it.
  double l = 1, lo = 0, hi = std::max(2.0, 2 + t_over_mu);
  for (int k = 0; k < 200; ++k) {
    const double f = l - 1 / (l * l) - t_over_mu;
    if (f == 0) return l;
    (f > 0 ? hi : lo) = l;
    double next = l - f / (1 + 2 / (l * l * l));
    if (!(next > lo && next < hi)) next = (lo + hi) / 2;
    if (std::abs(next - l) <= 1e-15 * l) return next;
    l = next;
  }
  return l;
}

ExactSolutionType stretched_block_type() { return {"stretched_block", {"t"}, check, make}; }

}  // namespace hs
