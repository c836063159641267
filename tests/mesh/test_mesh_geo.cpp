// The shipped .geo sources, meshed through load_mesh: volumes against closed forms, groups
// on their analytic surfaces, outward face orientation, P2 node placement, parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "mesh_test_util.hpp"

namespace hs::test {
namespace {

const double kPi = std::acos(-1.0);

double eighth_shell_volume(double a, double b) { return kPi / 6 * (b * b * b - a * a * a); }

// Every boundary face of the mesh (a vertex triple in one tetrahedron only), sorted.
std::set<std::array<int64_t, 3>> boundary_faces(const Mesh& m) {
  std::map<std::array<int64_t, 3>, int> count;
  const int f[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (int64_t t = 0; t < m.num_tets(); ++t)
    for (const auto& face : f) {
      std::array<int64_t, 3> k;
      for (int i = 0; i < 3; ++i) k[i] = m.tets[t * m.nodes_per_tet() + face[i]];
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  std::set<std::array<int64_t, 3>> boundary;
  for (const auto& [k, c] : count)
    if (c == 1) boundary.insert(k);
  return boundary;
}

// Each face's normal points away from the fourth vertex of the tetrahedron it bounds, and
// its vertices are vertices of that tetrahedron.
void expect_outward(const Mesh& m, const std::string& group) {
  const int npe = m.nodes_per_tet(), npf = m.nodes_per_face();
  const auto& faces = m.surfaces.at(group);
  const auto& tets = m.surface_tets.at(group);
  ASSERT_EQ(static_cast<int64_t>(tets.size()), num_faces(m, group));
  for (int64_t f = 0; f < num_faces(m, group); ++f) {
    const int64_t* tet = &m.tets[tets[f] * npe];
    const std::set<int64_t> face_nodes(&faces[f * npf], &faces[f * npf] + npf);
    const std::set<int64_t> tet_nodes(tet, tet + npe);
    int fourth = -1, shared = 0;
    for (int k = 0; k < 4; ++k) face_nodes.count(tet[k]) ? ++shared : fourth = k;
    ASSERT_EQ(shared, 3) << group << " face " << f;
    for (int64_t n : face_nodes) ASSERT_TRUE(tet_nodes.count(n)) << group << " face " << f;
    const Vec3 to_fourth = node(m, tet[fourth]) - node(m, faces[f * npf]);
    EXPECT_LT(face_area_vector(m, group, f).dot(to_fourth), 0) << group << " face " << f;
  }
}

// The groups cover the boundary exactly once and are closed: their area vectors add to 0.
void expect_closed_boundary(const Mesh& m, const std::vector<std::string>& groups) {
  const auto boundary = boundary_faces(m);
  std::set<std::array<int64_t, 3>> covered;
  Vec3 sum = Vec3::Zero();
  double area = 0;
  for (const auto& g : groups) {
    expect_outward(m, g);
    for (int64_t f = 0; f < num_faces(m, g); ++f) {
      const int64_t* v = &m.surfaces.at(g)[f * m.nodes_per_face()];
      std::array<int64_t, 3> k{v[0], v[1], v[2]};
      std::sort(k.begin(), k.end());
      EXPECT_TRUE(boundary.count(k)) << g << ": not a boundary face";
      EXPECT_TRUE(covered.insert(k).second) << g << ": face in two groups";
      sum += face_area_vector(m, g, f);
      area += face_area_vector(m, g, f).norm();
    }
  }
  EXPECT_EQ(covered.size(), boundary.size());
  EXPECT_LT(sum.norm(), 1e-12 * area);
}

double max_radius_error(const Mesh& m, const std::string& group, double r) {
  double err = 0;
  for (int64_t n : m.node_groups.at(group)) err = std::max(err, std::abs(node(m, n).norm() - r));
  return err;
}

TEST(LameSphere, VolumeConvergesToTheShellAtSecondOrder) {
  const double exact = eighth_shell_volume(1, 2);
  const Mesh coarse = load_geo("lame_sphere.geo", {{"h", 0.25}});
  const Mesh fine = load_geo("lame_sphere.geo", {{"h", 0.125}});
  EXPECT_GT(fine.num_nodes(), 4 * coarse.num_nodes());
  EXPECT_GT(fine.num_tets(), 4 * coarse.num_tets());
  const double e_coarse = std::abs(mesh_volume(coarse) - exact) / exact;
  const double e_fine = std::abs(mesh_volume(fine) - exact) / exact;
  // Chord error of the faceted spheres: O(h^2), about 0.3% at h = 0.25.
  EXPECT_LT(e_coarse, 0.01);
  EXPECT_GT(e_coarse / e_fine, 3.0);  // about 4 for h^2
  EXPECT_EQ(coarse.volume_names, std::vector<std::string>{"body"});
}

TEST(LameSphere, GroupsLieOnTheirSurfacesAndFaceOutwards) {
  for (int order : {1, 2}) {
    const Mesh m = load_geo("lame_sphere.geo", {{"a", 1}, {"b", 2}, {"h", 0.4}}, order);
    ASSERT_EQ(m.order, order);
    EXPECT_LT(max_radius_error(m, "inner", 1), 1e-9);
    EXPECT_LT(max_radius_error(m, "outer", 2), 1e-9);
    const char* planes[3] = {"symmetry_x", "symmetry_y", "symmetry_z"};
    for (int d = 0; d < 3; ++d) {
      for (int64_t n : m.node_groups.at(planes[d])) EXPECT_NEAR(node(m, n)[d], 0.0, 1e-12);
      for (int64_t f = 0; f < num_faces(m, planes[d]); ++f) {
        const Vec3 n = face_area_vector(m, planes[d], f).normalized();
        EXPECT_NEAR(n[d], -1.0, 1e-12) << planes[d];
      }
    }
    for (int64_t f = 0; f < num_faces(m, "inner"); ++f)  // towards the centre
      EXPECT_LT(face_area_vector(m, "inner", f).dot(face_centroid(m, "inner", f)), 0);
    for (int64_t f = 0; f < num_faces(m, "outer"); ++f)
      EXPECT_GT(face_area_vector(m, "outer", f).dot(face_centroid(m, "outer", f)), 0);
    expect_closed_boundary(m, {"inner", "outer", "symmetry_x", "symmetry_y", "symmetry_z"});
  }
}

TEST(LameSphere, ParametersChangeTheMesh) {
  const Mesh a1b3 = load_geo("lame_sphere.geo", {{"a", 1}, {"b", 3}, {"h", 0.4}});
  const double exact = eighth_shell_volume(1, 3);
  EXPECT_NEAR(mesh_volume(a1b3), exact, 0.02 * exact);
  EXPECT_LT(max_radius_error(a1b3, "outer", 3), 1e-9);
  const Mesh h05 = load_geo("lame_sphere.geo", {{"h", 0.5}});
  const Mesh h03 = load_geo("lame_sphere.geo", {{"h", 0.3}});
  EXPECT_GT(h03.num_tets(), 2 * h05.num_tets());
  // No parameters: the file's defaults (a = 1, b = 2, h = 0.25).
  const Mesh defaults = load_geo("lame_sphere.geo", {});
  const Mesh h025 = load_geo("lame_sphere.geo", {{"h", 0.25}});
  EXPECT_EQ(defaults.num_tets(), h025.num_tets());
  EXPECT_EQ(defaults.x, h025.x);
}

TEST(LameSphere, P2IsCurvedOnTheSpheresAndStraightInside) {
  const Mesh p1 = load_geo("lame_sphere.geo", {{"h", 0.4}}, 1);
  const Mesh p2 = load_geo("lame_sphere.geo", {{"h", 0.4}}, 2);
  ASSERT_EQ(p2.num_tets(), p1.num_tets());
  ASSERT_EQ(p2.tets.size(), 10 * p1.tets.size() / 4);
  std::set<int64_t> on_boundary;
  for (const auto& g : {"inner", "outer", "symmetry_x", "symmetry_y", "symmetry_z"})
    on_boundary.insert(p2.node_groups.at(g).begin(), p2.node_groups.at(g).end());
  const int pairs[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  for (int64_t t = 0; t < p2.num_tets(); ++t) {
    const int64_t* v = &p2.tets[10 * t];
    for (int e = 0; e < 6; ++e) {
      if (on_boundary.count(v[4 + e])) continue;
      const Vec3 mid = 0.5 * (node(p2, v[pairs[e][0]]) + node(p2, v[pairs[e][1]]));
      EXPECT_LT((node(p2, v[4 + e]) - mid).norm(), 1e-12);
    }
  }
  // Curved faces follow the spheres, so P2 is far closer to the exact volume.
  const double exact = eighth_shell_volume(1, 2);
  const double e1 = std::abs(mesh_volume(p1) - exact), e2 = std::abs(mesh_volume(p2) - exact);
  EXPECT_LT(e2, 0.05 * e1);
}

TEST(LameSphere, UniformRefinementSplitsEachTetrahedronIntoEight) {
  const Mesh once = load_geo("lame_sphere.geo", {{"h", 0.5}}, 1, 1);
  const Mesh base = load_geo("lame_sphere.geo", {{"h", 0.5}}, 1, 0);
  EXPECT_EQ(once.num_tets(), 8 * base.num_tets());
  EXPECT_LT(max_radius_error(once, "inner", 1), 1e-9);  // new nodes on the geometry
  const double exact = eighth_shell_volume(1, 2);
  EXPECT_LT(std::abs(mesh_volume(once) - exact), 0.5 * std::abs(mesh_volume(base) - exact));
}

TEST(Block, P2EdgeNodesAreMidpointsInGmshOrder) {
  const Mesh m = load_geo("block.geo", {{"H", 1}, {"h", 0.5}}, 2);
  ASSERT_EQ(m.nodes_per_tet(), 10);
  // Edge nodes 4:(0,1) 5:(1,2) 6:(2,0) 7:(3,0) 8:(3,2) 9:(3,1), see mesh.hpp.
  const int pairs[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  for (int64_t t = 0; t < m.num_tets(); ++t) {
    const int64_t* v = &m.tets[10 * t];
    for (int e = 0; e < 6; ++e) {
      const Vec3 mid = 0.5 * (node(m, v[pairs[e][0]]) + node(m, v[pairs[e][1]]));
      ASSERT_LT((node(m, v[4 + e]) - mid).norm(), 1e-14) << "tet " << t << " edge " << e;
    }
    EXPECT_GT(vertex_volume(m, t), 0);
  }
  // Tri6 faces: edge nodes 3:(0,1) 4:(1,2) 5:(2,0).
  const auto& top = m.surfaces.at("top");
  for (size_t f = 0; f < top.size() / 6; ++f)
    for (int e = 0; e < 3; ++e) {
      const Vec3 mid = 0.5 * (node(m, top[6 * f + e]) + node(m, top[6 * f + (e + 1) % 3]));
      EXPECT_LT((node(m, top[6 * f + 3 + e]) - mid).norm(), 1e-14);
    }
  EXPECT_NEAR(mesh_volume(m), 1.0, 1e-12);
}

TEST(Block, GroupsAndNormals) {
  const double H = 2.0;
  const Mesh m = load_geo("block.geo", {{"H", H}, {"h", 0.5}});
  EXPECT_NEAR(mesh_volume(m), H * H * H, 1e-12);
  const std::map<std::string, Vec3> normal = {{"bottom", {0, 0, -1}}, {"top", {0, 0, 1}},
                                              {"x0", {-1, 0, 0}},     {"x1", {1, 0, 0}},
                                              {"y0", {0, -1, 0}},     {"y1", {0, 1, 0}}};
  for (const auto& [g, n] : normal) {
    double area = 0;
    for (int64_t f = 0; f < num_faces(m, g); ++f) {
      const Vec3 a = face_area_vector(m, g, f);
      EXPECT_LT((a.normalized() - n).norm(), 1e-12) << g;
      area += a.norm();
    }
    EXPECT_NEAR(area, H * H, 1e-12) << g;
  }
  std::set<int64_t> sides;
  for (const auto& g : {"x0", "x1", "y0", "y1"})
    sides.insert(m.node_groups.at(g).begin(), m.node_groups.at(g).end());
  EXPECT_EQ(std::vector<int64_t>(sides.begin(), sides.end()), m.node_groups.at("sides"));
  EXPECT_EQ(num_faces(m, "sides"),
            num_faces(m, "x0") + num_faces(m, "x1") + num_faces(m, "y0") + num_faces(m, "y1"));
  for (int64_t n : m.node_groups.at("top")) EXPECT_EQ(node(m, n)[2], H);
  expect_closed_boundary(m, {"bottom", "top", "x0", "x1", "y0", "y1"});
  // The volume group holds every node.
  EXPECT_EQ(static_cast<int64_t>(m.node_groups.at("body").size()), m.num_nodes());
}

TEST(Cantilever, BoxOfLengthLAndSectionH) {
  for (double h : {0.05, 0.1}) {
    const double L = 1.0;
    const Mesh m = load_geo("cantilever.geo", {{"L", L}, {"h", h}});
    EXPECT_NEAR(mesh_volume(m), L * h * h, 1e-12 * L * h * h);
    Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
    for (int64_t n = 0; n < m.num_nodes(); ++n) {
      lo = lo.cwiseMin(node(m, n));
      hi = hi.cwiseMax(node(m, n));
    }
    EXPECT_LT((lo - Vec3(0, -h / 2, -h / 2)).norm(), 1e-15);
    EXPECT_LT((hi - Vec3(L, h / 2, h / 2)).norm(), 1e-15);
    // Mesh size h / 2: at least 2 node layers across and about 2 L / h along.
    std::set<double> xs;
    for (int64_t n : m.node_groups.at("top")) xs.insert(node(m, n)[0]);
    EXPECT_GE(static_cast<double>(xs.size()), 2 * L / h);
    for (int64_t n : m.node_groups.at("clamped")) EXPECT_EQ(node(m, n)[0], 0.0);
    for (int64_t n : m.node_groups.at("tip")) EXPECT_EQ(node(m, n)[0], L);
    for (int64_t n : m.node_groups.at("top")) EXPECT_EQ(node(m, n)[2], h / 2);
    for (int64_t f = 0; f < num_faces(m, "top"); ++f)
      EXPECT_NEAR(face_area_vector(m, "top", f).normalized()[2], 1.0, 1e-12);
    for (int64_t f = 0; f < num_faces(m, "clamped"); ++f)
      EXPECT_NEAR(face_area_vector(m, "clamped", f).normalized()[0], -1.0, 1e-12);
    for (int64_t f = 0; f < num_faces(m, "tip"); ++f)
      EXPECT_NEAR(face_area_vector(m, "tip", f).normalized()[0], 1.0, 1e-12);
  }
}

TEST(Cylinder, HollowWithAClosedCavity) {
  const double R = 0.015, L = 0.08, t = 0.003, r = R - t;
  const Mesh m = load_geo("cylinder.geo", {{"h", 0.004}});
  const double cavity = kPi * r * r * (L - 2 * t);
  const double exact = kPi * R * R * L - cavity;
  EXPECT_NEAR(mesh_volume(m), exact, 0.02 * exact);
  expect_closed_boundary(m, {"top", "tip", "cavity", "outer"});
  // Divergence theorem on the cavity surface: its normals point into the cavity, so
  // (1/3) sum x . n A is minus the (faceted) cavity volume.
  double flux = 0;
  for (int64_t f = 0; f < num_faces(m, "cavity"); ++f)
    flux += face_centroid(m, "cavity", f).dot(face_area_vector(m, "cavity", f)) / 3;
  EXPECT_NEAR(-flux, cavity, 0.02 * cavity);
  for (int64_t n : m.node_groups.at("top")) EXPECT_EQ(node(m, n)[2], 0.0);
}

TEST(BimaterialBar, TwoVolumeGroups) {
  const Mesh m = load_geo("bimaterial_bar.geo", {{"L1", 1}, {"L2", 0.5}, {"w", 0.2}, {"h", 0.1}});
  ASSERT_EQ(m.volume_names.size(), 2u);
  std::map<std::string, double> volume;
  for (int64_t t = 0; t < m.num_tets(); ++t)
    volume[m.volume_names[m.tet_volume[t]]] += vertex_volume(m, t);
  EXPECT_NEAR(volume["stiff"], 1.0 * 0.04, 1e-12);
  EXPECT_NEAR(volume["soft"], 0.5 * 0.04, 1e-12);
}

}  // namespace
}  // namespace hs::test
