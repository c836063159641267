// The twist: in cylindrical coordinates about the cube's axis (r, phi, z) -> (r, phi + theta,
// z) with theta = twist g(r) h(z), g = (1 - (r/R)^2)^4 for r < R = H/2 (0 beyond) and
// h = sin^2(pi z / H). The map is a shear in (r, phi, z), so det F = 1 everywhere; it is the
// identity on the cube's faces (g = 0 on the sides, h = 0 at top and bottom), with F = I
// there (g and h are flat there too), so that u = 0 and P = q I = 0 on every face: the
// body held at its bottom alone, its other faces free, has this solution, and the free faces
// fix the pressure. In Cartesian terms
//   F = Q(theta) (I + v (x) grad theta),  v = (-(X2 - c), X1 - c, 0),  c = H / 2,
// Q the rotation about the axis (det = 1 + grad theta . v = 1: grad theta is radial and axial).
// The incompressible neo-Hookean stress with a volumetric stress q of our choosing,
//   P = mu (F - F^-T) + q F^-T,  q = q0 mu sin(pi X1 / H) sin(pi X2 / H) sin(pi X3 / H),
// is what the compressible law with its volume multiplier gives at J = 1 (mu (F - F^-T) from
// the law, q from the multiplier); the body force B = -Div P makes it an equilibrium. B is taken
// by central differences of P (step 1e-5 H: its error ~1e-10 of mu / H, far below the
// discretisation's); the mean stress -tr(sigma)/3 = -mu (tr b - 3) / 3 - q is the reference of
// the pressure.
#include "verification/twisted_block.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace hs {
namespace {

class TwistedBlock : public ExactSolution {
 public:
  TwistedBlock(double H, double twist, double q0, double mu)
      : H_(H), c_(H / 2), twist_(twist), q0_(q0), mu_(mu) {}

  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double theta = s * twist_ * radial(X) * axial(X[2]);
    const double x = X[0] - c_, y = X[1] - c_;
    const double ct = std::cos(theta), st = std::sin(theta);
    return {ct * x - st * y - x, st * x + ct * y - y, 0};
  }

  bool has_body_force() const override { return true; }
  std::array<double, 3> body_force(const std::array<double, 3>& X) const override {
    const double d = 1e-5 * H_;
    Eigen::Vector3d div = Eigen::Vector3d::Zero();
    for (int j = 0; j < 3; ++j) {
      std::array<double, 3> p = X, m = X;
      p[j] += d;
      m[j] -= d;
      div += (stress(p).col(j) - stress(m).col(j)) / (2 * d);
    }
    return {-div[0], -div[1], -div[2]};
  }

  bool has_pressure() const override { return true; }
  double pressure(const std::array<double, 3>& X) const override {
    const Eigen::Matrix3d F = deformation_gradient(X);
    return -mu_ * ((F * F.transpose()).trace() - 3) / 3 - volumetric_stress(X);
  }

 private:
  // g(r) and g'(r) / r, 0 outside the inscribed cylinder.
  double radial(const std::array<double, 3>& X) const {
    const double t = 1 - rho2(X);
    return t > 0 ? t * t * t * t : 0;
  }
  double radial_slope_over_r(const std::array<double, 3>& X) const {
    const double t = 1 - rho2(X), R = H_ / 2;
    return t > 0 ? -8 * t * t * t / (R * R) : 0;
  }
  double rho2(const std::array<double, 3>& X) const {
    const double x = X[0] - c_, y = X[1] - c_, R = H_ / 2;
    return (x * x + y * y) / (R * R);
  }
  double axial(double z) const { return std::pow(std::sin(M_PI * z / H_), 2); }
  double axial_slope(double z) const { return M_PI / H_ * std::sin(2 * M_PI * z / H_); }

  Eigen::Matrix3d deformation_gradient(const std::array<double, 3>& X) const {
    const double x = X[0] - c_, y = X[1] - c_;
    const double g = radial(X), h = axial(X[2]), gr = radial_slope_over_r(X);
    const double theta = twist_ * g * h;
    const Eigen::Vector3d grad(twist_ * gr * h * x, twist_ * gr * h * y,
                               twist_ * g * axial_slope(X[2]));
    const Eigen::Vector3d v(-y, x, 0);
    const Eigen::Matrix3d Q = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return Q * (Eigen::Matrix3d::Identity() + v * grad.transpose());
  }
  double volumetric_stress(const std::array<double, 3>& X) const {
    const double k = M_PI / H_;
    return q0_ * mu_ * std::sin(k * X[0]) * std::sin(k * X[1]) * std::sin(k * X[2]);
  }
  Eigen::Matrix3d stress(const std::array<double, 3>& X) const {
    const Eigen::Matrix3d F = deformation_gradient(X);
    const Eigen::Matrix3d F_invT = F.inverse().transpose();
    return mu_ * (F - F_invT) + volumetric_stress(X) * F_invT;
  }

  double H_, c_, twist_, q0_, mu_;
};

void check(const ExactParameters& p) { p.positive("H"); }

std::unique_ptr<ExactSolution> make(const ExactParameters& p, const ExactSetting& setting) {
  const ExactMaterial& m = only_incompressible_neo_hookean(setting, "twisted_block");
  return std::make_unique<TwistedBlock>(p["H"], p["twist"], p["q"], m.mu);
}

}  // namespace

ExactSolutionType twisted_block_type() {
  return {"twisted_block", {"H", "twist", "q"}, check, make};
}

}  // namespace hs
