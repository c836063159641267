// Pieces shared by the element routines of src/fem (element.cpp, fbar_element.cpp): the
// reference Jacobian and the assembly of a quadrature point's 9x9 tangent into the element
// matrix. Internal to src/fem.
#pragma once

#include <Eigen/Dense>
#include <sstream>

#include "common/error.hpp"
#include "fem/element.hpp"
#include "fem/element_tables.hpp"

namespace hs {

template <int NPE>
using NodeMatrix = Eigen::Matrix<double, 3, NPE>;  // column a: a vector at node a

template <int NPE>
constexpr const QuadratureDegrees& degrees() {
  return NPE == 4 ? kP1Degrees : kP2Degrees;
}

[[noreturn]] inline void throw_bad_geometry(const double* X, double detJ) {
  std::ostringstream s;
  s << "tetrahedron with vertices";
  for (int a = 0; a < 4; ++a)
    s << " (" << X[3 * a] << ", " << X[3 * a + 1] << ", " << X[3 * a + 2] << ")";
  s << " has a non-positive reference Jacobian (det J = " << detJ
    << "): the mesh has an inverted or too strongly curved element";
  throw InputError(s.str());
}

// Reference Jacobian J = dX/dxi at a point with reference gradients dN; det J > 0 or throws.
template <int NPE>
double reference_jacobian(const NodeMatrix<NPE>& X, const NodeMatrix<NPE>& dN, Mat3& J) {
  J.noalias() = X * dN.transpose();
  const double detJ = J.determinant();
  if (!(detJ > 0)) throw_bad_geometry(X.data(), detJ);
  return detJ;
}

// Quadrature point q of the rule t on the element X: grad N_a (column a of G) and the point's
// weight times det J, the volume it stands for (returned).
template <int NPE>
double point_gradients(const NodeMatrix<NPE>& X, const TetTables<NPE>& t, size_t q,
                       NodeMatrix<NPE>& G) {
  Mat3 J;
  const double wdV = t.weights[q] * reference_jacobian<NPE>(X, t.dN[q], J);
  G = J.inverse().transpose() * t.dN[q];
  return wdV;
}

// K_ab += wdV sum_jl A_(ij)(kl) G_ja G_lb for the blocks b >= a (K is symmetric: every law
// has an energy, so A has the major symmetry; the lower blocks are mirrored at the end).
template <int NPE>
void add_stiffness(const Tangent& A, const NodeMatrix<NPE>& G, double wdV, double* K) {
  constexpr int n = 3 * NPE;
  for (int a = 0; a < NPE; ++a) {
    Eigen::Matrix<double, 3, 9> C;  // C(i, 3k + l) = wdV sum_j G_ja A(3i + j, 3k + l)
    for (int i = 0; i < 3; ++i)
      C.row(i) =
          wdV * (G(0, a) * A.row(3 * i) + G(1, a) * A.row(3 * i + 1) + G(2, a) * A.row(3 * i + 2));
    for (int b = a; b < NPE; ++b)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          K[(3 * a + i) * n + 3 * b + k] +=
              C(i, 3 * k) * G(0, b) + C(i, 3 * k + 1) * G(1, b) + C(i, 3 * k + 2) * G(2, b);
  }
}

template <int NPE>
void mirror_lower_blocks(double* K) {
  constexpr int n = 3 * NPE;
  for (int a = 0; a < NPE; ++a)
    for (int b = a + 1; b < NPE; ++b)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) K[(3 * b + k) * n + 3 * a + i] = K[(3 * a + i) * n + 3 * b + k];
}

}  // namespace hs
