// Patch tests on a distorted mesh of a cube: a linear displacement gives the exact constant
// stress, i.e. nodal forces equal to the boundary integrals of its traction (every material,
// P1 and P2); P2 reproduces the quadratic hydrostatic field of a block under gravity.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "../materials/material_fixtures.hpp"
#include "element_fixtures.hpp"
#include "fem/element.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {
namespace test_patch {

using namespace testing_fixtures;

// Sum of the element internal forces (minus body forces if rho g != 0) over the mesh.
std::vector<Eigen::Vector3d> assemble(const CubeMesh& mesh, const std::vector<Eigen::Vector3d>& u,
                                      const MaterialLaw& m, const Eigen::Vector3d& rho_g) {
  std::vector<Eigen::Vector3d> r(mesh.x.size(), Eigen::Vector3d::Zero());
  const size_t npe = mesh.tets[0].size();
  std::vector<double> re(3 * npe), fe(3 * npe);
  for (const auto& tet : mesh.tets) {
    const std::vector<double> X = gather(mesh.x, tet), ue = gather(u, tet);
    EXPECT_TRUE(tet_internal_force(mesh.order, X.data(), ue.data(), m, re.data(), nullptr).valid);
    tet_body_force(mesh.order, X.data(), 1.0, {rho_g(0), rho_g(1), rho_g(2)}, fe.data());
    for (size_t a = 0; a < npe; ++a)
      for (int i = 0; i < 3; ++i) r[tet[a]](i) += re[3 * a + i] - fe[3 * a + i];
  }
  return r;
}

struct Case {
  std::string model;
  int order;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.model << " P" << c.order; }

class LinearPatch : public ::testing::TestWithParam<Case> {};

TEST_P(LinearPatch, NodalForcesAreTheBoundaryTractionsOfTheConstantStress) {
  const CubeMesh mesh = cube_mesh(GetParam().order);
  ASSERT_EQ(mesh.boundary_faces.size(), 48u);  // 6 faces x 4 squares x 2 triangles
  const MaterialLaw& m = material_fixtures::law(GetParam().model);
  Eigen::Matrix3d H;  // u = H X, F = I + H
  H << 0.12, -0.05, 0.08, 0.03, -0.1, 0.04, -0.06, 0.09, 0.15;
  std::vector<Eigen::Vector3d> u;
  for (const auto& x : mesh.x) u.push_back(H * x);
  const std::vector<Eigen::Vector3d> r = assemble(mesh, u, m, Eigen::Vector3d::Zero());

  // Reference: r_a = int P grad N_a dV = sum over boundary faces of P N int N_a dA, where
  // int N_a dA is A/3 for the vertices of a Tri3 and 0 (vertices) or A/3 (edge nodes) on a
  // flat Tri6.
  const Eigen::Matrix3d P = stress(m, Eigen::Matrix3d::Identity() + H).P;
  std::vector<Eigen::Vector3d> expected(mesh.x.size(), Eigen::Vector3d::Zero());
  for (const auto& f : mesh.boundary_faces) {
    const Eigen::Vector3d area_normal =
        0.5 * (mesh.x[f[1]] - mesh.x[f[0]]).cross(mesh.x[f[2]] - mesh.x[f[0]]);
    const Eigen::Vector3d third = P * area_normal / 3.0;
    for (size_t a = (mesh.order == 1 ? 0 : 3); a < f.size(); ++a) expected[f[a]] += third;
  }
  double scale = 0;
  for (const auto& e : expected) scale = std::max(scale, e.norm());
  for (size_t a = 0; a < mesh.x.size(); ++a)
    EXPECT_LT((r[a] - expected[a]).norm(), 1e-13 * scale)
        << "node " << a << (mesh.on_boundary[a] ? " (boundary)" : " (interior)");
}

std::vector<Case> patch_cases() {
  std::vector<Case> cases;
  for (int order : {1, 2})
    for (const std::string& model : material_fixtures::all_law_names())
      cases.push_back({model, order});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Patch, LinearPatch, ::testing::ValuesIn(patch_cases()),
                         [](const auto& info) {
                           return info.param.model + "_P" + std::to_string(info.param.order);
                         });

TEST(QuadraticPatch, P2ReproducesTheHydrostaticFieldUnderGravity) {
  // Block 0 <= z <= H under gravity -rho g e_z with sigma = -rho g (H - z) I (docs: the
  // hydrostatic patch test); with K = E / (3 (1 - 2 nu)) and c = rho g / (3 K) the displacement
  //   u = (-c (H - z) x, -c (H - z) y, -c (H z - z^2/2) - c (x^2 + y^2)/2)
  // is quadratic, so P2 reproduces it: the residual vanishes at every interior node.
  const CubeMesh mesh = cube_mesh(2);
  const double E = 5.0, nu = 0.3, rho_g = 0.8, H = 2.0;
  const auto law = make_material_law("linear_elastic", {{"E", E}, {"nu", nu}});
  const MaterialLaw& m = *law;
  const double c = rho_g / (E / (1 - 2 * nu));
  std::vector<Eigen::Vector3d> u;
  for (const auto& p : mesh.x) {
    const double x = p(0), y = p(1), z = p(2);
    u.emplace_back(-c * (H - z) * x, -c * (H - z) * y,
                   -c * (H * z - z * z / 2) - c * (x * x + y * y) / 2);
  }
  const std::vector<Eigen::Vector3d> r = assemble(mesh, u, m, Eigen::Vector3d(0, 0, -rho_g));
  int interior = 0;
  for (size_t a = 0; a < mesh.x.size(); ++a) {
    if (mesh.on_boundary[a]) continue;
    ++interior;
    EXPECT_LT(r[a].norm(), 1e-14 * rho_g) << "node " << a;
  }
  // The centre vertex and the midpoints of the 26 interior edges: 14 from the centre (6 along
  // the axes, 8 Kuhn diagonals), 6 face diagonals of the inner planes, 6 cube diagonals.
  EXPECT_EQ(interior, 1 + 14 + 6 + 6);
}

// The F-bar P2 element's own zero-energy modes (tests/fem/test_element.cpp) do not survive
// assembly: on the cube clamped on its face x = 0 the linear-elastic stiffness at rest is
// positive definite, its softest mode (bending) 12 % softer than the displacement
// element's, which has no such modes.
double clamped_cube_softest_mode(bool fbar) {
  const CubeMesh mesh = cube_mesh(2);
  const MaterialLaw& m = material_fixtures::law("linear_elastic");
  const int N = static_cast<int>(mesh.x.size()), npe = 10, n = 3 * npe;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * N, 3 * N);
  std::vector<double> re(n), Ke(n * n);
  for (const auto& tet : mesh.tets) {
    const std::vector<double> X = gather(mesh.x, tet), ue(n, 0.0);
    fbar ? tet_internal_force_fbar(2, X.data(), ue.data(), m, re.data(), Ke.data())
         : tet_internal_force(2, X.data(), ue.data(), m, re.data(), Ke.data());
    for (int a = 0; a < npe; ++a)
      for (int b = 0; b < npe; ++b)
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k)
            K(3 * tet[a] + i, 3 * tet[b] + k) += Ke[(3 * a + i) * n + 3 * b + k];
  }
  std::vector<int> free;
  for (int a = 0; a < N; ++a)
    if (mesh.x[a](0) > 1e-12)
      for (int i = 0; i < 3; ++i) free.push_back(3 * a + i);
  Eigen::MatrixXd Kf(free.size(), free.size());
  for (size_t r = 0; r < free.size(); ++r)
    for (size_t c = 0; c < free.size(); ++c) Kf(r, c) = K(free[r], free[c]);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Kf).eigenvalues()(0);
}

TEST(FbarAssembly, ClampedCubeHasNoZeroEnergyMode) {
  const double displacement = clamped_cube_softest_mode(false);
  const double fbar = clamped_cube_softest_mode(true);
  EXPECT_GT(displacement, 0.0);
  EXPECT_GT(fbar, 0.8 * displacement);          // 0.88 measured
  EXPECT_LE(fbar, displacement * (1 + 1e-12));  // one constraint per element is softer
}

}  // namespace test_patch
}  // namespace
}  // namespace hs
