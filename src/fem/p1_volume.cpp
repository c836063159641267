// The current volume of a P1 tetrahedron and its derivatives in the nodal displacements
// (docs/formulation.md, "Nearly incompressible bodies on P1 meshes"). With F = I + H constant
// on the element and v = V det F:
//   dv/du_(a,i) = V cof(F)_ij (grad N_a)_j,                        cof(F) = det F F^-T,
//   d2v/du_(a,i) du_(b,k) = V eps_ikm (F (grad N_a x grad N_b))_m,
// the second from d cof(F)_ij / dF_kl = eps_ikm eps_jln F_mn. Both are polynomials in F, so
// they hold for an inverted element too.
#include <Eigen/Dense>
#include <algorithm>

#include "fem/element.hpp"
#include "materials/tensor.hpp"

namespace hs {

double p1_volume_change(const P1Geometry& g, const double* u, double* grad, double* hess,
                        bool linearised) {
  const Eigen::Map<const Eigen::Matrix<double, 3, 4>> G(g.grad), U(u);
  const Mat3 H = U * G.transpose();
  if (linearised) {
    if (grad) {
      Eigen::Map<Eigen::Matrix<double, 3, 4>> dv(grad);
      dv = g.volume * G;
    }
    if (hess) std::fill(hess, hess + 144, 0.0);
    return g.volume * H.trace();
  }
  const Mat3 F = Mat3::Identity() + H;
  const double J_minus_one = tensor::det_minus_one(H);
  if (grad) {
    // cof(F) column by column: cof(F) e_j = F e_(j+1) x F e_(j+2).
    Mat3 cof;
    for (int j = 0; j < 3; ++j) cof.col(j) = F.col((j + 1) % 3).cross(F.col((j + 2) % 3));
    Eigen::Map<Eigen::Matrix<double, 3, 4>> dv(grad);
    dv = g.volume * cof * G;
  }
  if (hess) {
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const Eigen::Vector3d w = g.volume * F * G.col(a).cross(G.col(b));
        // eps_ikm w_m: the matrix of y -> -(w x y).
        const double block[3][3] = {{0, w(2), -w(1)}, {-w(2), 0, w(0)}, {w(1), -w(0), 0}};
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) hess[(3 * a + i) * 12 + 3 * b + k] = block[i][k];
      }
  }
  return g.volume * J_minus_one;
}

}  // namespace hs
