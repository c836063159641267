// Follower pressure on Tri3/Tri6 faces: closed surfaces carry no net force or moment, the
// forces are -p times the derivative of the enclosed volume, the load stiffness matches finite
// differences, and a flat face carries -p A n.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "element_fixtures.hpp"
#include "fem/element.hpp"

namespace hs {
namespace {

using namespace testing_fixtures;

// Nodal forces of a uniform pressure p on all four outward faces of a tetrahedron.
std::vector<double> closed_surface_forces(int order, const std::vector<double>& x, double p,
                                          std::vector<double>* K = nullptr) {
  const int npe = order == 1 ? 4 : 10, npf = order == 1 ? 3 : 6;
  std::vector<double> f(3 * npe, 0.0), xf(3 * npf), ff(3 * npf), Kf(9 * npf * npf);
  if (K) K->assign(9 * npe * npe, 0.0);
  for (int face = 0; face < 4; ++face) {
    const std::vector<int> nodes = face_nodes(order, face);
    for (int a = 0; a < npf; ++a)
      for (int i = 0; i < 3; ++i) xf[3 * a + i] = x[3 * nodes[a] + i];
    face_pressure(order, xf.data(), p, ff.data(), K ? Kf.data() : nullptr);
    for (int a = 0; a < npf; ++a) {
      for (int i = 0; i < 3; ++i) f[3 * nodes[a] + i] += ff[3 * a + i];
      if (K)
        for (int b = 0; b < npf; ++b)
          for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k)
              (*K)[(3 * nodes[a] + i) * 3 * npe + 3 * nodes[b] + k] +=
                  Kf[(3 * a + i) * 3 * npf + 3 * b + k];
    }
  }
  return f;
}

class FacePressure : public ::testing::TestWithParam<int> {};

TEST_P(FacePressure, ClosedSurfaceHasNoNetForceOrMoment) {
  const int order = GetParam();
  const std::vector<double> x = distorted_tet(order, 0.1);
  const double p = 3.5;
  const std::vector<double> f = closed_surface_forces(order, x, p);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  double scale = 0;
  for (size_t a = 0; a < x.size() / 3; ++a) {
    const Eigen::Vector3d fa(f[3 * a], f[3 * a + 1], f[3 * a + 2]);
    force += fa;
    moment += Eigen::Vector3d(x[3 * a], x[3 * a + 1], x[3 * a + 2]).cross(fa);
    scale = std::max(scale, fa.norm());
  }
  EXPECT_LT(force.norm(), 1e-14 * scale);
  EXPECT_LT(moment.norm(), 1e-14 * scale);
}

TEST_P(FacePressure, ForcesAreMinusPressureTimesVolumeDerivative) {
  // The enclosed volume V(x) (tet_volume of the current nodes) has dV/dx_a = int N_a n da,
  // so f_a = -p dV/dx_a; this ties the face routine to the independent volume routine.
  const int order = GetParam();
  const std::vector<double> x = distorted_tet(order, 0.1);
  const double p = 3.5, h = 1e-6;
  const std::vector<double> f = closed_surface_forces(order, x, p);
  for (size_t d = 0; d < x.size(); ++d) {
    std::vector<double> xp = x, xm = x;
    xp[d] += h;
    xm[d] -= h;
    const double dV = (tet_volume(order, xp.data()) - tet_volume(order, xm.data())) / (2 * h);
    EXPECT_NEAR(f[d], -p * dV, 1e-8) << "dof " << d;
  }
}

TEST_P(FacePressure, EnclosedVolumeOfAClosedSurfaceIsExact) {
  // The faces of a (curved) tetrahedron point out of it: seen as a cavity wall they enclose
  // minus its volume, which tet_volume integrates independently over the solid.
  const int order = GetParam(), npf = order == 1 ? 3 : 6;
  const std::vector<double> x = distorted_tet(order, 0.1);
  double enclosed = 0;
  std::vector<double> xf(3 * npf);
  for (int face = 0; face < 4; ++face) {
    const std::vector<int> nodes = face_nodes(order, face);
    for (int a = 0; a < npf; ++a)
      for (int i = 0; i < 3; ++i) xf[3 * a + i] = x[3 * nodes[a] + i];
    enclosed += face_enclosed_volume(order, xf.data());
  }
  const double solid = tet_volume(order, x.data());
  EXPECT_NEAR(enclosed, -solid, 1e-14 * solid);
  // A translation changes no volume (the faces' shares do change, but not their sum).
  std::vector<double> moved = x;
  for (size_t d = 0; d < moved.size(); ++d) moved[d] += 10.0 * (d % 3 == 1);
  double enclosed_moved = 0;
  for (int face = 0; face < 4; ++face) {
    const std::vector<int> nodes = face_nodes(order, face);
    for (int a = 0; a < npf; ++a)
      for (int i = 0; i < 3; ++i) xf[3 * a + i] = moved[3 * nodes[a] + i];
    enclosed_moved += face_enclosed_volume(order, xf.data());
  }
  EXPECT_NEAR(enclosed_moved, -solid, 1e-12 * solid);
}

TEST_P(FacePressure, LoadStiffnessMatchesFiniteDifferences) {
  const int order = GetParam(), npf = order == 1 ? 3 : 6, n = 3 * npf;
  std::vector<double> x = random_vector(n, 1.0, 21);  // an arbitrary (curved) face
  const double p = -2.0, h = 1e-6;
  std::vector<double> f(n), K(n * n), fp(n), fm(n);
  face_pressure(order, x.data(), p, f.data(), K.data());
  double worst = 0, scale = 0;
  for (double k : K) scale = std::max(scale, std::abs(k));
  for (int d = 0; d < n; ++d) {
    std::vector<double> xp = x, xm = x;
    xp[d] += h;
    xm[d] -= h;
    face_pressure(order, xp.data(), p, fp.data(), nullptr);
    face_pressure(order, xm.data(), p, fm.data(), nullptr);
    for (int i = 0; i < n; ++i)
      worst = std::max(worst, std::abs(K[i * n + d] - (fp[i] - fm[i]) / (2 * h)));
  }
  EXPECT_LT(worst, 1e-8 * scale);
}

TEST_P(FacePressure, ClosedSurfaceLoadStiffnessIsSymmetric) {
  // On a closed surface K = -p d^2 V / dx^2, a Hessian.
  const int order = GetParam(), n = order == 1 ? 12 : 30;
  std::vector<double> K;
  closed_surface_forces(order, distorted_tet(order, 0.1), 3.5, &K);
  double asym = 0, scale = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      asym = std::max(asym, std::abs(K[i * n + j] - K[j * n + i]));
      scale = std::max(scale, std::abs(K[i * n + j]));
    }
  EXPECT_LT(asym, 1e-14 * scale);
}

TEST_P(FacePressure, FlatFaceCarriesMinusPressureTimesAreaAlongItsNormal) {
  const int order = GetParam(), npf = order == 1 ? 3 : 6;
  // Triangle in the plane z = 0.5 x + 0.2 y, area A and unit normal n of its vertices.
  const Eigen::Vector3d v[3] = {{0.1, 0.2, 0.09}, {1.3, 0.4, 0.73}, {0.5, 1.1, 0.47}};
  const Eigen::Vector3d area_normal = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]);
  std::vector<double> x;
  for (const auto& p : v) x.insert(x.end(), {p(0), p(1), p(2)});
  // Tri6: edge nodes moved along their (straight) edges, which keeps the same flat triangle.
  const double shift[3] = {0.1, -0.15, 0.05};
  for (int e = 0; order == 2 && e < 3; ++e) {
    const Eigen::Vector3d m = 0.5 * (v[e] + v[(e + 1) % 3]) + shift[e] * (v[(e + 1) % 3] - v[e]);
    x.insert(x.end(), {m(0), m(1), m(2)});
  }
  const double p = 2.5;
  std::vector<double> f(3 * npf);
  face_pressure(order, x.data(), p, f.data(), nullptr);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int a = 0; a < npf; ++a) total += Eigen::Vector3d(f[3 * a], f[3 * a + 1], f[3 * a + 2]);
  EXPECT_LT((total + p * area_normal).norm(), 1e-14 * p * area_normal.norm());
  // Sign: a positive pressure pushes against the normal, i.e. into the body.
  EXPECT_LT(total.dot(area_normal), 0.0);
}

// The straight triangle of vertices v as a Tri3 (order 1) or Tri6 with its edge nodes at the
// midpoints (order 2), node-major.
std::vector<double> straight_face(const Eigen::Vector3d (&v)[3], int order) {
  std::vector<double> x;
  for (const auto& p : v) x.insert(x.end(), {p(0), p(1), p(2)});
  for (int e = 0; order == 2 && e < 3; ++e) {
    const Eigen::Vector3d m = 0.5 * (v[e] + v[(e + 1) % 3]);
    x.insert(x.end(), {m(0), m(1), m(2)});
  }
  return x;
}

TEST(FacePressureDistribution, ConsistentSharesOnStraightFaces) {
  // int N_a da on a straight triangle: A/3 per Tri3 vertex; 0 per Tri6 vertex, A/3 per edge node.
  const Eigen::Vector3d v[3] = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}};  // A = 1, n = +z
  const std::vector<double> x3 = straight_face(v, 1), x6 = straight_face(v, 2);
  std::vector<double> f3(9), f6(18);
  face_pressure(1, x3.data(), 3.0, f3.data(), nullptr);
  face_pressure(2, x6.data(), 3.0, f6.data(), nullptr);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(f3[3 * a + 2], -1.0, 1e-15);
  for (int a = 0; a < 6; ++a) EXPECT_NEAR(f6[3 * a + 2], a < 3 ? 0.0 : -1.0, 1e-15);
  for (int a = 0; a < 6; ++a) EXPECT_EQ(f6[3 * a] + f6[3 * a + 1], 0.0);
}

// A dead traction t on a flat face: the shares are t int N_a dA (A/3 per Tri3 vertex; 0 per Tri6
// vertex and A/3 per edge node), whatever the face's orientation; the total is t A.
TEST(FaceTraction, ConsistentSharesAndTotalOnFlatFaces) {
  const Eigen::Vector3d v[3] = {{0.1, 0.2, 0.09}, {1.3, 0.4, 0.73}, {0.5, 1.1, 0.47}};
  const double A = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm();
  const std::array<double, 3> t = {0.5, -2.0, 1.25};
  const std::vector<double> x3 = straight_face(v, 1), x6 = straight_face(v, 2);
  std::vector<double> f3(9), f6(18);
  face_traction(1, x3.data(), t, f3.data());
  face_traction(2, x6.data(), t, f6.data());
  for (int i = 0; i < 3; ++i) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(f3[3 * a + i], t[i] * A / 3, 1e-14);
    for (int a = 0; a < 6; ++a) EXPECT_NEAR(f6[3 * a + i], a < 3 ? 0.0 : t[i] * A / 3, 1e-14);
  }
}

INSTANTIATE_TEST_SUITE_P(Orders, FacePressure, ::testing::Values(1, 2));

}  // namespace
}  // namespace hs
