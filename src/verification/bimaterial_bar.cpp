#include "verification/bimaterial_bar.hpp"

namespace hs {
namespace {

// Uniform stress t, so u_x = t x / E1 up to L1 and t L1 / E1 + t (x - L1) / E2 beyond; no
// lateral displacement. Piecewise linear: P1 and P2 reproduce it exactly at any stiffness
// contrast.
class BimaterialBar : public ExactSolution {
 public:
  BimaterialBar(double L1, double t, double E1, double E2) : L1_(L1), t_(t), E1_(E1), E2_(E2) {}
  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double x = X[0];
    const double ux = x <= L1_ ? t_ * x / E1_ : t_ * L1_ / E1_ + t_ * (x - L1_) / E2_;
    return {s * ux, 0, 0};
  }

 private:
  double L1_, t_, E1_, E2_;
};

void check(const ExactParameters& p) { p.positive("L1"); }

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const double E1 = material_of(setting, "stiff", "bimaterial_bar").E;
  const double E2 = material_of(setting, "soft", "bimaterial_bar").E;
  return std::make_unique<BimaterialBar>(p["L1"], p["t"], E1, E2);
}

}  // namespace

ExactSolutionType bimaterial_bar_type() { return {"bimaterial_bar", {"L1", "t"}, check, make}; }

}  // namespace hs
