// Element routines on P1/P2 tetrahedra (docs/formulation.md, "Element routines").
// Total-Lagrangian: at each quadrature point of the reference element
//   J = dX/dxi,  grad N_a = J^-T dN_a/dxi,  F = I + H,  H = sum_a u_a (x) grad N_a,
//   r_a = int P grad N_a dV,  K_ab,ik = int sum_jl A_ijkl (grad N_a)_j (grad N_b)_l dV.
// Quadrature degrees: P1 stiffness 1 point (F is constant), P2 stiffness 4 points (degree 2:
// exact for linear elasticity on straight elements); volume, body force and mass use rules
// exact for the polynomial integrands det J, N_a det J and N_a N_b det J of curved P2 elements
// (det J is cubic there).
#include "fem/element.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "fem/element_kernels.hpp"
#include "fem/element_tables.hpp"

namespace hs {
namespace {

// One quadrature point of the internal force: G holds grad N_a in column a, wdV its weight
// times the volume it stands for; adds to R, to K (when given) and to the energy.
template <int NPE>
void add_internal_force_point(const NodeMatrix<NPE>& G, double wdV, const NodeMatrix<NPE>& Um,
                              const MaterialLaw& m, NodeMatrix<NPE>& R, double* K,
                              ElementOutput& out) {
  const Mat3 H = Um * G.transpose();  // F - I
  const StressResult s = stress_from_displacement_gradient(m, H, K != nullptr);
  if (!std::isfinite(s.psi)) out.valid = false;
  out.energy += wdV * s.psi;
  R.noalias() += wdV * s.P * G;
  if (K) add_stiffness<NPE>(s.A, G, wdV, K);
}

// The internal force of an element whose quadrature points are given by `points`, called
// with a function add(G, wdV) that it calls once per point.
template <int NPE, class Points>
ElementOutput integrate_internal_force(const double* u, const MaterialLaw& m, double* r, double* K,
                                       Points points) {
  constexpr int n = 3 * NPE;
  const NodeMatrix<NPE> Um = Eigen::Map<const NodeMatrix<NPE>>(u);
  NodeMatrix<NPE> R = NodeMatrix<NPE>::Zero();
  if (K) std::fill(K, K + n * n, 0.0);
  ElementOutput out;
  points([&](const NodeMatrix<NPE>& G, double wdV) {
    add_internal_force_point<NPE>(G, wdV, Um, m, R, K, out);
  });
  Eigen::Map<NodeMatrix<NPE>> r_out(r);
  r_out = R;
  if (K) mirror_lower_blocks<NPE>(K);
  return out;
}

template <int NPE>
ElementOutput internal_force(const double* X, const double* u, const MaterialLaw& m, double* r,
                             double* K) {
  const auto& t = tet_tables<NPE>(degrees<NPE>().stiffness);
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  return integrate_internal_force<NPE>(u, m, r, K, [&](auto add) {
    NodeMatrix<NPE> G;
    for (size_t q = 0; q < t.weights.size(); ++q) {
      const double wdV = point_gradients<NPE>(Xm, t, q, G);
      add(G, wdV);
    }
  });
}

// f_a = int b(X) N_a dV with the rule of `degree`; b(X) a force per unit reference volume.
template <int NPE, class Density>
void body_force(const double* X, int degree, const Density& b, double* f) {
  const auto& t = tet_tables<NPE>(degree);
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  NodeMatrix<NPE> Fm = NodeMatrix<NPE>::Zero();
  for (size_t q = 0; q < t.weights.size(); ++q) {
    Mat3 J;
    const double wdV = t.weights[q] * reference_jacobian<NPE>(Xm, t.dN[q], J);
    const Eigen::Vector3d Xq = Xm * t.N[q];
    Fm.noalias() += wdV * b(Xq) * t.N[q].transpose();
  }
  Eigen::Map<NodeMatrix<NPE>> f_out(f);
  f_out = Fm;
}

template <int NPE>
void mass(const double* X, double rho, double* M) {
  constexpr int n = 3 * NPE;
  const auto& t = tet_tables<NPE>(degrees<NPE>().mass);
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  Eigen::Matrix<double, NPE, NPE> Ms = Eigen::Matrix<double, NPE, NPE>::Zero();
  for (size_t q = 0; q < t.weights.size(); ++q) {
    Mat3 J;
    const double wdV = t.weights[q] * reference_jacobian<NPE>(Xm, t.dN[q], J);
    Ms.noalias() += (rho * wdV) * t.N[q] * t.N[q].transpose();
  }
  std::fill(M, M + n * n, 0.0);
  for (int a = 0; a < NPE; ++a)
    for (int b = 0; b < NPE; ++b)
      for (int i = 0; i < 3; ++i) M[(3 * a + i) * n + 3 * b + i] = Ms(a, b);
}

template <int NPE>
double volume(const double* X) {
  const auto& t = tet_tables<NPE>(degrees<NPE>().volume);
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  double V = 0;
  for (size_t q = 0; q < t.weights.size(); ++q) {
    Mat3 J;
    V += t.weights[q] * reference_jacobian<NPE>(Xm, t.dN[q], J);
  }
  return V;
}

template <int NPE>
ElementFields fields(const double* X, const double* u, const MaterialLaw& m) {
  const auto& t = tet_tables<NPE>(1);  // the centroid
  const NodeMatrix<NPE> Xm = Eigen::Map<const NodeMatrix<NPE>>(X);
  const NodeMatrix<NPE> Um = Eigen::Map<const NodeMatrix<NPE>>(u);
  Mat3 J;
  reference_jacobian<NPE>(Xm, t.dN[0], J);
  const Mat3 H = Um * (J.inverse().transpose() * t.dN[0]).transpose();
  const Mat3 F = Mat3::Identity() + H;
  ElementFields out;
  out.J = F.determinant();
  out.stress = cauchy_stress(m, F);
  out.von_mises = von_mises(out.stress);
  out.strain = green_lagrange_strain(H);
  return out;
}

template <int NPE>
bool orientation_preserved(const double* X, const double* u) {
  // P1: dx/dxi's columns are x_1 - x_0, x_2 - x_0, x_3 - x_0 (L_0 = 1 - sum xi).
  if constexpr (NPE == 4) {
    double e[3][3];
    for (int a = 0; a < 3; ++a)
      for (int d = 0; d < 3; ++d) e[a][d] = (X[3 * a + 3 + d] + u[3 * a + 3 + d]) - (X[d] + u[d]);
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    return det > 0;  // false for NaN too
  }
  const auto& t = tet_tables<NPE>(1);  // the centroid
  const NodeMatrix<NPE> x =
      Eigen::Map<const NodeMatrix<NPE>>(X) + Eigen::Map<const NodeMatrix<NPE>>(u);
  const Mat3 dx = x * t.dN[0].transpose();
  return dx.determinant() > 0;  // false for NaN too
}

}  // namespace

Mat3 green_lagrange_strain(const Mat3& H) { return 0.5 * (H + H.transpose() + H.transpose() * H); }

std::array<double, 3> principal_values(const Mat3& symmetric) {
  // The closed-form roots (computeDirect) cost a fifth of the iterative solver's time, which
  // was a third of an output step, but lose about 1e-16 / (relative gap) of the largest value
  // to cancellation where two eigenvalues are close (a uniaxial stress has two equal ones):
  // there, the iterative solver.
  Eigen::SelfAdjointEigenSolver<Mat3> solver;
  solver.computeDirect(symmetric, Eigen::EigenvaluesOnly);
  Eigen::Vector3d ascending = solver.eigenvalues();
  const double gap = std::min(ascending[1] - ascending[0], ascending[2] - ascending[1]);
  if (gap < 1e-3 * ascending.cwiseAbs().maxCoeff())
    ascending =
        Eigen::SelfAdjointEigenSolver<Mat3>(symmetric, Eigen::EigenvaluesOnly).eigenvalues();
  return {ascending[2], ascending[1], ascending[0]};
}

P1Geometry tet_p1_geometry(const double* X) {
  const auto& t = tet_tables<4>(1);  // one point: grad N is constant on a P1 element
  const NodeMatrix<4> Xm = Eigen::Map<const NodeMatrix<4>>(X);
  Mat3 J;
  P1Geometry g;
  g.volume = t.weights[0] * reference_jacobian<4>(Xm, t.dN[0], J);
  Eigen::Map<NodeMatrix<4>> grad(g.grad);
  grad = J.inverse().transpose() * t.dN[0];
  return g;
}

ElementOutput tet_internal_force_p1(const P1Geometry& g, const double* u, const MaterialLaw& m,
                                    double* r, double* K) {
  return integrate_internal_force<4>(
      u, m, r, K, [&](auto add) { add(Eigen::Map<const NodeMatrix<4>>(g.grad), g.volume); });
}

ElementOutput tet_internal_force(int order, const double* X, const double* u, const MaterialLaw& m,
                                 double* r, double* K) {
  return tet_num_nodes(order) == 4 ? internal_force<4>(X, u, m, r, K)
                                   : internal_force<10>(X, u, m, r, K);
}

void tet_body_force(int order, const double* X, double rho, const std::array<double, 3>& g,
                    double* f) {
  const Eigen::Vector3d rho_g = rho * Eigen::Vector3d(g[0], g[1], g[2]);
  const auto b = [&](const Eigen::Vector3d&) { return rho_g; };
  tet_num_nodes(order) == 4 ? body_force<4>(X, kP1Degrees.body, b, f)
                            : body_force<10>(X, kP2Degrees.body, b, f);
}

void tet_body_force(int order, const double* X, const ForceDensity& density, double* f) {
  const auto b = [&](const Eigen::Vector3d& Xq) {
    const auto v = density({Xq[0], Xq[1], Xq[2]});
    return Eigen::Vector3d(v[0], v[1], v[2]);
  };
  const int degree = 2 * order + 4;  // a smooth field: the error far below the element's
  tet_num_nodes(order) == 4 ? body_force<4>(X, degree, b, f) : body_force<10>(X, degree, b, f);
}

void tet_mass(int order, const double* X, double rho, double* M) {
  tet_num_nodes(order) == 4 ? mass<4>(X, rho, M) : mass<10>(X, rho, M);
}

double tet_volume(int order, const double* X) {
  return tet_num_nodes(order) == 4 ? volume<4>(X) : volume<10>(X);
}

bool tet_orientation_preserved(int order, const double* X, const double* u) {
  return tet_num_nodes(order) == 4 ? orientation_preserved<4>(X, u)
                                   : orientation_preserved<10>(X, u);
}

ElementFields tet_fields(int order, const double* X, const double* u, const MaterialLaw& m) {
  return tet_num_nodes(order) == 4 ? fields<4>(X, u, m) : fields<10>(X, u, m);
}

}  // namespace hs
