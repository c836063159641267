// The F-bar element (docs/formulation.md, "Nearly incompressible bodies: the F-bar element").
// At every quadrature point the law sees
//   Fbar = (Jbar / J)^(1/3) F,   Jbar = v / V = (1/V) sum_q W_q J_q,
// the element's volume ratio, so the whole element carries one volumetric constraint (det
// Fbar = Jbar): a P2 element keeps its 30 displacements against one constraint instead of
// four, which is what frees it from locking. The energy is Pi = sum_q W_q psi(Fbar_q), and
// its derivatives follow from e_q(F_q, Jbar) = psi(Fbar(F_q, Jbar)) by the chain rule:
//   M_q = dFbar/dF = beta (Id - 1/3 F (x) F^-T),   dFbar/dJbar = Fbar / (3 Jbar),
//   de/dF = beta P - tau F^-T,   de/dJbar = tau / Jbar,   tau = Pbar : Fbar / 3,
//   dJbar/dF_q = (W_q / V) J_q F_q^-T,
//   r = sum_q W_q (beta P - tau F^-T) G_q + (T / Jbar) b,   T = sum_q W_q tau_q,
// with b = dJbar/du. The tangent is a per-point 9x9 part (assembled as any law's) plus the
// rank-two coupling through Jbar, c b^T + b c^T + D b b^T (the derivation beside each term).
// P1 elements have one point and J = Jbar: there F-bar is the displacement element.
// A small-strain law (linear elasticity) gets the linearisation instead, B-bar: Hbar = H +
// (theta_mean - tr H)/3 I, theta_mean = (1/V) sum_q W_q tr H_q, so that the problem stays
// linear (F-bar's Fbar is not linear in u even where the law is).
#include <array>
#include <cmath>
#include <limits>

#include "fem/element_kernels.hpp"
#include "fem/element_tables.hpp"
#include "materials/tensor.hpp"
#include "materials/volumetric_term.hpp"

namespace hs {
namespace {

using Vec9 = Eigen::Matrix<double, 9, 1>;

// The displacement element's rules (P1 1 point, P2 4). The F-bar P2 element has, besides the
// rigid modes, three zero-energy modes of its own, whatever the rule: the special conformal
// fields u = 2 (a.y) y - |y|^2 a (y = x - centroid), whose strain is purely volumetric with zero
// mean. In a mesh they are not: no continuous field is such a mode on every element at once
// (deviatoric Korn inequality), which tests/fem/test_patch.cpp checks on an assembled mesh.
template <int NPE>
constexpr int fbar_degree() {
  return degrees<NPE>().stiffness;
}
constexpr int kMaxPoints = 8;

// What the second pass needs of a quadrature point.
template <int NPE>
struct FbarPoint {
  NodeMatrix<NPE> G;  // grad N_a in column a
  double W = 0;       // weight times the volume it stands for
  Mat3 H;             // F - I
  double J_minus_one = 0;
  Mat3 FinvT;
};

template <int NPE>
ElementOutput inverted_element(double* r, double* K) {
  constexpr int n = 3 * NPE;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::fill(r, r + n, nan);
  if (K) std::fill(K, K + n * n, nan);
  return {false, std::numeric_limits<double>::infinity()};
}

// `newton`: the split law and Newton's pressure (element.hpp, FbarNewtonPressure); m is then
// the law less its volumetric term.
template <int NPE>
ElementOutput fbar_internal_force(const double* X, const double* u, const MaterialLaw& m, double* r,
                                  double* K, FbarNewtonPressure* newton = nullptr) {
  constexpr int n = 3 * NPE;
  const auto& t = tet_tables<NPE>(fbar_degree<NPE>());
  const int nq = static_cast<int>(t.weights.size());
  if (nq > kMaxPoints) throw std::logic_error("F-bar element: too many quadrature points");
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  const NodeMatrix<NPE> Um = Eigen::Map<const NodeMatrix<NPE>>(u);

  // Pass 1: kinematics, the volume ratio Jbar and b = dJbar/du.
  std::array<FbarPoint<NPE>, kMaxPoints> pts;
  double V = 0, v_minus_V = 0;
  for (int q = 0; q < nq; ++q) {
    FbarPoint<NPE>& p = pts[q];
    p.W = point_gradients<NPE>(Xm, t, q, p.G);
    p.H = Um * p.G.transpose();
    p.J_minus_one = tensor::det_minus_one(p.H);
    if (!(1.0 + p.J_minus_one > 0)) return inverted_element<NPE>(r, K);
    p.FinvT = (Mat3::Identity() + p.H).inverse().transpose();
    V += p.W;
    v_minus_V += p.W * p.J_minus_one;
  }
  const double Jbar_minus_one = v_minus_V / V;  // Jbar - 1 without the cancellation in v/V - 1
  const double Jbar = 1.0 + Jbar_minus_one;
  if (!(Jbar > 0)) return inverted_element<NPE>(r, K);
  NodeMatrix<NPE> b = NodeMatrix<NPE>::Zero();
  for (int q = 0; q < nq; ++q)
    b.noalias() += (pts[q].W * (1.0 + pts[q].J_minus_one) / V) * pts[q].FinvT * pts[q].G;

  // Pass 2: the law at Fbar, the residual and the per-point tangent.
  ElementOutput out;
  NodeMatrix<NPE> R = NodeMatrix<NPE>::Zero(), c = NodeMatrix<NPE>::Zero();
  double T = 0, D = 0;
  if (K) std::fill(K, K + n * n, 0.0);
  std::array<Tangent, kMaxPoints> Tq;
  for (int q = 0; q < nq; ++q) {
    const FbarPoint<NPE>& p = pts[q];
    const double J = 1.0 + p.J_minus_one;
    // beta - 1 = (Jbar/J)^(1/3) - 1 from Jbar - J, exact for small strains.
    const double beta_minus_one =
        std::expm1(std::log1p((Jbar_minus_one - p.J_minus_one) / J) / 3.0);
    const double beta = 1.0 + beta_minus_one;
    const Mat3 Hbar = beta * p.H + beta_minus_one * Mat3::Identity();
    const Mat3 Fbar = Mat3::Identity() + Hbar;
    const StressResult s = m.stress(Hbar, K != nullptr);
    if (!std::isfinite(s.psi)) return inverted_element<NPE>(r, K);
    const double tau = (s.P.array() * Fbar.array()).sum() / 3.0;
    out.energy += p.W * s.psi;
    R.noalias() += p.W * (beta * s.P - tau * p.FinvT) * p.G;
    T += p.W * tau;
    if (!K) continue;
    const Vec9 f = tensor::flatten(Mat3::Identity() + p.H), mv = tensor::flatten(p.FinvT);
    const Vec9 pv = tensor::flatten(s.P), fbar = tensor::flatten(Fbar);
    // M = dFbar/dF; d2e/dF2 = M^T A M + sum_ij Pbar_ij d2Fbar_ij/dF2, the second term
    // tau/3 m m^T + tau D - beta/3 (m p^T + p m^T) with D_ijkl = F^-T_il F^-T_kj (= -dF^-T/dF).
    const Tangent M = beta * (Tangent::Identity() - (1.0 / 3.0) * f * mv.transpose());
    Tangent& A9 = Tq[q];
    A9 = M.transpose() * s.A * M + (tau / 3.0) * mv * mv.transpose() -
         (beta / 3.0) * (mv * pv.transpose() + pv * mv.transpose());
    tensor::add_il_kj(A9, tau, p.FinvT, p.FinvT);
    A9 *= p.W;
    // d2e/dF dJbar = M^T (p + A fbar) / (3 Jbar); d2e/dJbar2 = (fbar A fbar - 6 tau) / (9 Jbar^2).
    const Vec9 cq = M.transpose() * (pv + s.A * fbar) * (p.W / (3.0 * Jbar));
    c.noalias() += Eigen::Map<const Mat3>(cq.data()).transpose() * p.G;
    D += p.W * (fbar.dot(s.A * fbar) - 6.0 * tau) / (9.0 * Jbar * Jbar);
  }
  double S1 = T / Jbar;  // dPi/dJbar
  double S1_tangent = S1;
  if (newton) {  // the volumetric term V [lambda ln Jbar + k/2 (ln Jbar)^2], of Jbar alone
    const VolumetricValues vol = volumetric_function(newton->k, Jbar_minus_one);
    const double ln_Jbar = std::log1p(Jbar_minus_one);
    const double q = newton->lambda + (newton->exact ? ln_Jbar * newton->k : newton->q);
    out.energy += V * (vol.U + newton->lambda * ln_Jbar);
    S1 += V * (vol.dU + newton->lambda / Jbar);
    S1_tangent += V * q / Jbar;
    D += V * (newton->k - q) / (Jbar * Jbar);
    newton->ln_Jbar = ln_Jbar;
    Eigen::Map<NodeMatrix<NPE>>(newton->g) = b / Jbar;
  }
  R.noalias() += S1 * b;
  Eigen::Map<NodeMatrix<NPE>> r_out(r);
  r_out = R;
  if (!K) return out;

  // The per-point parts, with S1 d2Jbar/dF_q^2 = S1 (W_q/V) J_q (m m^T - D) added to each.
  for (int q = 0; q < nq; ++q) {
    const FbarPoint<NPE>& p = pts[q];
    const double a = S1_tangent * p.W * (1.0 + p.J_minus_one) / V;
    tensor::add_outer(Tq[q], a, p.FinvT, p.FinvT);
    tensor::add_il_kj(Tq[q], -a, p.FinvT, p.FinvT);
    add_stiffness<NPE>(Tq[q], p.G, 1.0, K);
  }
  mirror_lower_blocks<NPE>(K);
  // The coupling through Jbar: K += c b^T + b c^T + D b b^T.
  Eigen::Map<Eigen::Matrix<double, n, n, Eigen::RowMajor>> Km(K);
  const Eigen::Map<const Eigen::Matrix<double, n, 1>> bv(b.data()), cv(c.data());
  Km.noalias() += cv * bv.transpose() + bv * cv.transpose() + D * bv * bv.transpose();
  return out;
}

// B-bar: the same structure with the kinematic map linear, M = Id - 1/3 I (x) I, so the
// per-point tangent is M^T A M and the coupling through theta_mean c b^T + b c^T + D b b^T
// with b = d theta_mean/du, c = sum_q W_q/3 M^T A I G_q, D = sum_q W_q I : A : I / 9.
template <int NPE>
ElementOutput bbar_internal_force(const double* X, const double* u, const MaterialLaw& m, double* r,
                                  double* K) {
  constexpr int n = 3 * NPE;
  const auto& t = tet_tables<NPE>(fbar_degree<NPE>());
  const int nq = static_cast<int>(t.weights.size());
  if (nq > kMaxPoints) throw std::logic_error("B-bar element: too many quadrature points");
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  const NodeMatrix<NPE> Um = Eigen::Map<const NodeMatrix<NPE>>(u);
  std::array<NodeMatrix<NPE>, kMaxPoints> G;
  std::array<double, kMaxPoints> W;
  std::array<Mat3, kMaxPoints> H;
  double V = 0, theta = 0;
  NodeMatrix<NPE> b = NodeMatrix<NPE>::Zero();
  for (int q = 0; q < nq; ++q) {
    W[q] = point_gradients<NPE>(Xm, t, q, G[q]);
    H[q] = Um * G[q].transpose();
    V += W[q];
    theta += W[q] * H[q].trace();
    b.noalias() += W[q] * G[q];  // Mat3::Identity() * G, divided by V below
  }
  theta /= V;
  b /= V;
  const Vec9 iv = tensor::flatten(Mat3::Identity());
  const Tangent M = Tangent::Identity() - (1.0 / 3.0) * iv * iv.transpose();
  ElementOutput out;
  NodeMatrix<NPE> R = NodeMatrix<NPE>::Zero(), c = NodeMatrix<NPE>::Zero();
  double S = 0, D = 0;
  if (K) std::fill(K, K + n * n, 0.0);
  for (int q = 0; q < nq; ++q) {
    const Mat3 Hbar = H[q] + (theta - H[q].trace()) / 3.0 * Mat3::Identity();
    const StressResult s = m.stress(Hbar, K != nullptr);
    out.energy += W[q] * s.psi;
    R.noalias() += W[q] * (s.P - s.P.trace() / 3.0 * Mat3::Identity()) * G[q];
    S += W[q] * s.P.trace() / 3.0;
    if (!K) continue;
    const Tangent A9 = W[q] * M.transpose() * s.A * M;
    add_stiffness<NPE>(A9, G[q], 1.0, K);
    const Vec9 cq = M.transpose() * (s.A * iv) * (W[q] / 3.0);
    c.noalias() += Eigen::Map<const Mat3>(cq.data()).transpose() * G[q];
    D += W[q] * iv.dot(s.A * iv) / 9.0;
  }
  R.noalias() += S * b;
  Eigen::Map<NodeMatrix<NPE>> r_out(r);
  r_out = R;
  if (!K) return out;
  mirror_lower_blocks<NPE>(K);
  Eigen::Map<Eigen::Matrix<double, n, n, Eigen::RowMajor>> Km(K);
  const Eigen::Map<const Eigen::Matrix<double, n, 1>> bv(b.data()), cv(c.data());
  Km.noalias() += cv * bv.transpose() + bv * cv.transpose() + D * bv * bv.transpose();
  return out;
}

// Jbar - 1 of an element on the rule of fbar_internal_force, or (small_strain) its
// linearisation theta_mean, the mean of tr H.
template <int NPE>
double volume_ratio_minus_one(const NodeMatrix<NPE>& Xm, const NodeMatrix<NPE>& Um,
                              bool small_strain) {
  const auto& t = tet_tables<NPE>(fbar_degree<NPE>());
  double V = 0, v_minus_V = 0;
  for (size_t q = 0; q < t.weights.size(); ++q) {
    NodeMatrix<NPE> G;
    const double W = point_gradients<NPE>(Xm, t, q, G);
    const Mat3 H = Um * G.transpose();
    V += W;
    v_minus_V += W * (small_strain ? H.trace() : tensor::det_minus_one(H));
  }
  return v_minus_V / V;
}

template <int NPE>
ElementFields fbar_fields(const double* X, const double* u, const MaterialLaw& m) {
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  const NodeMatrix<NPE> Um = Eigen::Map<const NodeMatrix<NPE>>(u);
  NodeMatrix<NPE> G;
  point_gradients<NPE>(Xm, tet_tables<NPE>(1), 0, G);  // the centroid
  const Mat3 H = Um * G.transpose();
  const double mean = volume_ratio_minus_one<NPE>(Xm, Um, m.small_strain());
  ElementFields out;
  out.J = 1.0 + mean;
  const Mat3 F = Mat3::Identity() + H;
  const Mat3 Fbar = m.small_strain() ? Mat3(F + (mean - H.trace()) / 3.0 * Mat3::Identity())
                                     : Mat3(std::cbrt(out.J / F.determinant()) * F);
  out.stress = cauchy_stress(m, Fbar);
  out.von_mises = von_mises(out.stress);
  out.strain = green_lagrange_strain(Fbar - Mat3::Identity());
  return out;
}

}  // namespace

ElementFields tet_fields_fbar(int order, const double* X, const double* u, const MaterialLaw& m) {
  return tet_num_nodes(order) == 4 ? fbar_fields<4>(X, u, m) : fbar_fields<10>(X, u, m);
}

double tet_volume_ratio_minus_one_fbar(int order, const double* X, const double* u) {
  if (tet_num_nodes(order) == 4)
    return volume_ratio_minus_one<4>(Eigen::Map<const NodeMatrix<4>>(X),
                                     Eigen::Map<const NodeMatrix<4>>(u), false);
  return volume_ratio_minus_one<10>(Eigen::Map<const NodeMatrix<10>>(X),
                                    Eigen::Map<const NodeMatrix<10>>(u), false);
}

ElementOutput tet_internal_force_fbar(int order, const double* X, const double* u,
                                      FbarNewtonPressure& p, double* r, double* K) {
  return tet_num_nodes(order) == 4 ? fbar_internal_force<4>(X, u, *p.rest, r, K, &p)
                                   : fbar_internal_force<10>(X, u, *p.rest, r, K, &p);
}

ElementOutput tet_internal_force_fbar(int order, const double* X, const double* u,
                                      const MaterialLaw& m, double* r, double* K) {
  if (m.small_strain())
    return tet_num_nodes(order) == 4 ? bbar_internal_force<4>(X, u, m, r, K)
                                     : bbar_internal_force<10>(X, u, m, r, K);
  return tet_num_nodes(order) == 4 ? fbar_internal_force<4>(X, u, m, r, K)
                                   : fbar_internal_force<10>(X, u, m, r, K);
}

}  // namespace hs
