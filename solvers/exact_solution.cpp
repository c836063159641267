#include "solvers/exact_solution.hpp"

#include <cmath>
#include <functional>

#include "common/error.hpp"

namespace hs {
namespace {

double parameter(const Config& c, const std::string& name) {
  auto it = c.exact.parameters.find(name);
  if (it == c.exact.parameters.end())
    throw InputError(c.deck_path + ": exact.parameters." + name + ": required by exact solution '" +
                     c.exact.type + "'");
  return it->second;
}

const MaterialConfig& only_material(const Config& c) {
  if (c.materials.size() != 1)
    throw InputError(c.deck_path + ": materials: exact solution '" + c.exact.type +
                     "' needs exactly one material");
  return c.materials[0];
}

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

// Block 0 <= z <= H under gravity -g e_z, stress -rho g (H - z) I, bulk modulus K:
//   u = (-c (H - z) x, -c (H - z) y, -c (H z - z^2/2) - c (x^2 + y^2)/2), c = rho g / (3K).
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

// Incompressible inflation: r^3 = R^3 + a^3 - A^3, inner stretch growing linearly in s.
class NeoHookeanSphere : public ExactSolution {
 public:
  NeoHookeanSphere(double A, double stretch) : A_(A), stretch_(stretch) {}
  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double R = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    const double la = 1 + s * (stretch_ - 1);
    const double r = std::cbrt(R * R * R + A_ * A_ * A_ * (la * la * la - 1));
    const double k = r / R - 1;
    return {k * X[0], k * X[1], k * X[2]};
  }

 private:
  double A_, stretch_;
};

// Euler-Bernoulli cantilever along +x, clamped at x = 0, gravity along -z, square section h
// centred on the axis: w(x) = q x^2 (6 L^2 - 4 L x + x^2) / (24 E I), q = rho g h^2.
// Only the deflection of the axis is exact; the L2 error is not meaningful for this deck, so
// the deck compares the tip deflection instead (summary error.tip_relative).
class Cantilever : public ExactSolution {
 public:
  Cantilever(double q_over_EI, double L) : k_(q_over_EI), L_(L) {}
  std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const override {
    const double x = X[0];
    return {0, 0, -s * k_ * x * x * (6 * L_ * L_ - 4 * L_ * x + x * x) / 24};
  }

 private:
  double k_, L_;
};

// Two materials in series along x (nu = 0), pulled by a traction t at the end: uniform
// stress t, so u_x = t x / E1 up to L1 and t L1 / E1 + t (x - L1) / E2 beyond; no lateral
// displacement. Piecewise linear: P1 and P2 reproduce it exactly at any stiffness contrast.
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

const MaterialConfig& material_of(const Config& c, const std::string& group) {
  for (const auto& m : c.materials)
    if (m.group == group) return m;
  throw InputError(c.deck_path + ": materials: exact solution '" + c.exact.type +
                   "' needs a material for group '" + group + "'");
}

}  // namespace

double lame_sphere_radial_displacement(double r, double a, double b, double p, double E,
                                       double nu) {
  const double a3 = a * a * a, b3 = b * b * b;
  return p * a3 / (E * (b3 - a3)) * ((1 - 2 * nu) * r + (1 + nu) * b3 / (2 * r * r));
}

double neo_hookean_sphere_pressure(double la, double A, double B) {
  const double lb = std::cbrt(1 + (la * la * la - 1) * std::pow(A / B, 3));
  auto g = [](double l) { return 2 / l + 1 / (2 * l * l * l * l); };
  return g(lb) - g(la);
}

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

std::unique_ptr<ExactSolution> make_exact_solution(const Config& c) {
  const std::string& type = c.exact.type;
  if (type.empty() || type == "none") return nullptr;
  if (type == "lame_sphere") {
    const auto& m = only_material(c);
    return std::make_unique<LameSphere>(parameter(c, "a"), parameter(c, "b"), parameter(c, "p"),
                                        m.E, m.nu);
  }
  if (type == "hydrostatic_block") {
    const auto& m = only_material(c);
    const double g = std::sqrt(c.gravity[0] * c.gravity[0] + c.gravity[1] * c.gravity[1] +
                               c.gravity[2] * c.gravity[2]);
    const double K = m.lambda + 2 * m.mu / 3;
    return std::make_unique<HydrostaticBlock>(parameter(c, "H"), m.density * g / (3 * K));
  }
  if (type == "neo_hookean_sphere")
    return std::make_unique<NeoHookeanSphere>(parameter(c, "A"), parameter(c, "stretch"));
  if (type == "cantilever_gravity") {
    const auto& m = only_material(c);
    const double h = parameter(c, "h"), L = parameter(c, "L");
    const double g = std::abs(c.gravity[2]);
    const double I = std::pow(h, 4) / 12;
    return std::make_unique<Cantilever>(m.density * g * h * h / (m.E * I), L);
  }
  if (type == "bimaterial_bar")
    return std::make_unique<BimaterialBar>(parameter(c, "L1"), parameter(c, "t"),
                                           material_of(c, "stiff").E, material_of(c, "soft").E);
  throw InputError(c.deck_path + ": exact.type: unknown exact solution '" + type + "'");
}

}  // namespace hs
