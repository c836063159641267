// Open, non-manifold and inconsistently oriented meshes are refused with the first bad edge.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

std::string error_of(const SurfaceMesh& mesh) {
  try {
    fw::check_closed_surface(mesh, "cavity.obj");
  } catch (const fw::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Topology, ClosedSurfacesPass) {
  for (const SurfaceMesh& m : {fw::shapes::icosphere(2), fw::shapes::torus(1, 0.3, 12, 8),
                               e_shape(), flipped(comb(3)), octahedron({0, 0, 0}, 1)}) {
    EXPECT_EQ(error_of(m), "");
  }
}

TEST(Topology, OpenSurfaceNamesTheEdge) {
  SurfaceMesh m = octahedron({0, 0, 0}, 1);
  m.triangles.erase(m.triangles.begin() + 3, m.triangles.begin() + 6);  // drop triangle 1
  // Triangle 0 is (0, 2, 4); its edge (2, 4) was shared with the dropped (2, 1, 4).
  EXPECT_EQ(error_of(m),
            "cavity.obj: not a closed surface: edge (2, 4) is used by triangle 0 only: the "
            "surface is open there");
  EXPECT_THROW(fw::compute(m, options(fw::Implementation::cpu_fast, 10)), fw::InputError);
}

TEST(Topology, FlippedTriangleNamesTheEdge) {
  SurfaceMesh m = octahedron({0, 0, 0}, 1);
  std::swap(m.triangles[4], m.triangles[5]);  // triangle 1 becomes (2, 4, 1)
  EXPECT_EQ(error_of(m),
            "cavity.obj: not a closed surface: edge (2, 4) is used in the same direction by "
            "triangles 0 and 1: their orientations disagree (flip one)");
}

TEST(Topology, NonManifoldEdgeNamesTheEdge) {
  // Two octahedra sharing the edge between their vertices 0 and 2 (same coordinates, same
  // indices): that edge has four triangles.
  SurfaceMesh a = octahedron({0, 0, 0}, 1);
  SurfaceMesh b = octahedron({1, 1, 0}, 1);
  SurfaceMesh m = a;
  int offset = a.num_vertices();
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (int v : b.triangles) {
    // b's vertex 1 (-x) is a's vertex 2 (+y) and b's vertex 3 (-y) is a's vertex 0 (+x).
    int mapped = v == 1 ? 2 : v == 3 ? 0 : v + offset;
    m.triangles.push_back(mapped);
  }
  std::string e = error_of(m);
  EXPECT_NE(e.find("edge (0, 2) is shared by 4 triangles"), std::string::npos) << e;
  EXPECT_NE(e.find("not manifold"), std::string::npos) << e;
}

// A fan of 100,000 triangles on one edge: the message named every one, a line of megabytes.
TEST(Topology, AnEdgeSharedByManyTrianglesGivesAShortMessage) {
  SurfaceMesh m;
  m.vertices = {0, 0, 0, 1, 0, 0};
  const int fan = 100000;
  for (int k = 0; k < fan; ++k) {
    m.vertices.insert(m.vertices.end(), {0.5, std::cos(k * 1e-4), std::sin(k * 1e-4)});
    m.triangles.insert(m.triangles.end(), {0, 1, 2 + k});
  }
  const std::string e = error_of(m);
  EXPECT_NE(e.find("edge (0, 1) is shared by 100000 triangles (0, 1, 2, 3, 4, 5, 6, 7, ...)"),
            std::string::npos)
      << e.substr(0, 200);
  EXPECT_LT(e.size(), 300u);
}

TEST(Topology, BadIndicesAndDegenerateTriangles) {
  SurfaceMesh m = octahedron({0, 0, 0}, 1);
  m.triangles[7] = 6;
  EXPECT_EQ(error_of(m), "cavity.obj: triangle 2 has vertex index 6, outside [0, 6)");
  m = octahedron({0, 0, 0}, 1);
  m.triangles[8] = m.triangles[6];
  EXPECT_EQ(error_of(m), "cavity.obj: triangle 2 repeats a vertex (1, 3, 1)");
  EXPECT_EQ(error_of(SurfaceMesh{}), "cavity.obj: the surface has no triangles");
}
