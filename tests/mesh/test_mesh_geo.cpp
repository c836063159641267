// The shipped .geo sources, meshed through load_mesh: volumes against closed forms, groups
// on their analytic surfaces, outward face orientation, P2 node placement, parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "common/error.hpp"
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

// Enclosed volume of a cavity group by the divergence theorem: its normals point into the
// cavity, so (1/3) sum x . n A is minus the (faceted) cavity volume.
double cavity_volume(const Mesh& m, const std::string& group) {
  double flux = 0;
  for (int64_t f = 0; f < num_faces(m, group); ++f)
    flux += face_centroid(m, group, f).dot(face_area_vector(m, group, f)) / 3;
  return -flux;
}

// The one node of a point group, checked to lie at `where`.
void expect_point_node(const Mesh& m, const std::string& group, const Vec3& where, double tol) {
  ASSERT_TRUE(m.node_groups.count(group)) << group;
  ASSERT_EQ(m.node_groups.at(group).size(), 1u) << group;
  EXPECT_LT((node(m, m.node_groups.at(group)[0]) - where).norm(), tol) << group;
}

// Loading `name` with `parameters` fails with an InputError that mentions `part`.
void expect_refused(const std::string& name, std::map<std::string, double> parameters,
                    const std::string& part) {
  try {
    load_geo(name, std::move(parameters));
    ADD_FAILURE() << name << ": no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
        << "'" << part << "' not in: " << e.what();
  }
}

TEST(Finger, SlabWithAClosedBoxCavityBelowTheMidPlane) {
  // The file's defaults.
  const double L = 0.09, W = 0.018, T = 0.016, lc = 0.07, wc = 0.01, tc = 0.005, xb = 0.01,
               ez = -0.003;
  const Mesh m = load_geo("finger.geo", {});
  EXPECT_EQ(m.volume_names, std::vector<std::string>{"body"});
  EXPECT_GT(m.num_nodes(), 200);  // coarse: a few hundred nodes
  EXPECT_LT(m.num_nodes(), 600);
  // Flat faces only: the faceted volumes are exact.
  const double cavity = lc * wc * tc;
  const double exact = L * W * T - cavity;
  EXPECT_NEAR(mesh_volume(m), exact, 1e-9 * exact);
  expect_closed_boundary(m, {"base", "tip", "cavity", "outer"});
  EXPECT_NEAR(cavity_volume(m, "cavity"), cavity, 1e-9 * cavity);
  for (int64_t n : m.node_groups.at("base")) EXPECT_EQ(node(m, n)[0], 0.0);
  for (int64_t n : m.node_groups.at("tip")) EXPECT_NEAR(node(m, n)[0], L, 1e-15);
  for (int64_t f = 0; f < num_faces(m, "base"); ++f)
    EXPECT_NEAR(face_area_vector(m, "base", f).normalized()[0], -1.0, 1e-12);
  for (int64_t f = 0; f < num_faces(m, "tip"); ++f)
    EXPECT_NEAR(face_area_vector(m, "tip", f).normalized()[0], 1.0, 1e-12);
  // The cavity's nodes lie on its box, which is below the mid-plane; its faces point into
  // the box (towards its centre).
  const Vec3 lo(xb, -wc / 2, ez - tc / 2), hi(xb + lc, wc / 2, ez + tc / 2);
  for (int64_t n : m.node_groups.at("cavity")) {
    const Vec3 x = node(m, n);
    EXPECT_TRUE(((x - lo).minCoeff() > -1e-12) && ((hi - x).minCoeff() > -1e-12));
    EXPECT_LT(std::min((x - lo).cwiseAbs().minCoeff(), (hi - x).cwiseAbs().minCoeff()), 1e-12);
    EXPECT_LT(x[2], 0.0);
  }
  const Vec3 centre = (lo + hi) / 2;
  for (int64_t f = 0; f < num_faces(m, "cavity"); ++f)
    EXPECT_LT(face_area_vector(m, "cavity", f).dot(face_centroid(m, "cavity", f) - centre), 0);
  // The effector: a mesh node at the centre of the tip face, in the tip group.
  expect_point_node(m, "effector", Vec3(L, 0, 0), 1e-15);
  const auto& tip = m.node_groups.at("tip");
  EXPECT_TRUE(std::binary_search(tip.begin(), tip.end(), m.node_groups.at("effector")[0]));
}

TEST(Finger, ParametersMoveTheCavityAndRefineTheMesh) {
  const double L = 0.1, W = 0.02, T = 0.02, lc = 0.06, wc = 0.012, tc = 0.006, xb = 0.015,
               ez = 0.004;
  const Mesh m = load_geo("finger.geo", {{"L", L},
                                         {"W", W},
                                         {"T", T},
                                         {"lc", lc},
                                         {"wc", wc},
                                         {"tc", tc},
                                         {"xb", xb},
                                         {"ez", ez},
                                         {"h", 0.004}});
  const double exact = L * W * T - lc * wc * tc;
  EXPECT_NEAR(mesh_volume(m), exact, 1e-9 * exact);
  expect_closed_boundary(m, {"base", "tip", "cavity", "outer"});
  EXPECT_NEAR(cavity_volume(m, "cavity"), lc * wc * tc, 1e-9 * lc * wc * tc);
  for (int64_t n : m.node_groups.at("cavity")) {
    EXPECT_GT(node(m, n)[2], ez - tc / 2 - 1e-12);  // above the mid-plane now
    EXPECT_GT(node(m, n)[0], xb - 1e-12);
  }
  expect_point_node(m, "effector", Vec3(L, 0, 0), 1e-15);
  // The refinement series of the file's comment: about 2k and 10k nodes.
  const Mesh m2k = load_geo("finger.geo", {{"h", 0.0026}});
  const Mesh m10k = load_geo("finger.geo", {{"h", 0.00135}});
  EXPECT_GT(m2k.num_nodes(), 1500);
  EXPECT_LT(m2k.num_nodes(), 2500);
  EXPECT_GT(m10k.num_nodes(), 8000);
  EXPECT_LT(m10k.num_nodes(), 12500);
  expect_closed_boundary(m10k, {"base", "tip", "cavity", "outer"});
  expect_point_node(m10k, "effector", Vec3(0.09, 0, 0), 1e-15);
  // A cavity that would cut the bottom face is refused with the walls' thicknesses.
  expect_refused("finger.geo", {{"ez", -0.006}}, "thinner than");
}

// finger_cad.geo imports finger_cad.step (millimetres, scaled to metres) and names its groups
// by bounding boxes (docs/tutorial_cad.md): the same finger as finger.geo with its long edges
// rounded, so the volumes are those of the CAD model less what the facets cut off.
TEST(FingerCad, StepFileMeshedWithItsGroups) {
  const double kMm3 = 1e-9;
  const double fillets = 4 * (1 - kPi / 4) * 70 * 1.5 * 1.5 * kMm3;  // the cavity's 4 edges
  const double cavity = 70 * 10 * 5 * kMm3 - fillets;                // 3.365 ml
  const double body = (90 * 18 * 16 - 4 * (1 - kPi / 4) * 90 * 3 * 3) * kMm3 - cavity;
  const Mesh m = load_geo("finger_cad.geo", {});
  EXPECT_EQ(m.volume_names, std::vector<std::string>{"body"});
  EXPECT_GT(m.num_nodes(), 700);  // about 1,000 nodes at the default h = 0.004
  EXPECT_LT(m.num_nodes(), 1400);
  expect_closed_boundary(m, {"base", "tip", "cavity", "outer"});
  // Flat facets cut into the rounded edges: a little less cavity, within a few percent.
  EXPECT_LT(cavity_volume(m, "cavity"), cavity);
  EXPECT_GT(cavity_volume(m, "cavity"), 0.95 * cavity);
  EXPECT_NEAR(mesh_volume(m), body, 0.01 * body);
  for (int64_t n : m.node_groups.at("base")) EXPECT_NEAR(node(m, n)[0], 0.0, 1e-12);
  for (int64_t n : m.node_groups.at("tip")) EXPECT_NEAR(node(m, n)[0], 0.09, 1e-12);
  // The cavity's nodes lie within its box, 10 mm from either end, below the mid-plane.
  const Vec3 lo(0.01, -0.005, -0.0055), hi(0.08, 0.005, -0.0005);
  for (int64_t n : m.node_groups.at("cavity")) {
    const Vec3 x = node(m, n);
    EXPECT_TRUE(((x - lo).minCoeff() > -1e-9) && ((hi - x).minCoeff() > -1e-9)) << x.transpose();
  }
  expect_point_node(m, "effector", Vec3(0.09, 0, 0), 1e-12);
}

// The nodes of pendulum.geo's cavity k (0-based) lie on the faces of its sector:
// r1 <= r <= r2, |angle - k 90 degrees| <= phi / 2, z0 <= z <= z0 + lc.
void expect_on_sector(const Mesh& m, int k, double r1, double r2, double phi_deg, double z0,
                      double lc) {
  const std::string g = "cavity_" + std::to_string(k + 1);
  const double half = phi_deg * kPi / 360, theta = k * kPi / 2, z1 = z0 + lc;
  for (int64_t n : m.node_groups.at(g)) {
    const Vec3 x = node(m, n);
    const double r = std::hypot(x[0], x[1]);
    // Angle from the sector's axis, in (-pi, pi].
    const double d = std::atan2(-std::sin(theta) * x[0] + std::cos(theta) * x[1],
                                std::cos(theta) * x[0] + std::sin(theta) * x[1]);
    EXPECT_GT(r, r1 - 1e-9) << g;
    EXPECT_LT(r, r2 + 1e-9) << g;
    EXPECT_LT(std::abs(d), half + 1e-9) << g;
    EXPECT_GT(x[2], z0 - 1e-12) << g;
    EXPECT_LT(x[2], z1 + 1e-12) << g;
    EXPECT_TRUE(std::abs(r - r1) < 1e-9 || std::abs(r - r2) < 1e-9 ||
                r * std::abs(std::abs(d) - half) < 1e-9 || std::abs(x[2] - z0) < 1e-12 ||
                std::abs(x[2] - z1) < 1e-12)
        << g << " node " << n << " on no face of its sector";
  }
}

const std::vector<std::string> kPendulumGroups = {"top",      "cavity_1", "cavity_2",
                                                  "cavity_3", "cavity_4", "outer"};

TEST(Pendulum, CylinderWithFourClosedSectorCavitiesAroundTheAxis) {
  // The file's defaults.
  const double R = 0.015, L = 0.1, r1 = 0.005, r2 = 0.012, phi = 60, lc = 0.05, tb = 0.005;
  const Mesh m = load_geo("pendulum.geo", {});
  EXPECT_EQ(m.volume_names, std::vector<std::string>{"body"});
  EXPECT_GT(m.num_nodes(), 1500);  // about 2k nodes
  EXPECT_LT(m.num_nodes(), 2500);
  const double cavity = phi / 360 * kPi * (r2 * r2 - r1 * r1) * lc;
  const double exact = kPi * R * R * L - 4 * cavity;
  EXPECT_NEAR(mesh_volume(m), exact, 0.02 * exact);
  expect_closed_boundary(m, kPendulumGroups);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(cavity_volume(m, "cavity_" + std::to_string(k + 1)), cavity, 0.02 * cavity);
    expect_on_sector(m, k, r1, r2, phi, -L + tb, lc);
  }
  for (int64_t n : m.node_groups.at("top")) EXPECT_EQ(node(m, n)[2], 0.0);
  for (int64_t f = 0; f < num_faces(m, "top"); ++f)
    EXPECT_NEAR(face_area_vector(m, "top", f).normalized()[2], 1.0, 1e-12);
  // "outer" is the lateral surface and the bottom face.
  for (int64_t n : m.node_groups.at("outer")) {
    const Vec3 x = node(m, n);
    EXPECT_TRUE(std::abs(std::hypot(x[0], x[1]) - R) < 1e-9 || std::abs(x[2] + L) < 1e-12);
  }
  // The effector: a mesh node at the centre of the bottom face, in the outer group.
  expect_point_node(m, "effector", Vec3(0, 0, -L), 1e-15);
  const auto& outer = m.node_groups.at("outer");
  EXPECT_TRUE(std::binary_search(outer.begin(), outer.end(), m.node_groups.at("effector")[0]));
}

TEST(Pendulum, ParametersAndRefinement) {
  const double R = 0.02, L = 0.12, r1 = 0.006, r2 = 0.016, phi = 70, lc = 0.06, tb = 0.008;
  const Mesh m = load_geo("pendulum.geo", {{"R", R},
                                           {"L", L},
                                           {"r1", r1},
                                           {"r2", r2},
                                           {"phi", phi},
                                           {"lc", lc},
                                           {"tb", tb},
                                           {"h", 0.005}});
  const double cavity = phi / 360 * kPi * (r2 * r2 - r1 * r1) * lc;
  const double exact = kPi * R * R * L - 4 * cavity;
  EXPECT_NEAR(mesh_volume(m), exact, 0.02 * exact);
  expect_closed_boundary(m, kPendulumGroups);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(cavity_volume(m, "cavity_" + std::to_string(k + 1)), cavity, 0.02 * cavity);
    expect_on_sector(m, k, r1, r2, phi, -L + tb, lc);
  }
  expect_point_node(m, "effector", Vec3(0, 0, -L), 1e-15);
  // The refinement series of the file's comment: about 10k nodes, and the faceting error
  // of the volumes falls.
  const double R0 = 0.015, L0 = 0.1, r10 = 0.005, r20 = 0.012, lc0 = 0.05;
  const double cavity0 = kPi / 6 * (r20 * r20 - r10 * r10) * lc0;
  const double exact0 = kPi * R0 * R0 * L0 - 4 * cavity0;
  const Mesh coarse = load_geo("pendulum.geo", {});
  const Mesh fine = load_geo("pendulum.geo", {{"h", 0.00185}});
  EXPECT_GT(fine.num_nodes(), 8000);
  EXPECT_LT(fine.num_nodes(), 12500);
  expect_closed_boundary(fine, kPendulumGroups);
  EXPECT_LT(std::abs(mesh_volume(fine) - exact0), std::abs(mesh_volume(coarse) - exact0));
  EXPECT_LT(std::abs(cavity_volume(fine, "cavity_3") - cavity0),
            std::abs(cavity_volume(coarse, "cavity_3") - cavity0));
  expect_point_node(fine, "effector", Vec3(0, 0, -L0), 1e-15);
  // Neighbouring cavities that would (almost) touch are refused with the walls' thicknesses.
  expect_refused("pendulum.geo", {{"phi", 85}}, "thinner than");
}

}  // namespace
}  // namespace hs::test
