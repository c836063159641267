// Follower pressure on a Tri3/Tri6 face of the current configuration (docs/formulation.md,
// "Follower pressure"). With the face parametrised by the reference triangle,
// x(s, t) = sum_b x_b N_b(s, t), the area-weighted normal is n da = (x_s x x_t) ds dt, so
//   f_a = -p int N_a (x_s x x_t) ds dt,
// a polynomial integral (degree 1 on Tri3, 4 on Tri6), integrated exactly. Its derivative in
// x_b, using d(x_s x x_t) = dx_s x x_t + x_s x dx_t and v x w = [v]_x w, is
//   K_ab = df_a/dx_b = -p int N_a (N_b,t [x_s]_x - N_b,s [x_t]_x) ds dt,
// the load stiffness (not symmetric on an open surface). This is PETSc's ex77 traction
// p cof(F) N pulled to the current surface.
#include "common/error.hpp"
#include "fem/element.hpp"
#include "fem/element_tables.hpp"

namespace hs {
namespace {

Mat3 cross_matrix(const Eigen::Vector3d& v) {  // [v]_x w = v x w
  Mat3 W;
  W << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return W;
}

template <int NPF>
void pressure(const double* x, double p, double* f, double* K) {
  using FaceMatrix = Eigen::Matrix<double, 3, NPF>;
  constexpr int n = 3 * NPF;
  const auto& t = tri_tables<NPF>(NPF == 3 ? 1 : 4);
  const FaceMatrix xm = Eigen::Map<const FaceMatrix>(x);
  FaceMatrix fm = FaceMatrix::Zero();
  if (K) std::fill(K, K + n * n, 0.0);
  for (size_t q = 0; q < t.weights.size(); ++q) {
    const Eigen::Vector3d xs = xm * t.dN[q].row(0).transpose();
    const Eigen::Vector3d xt = xm * t.dN[q].row(1).transpose();
    const double pw = p * t.weights[q];
    fm.noalias() -= pw * xs.cross(xt) * t.N[q].transpose();
    if (!K) continue;
    const Mat3 Xs = cross_matrix(xs), Xt = cross_matrix(xt);
    for (int a = 0; a < NPF; ++a)
      for (int b = 0; b < NPF; ++b) {
        const Mat3 block = -pw * t.N[q](a) * (t.dN[q](1, b) * Xs - t.dN[q](0, b) * Xt);
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) K[(3 * a + i) * n + 3 * b + k] += block(i, k);
      }
  }
  Eigen::Map<FaceMatrix> f_out(f);
  f_out = fm;
}

template <int NPF>
double enclosed_volume(const double* x) {
  using FaceMatrix = Eigen::Matrix<double, 3, NPF>;
  const auto& t = tri_tables<NPF>(NPF == 3 ? 1 : 4);
  const FaceMatrix xm = Eigen::Map<const FaceMatrix>(x);
  double v = 0;
  for (size_t q = 0; q < t.weights.size(); ++q) {
    const Eigen::Vector3d xq = xm * t.N[q];
    const Eigen::Vector3d xs = xm * t.dN[q].row(0).transpose();
    const Eigen::Vector3d xt = xm * t.dN[q].row(1).transpose();
    v -= t.weights[q] * xq.dot(xs.cross(xt)) / 3;
  }
  return v;
}

template <int NPF>
void traction(const double* X, const std::array<double, 3>& t_ref, double* f) {
  using FaceMatrix = Eigen::Matrix<double, 3, NPF>;
  const auto& t = tri_tables<NPF>(NPF == 3 ? 1 : 4);
  const FaceMatrix Xm = Eigen::Map<const FaceMatrix>(X);
  const Eigen::Vector3d tv(t_ref[0], t_ref[1], t_ref[2]);
  FaceMatrix fm = FaceMatrix::Zero();
  for (size_t q = 0; q < t.weights.size(); ++q) {
    const Eigen::Vector3d Xs = Xm * t.dN[q].row(0).transpose();
    const Eigen::Vector3d Xt = Xm * t.dN[q].row(1).transpose();
    fm.noalias() += (t.weights[q] * Xs.cross(Xt).norm()) * tv * t.N[q].transpose();
  }
  Eigen::Map<FaceMatrix> f_out(f);
  f_out = fm;
}

}  // namespace

void face_traction(int order, const double* X, const std::array<double, 3>& t, double* f) {
  tri_num_nodes(order) == 3 ? traction<3>(X, t, f) : traction<6>(X, t, f);
}

double face_enclosed_volume(int order, const double* x) {
  return tri_num_nodes(order) == 3 ? enclosed_volume<3>(x) : enclosed_volume<6>(x);
}

void face_pressure(int order, const double* x, double p, double* f, double* K) {
  tri_num_nodes(order) == 3 ? pressure<3>(x, p, f, K) : pressure<6>(x, p, f, K);
}

}  // namespace hs
