// The file readers: each format written here from a generated mesh reads back to the same
// surface (same volume); STL corners are merged; errors name the file and line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fluidweight/mesh_io.hpp"
#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

std::string temp_path(const std::string& name) { return scratch_folder() + name; }

std::string write(const std::string& name, const std::string& text) {
  std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string expect_error(const std::string& path) {
  try {
    fw::read_surface(path);
  } catch (const fw::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was read without error";
  return "";
}

const SurfaceMesh& sample() {
  static SurfaceMesh mesh = transformed(fw::shapes::torus(1, 0.3, 16, 8), rotation({1, 2, 0}, 0.3));
  return mesh;
}

}  // namespace

TEST(Readers, ObjWithPolygonsNegativeIndicesAndNormals) {
  // A cube as quads, with texture and normal indices and relative (negative) indices.
  std::string text =
      "# cube\nmtllib none.mtl\no cube\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "vn 0 0 1\nvt 0 0\n"
      "f 1/1/1 4/1/1 3/1/1 2/1/1\nf 5//1 6//1 7//1 8//1\nf 1 2 6 5\n"
      "f -7 -6 -2 -3\nf 3 4 8 7\nf 4 1 5 8\n";
  SurfaceMesh m = fw::read_surface(write("cube.obj", text));
  EXPECT_EQ(m.num_vertices(), 8);
  EXPECT_EQ(m.num_triangles(), 12);
  fw::check_closed_surface(m);
  EXPECT_NEAR(volume(m), 1.0, 1e-15);
}

TEST(Readers, OffStlAsciiStlBinaryAndMshGiveTheSameSurface) {
  const SurfaceMesh& m = sample();
  const double v = volume(m);
  std::ostringstream off, stl;
  off << "OFF\n# comment\n" << m.num_vertices() << " " << m.num_triangles() << " 0\n";
  off.precision(17);
  stl.precision(17);
  for (int k = 0; k < m.num_vertices(); ++k) {
    off << m.vertices[3 * k] << " " << m.vertices[3 * k + 1] << " " << m.vertices[3 * k + 2]
        << "\n";
  }
  stl << "solid torus\n";
  std::string binary(80, ' ');
  uint32_t count = m.num_triangles();
  binary.append(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < m.num_triangles(); ++t) {
    const int* c = &m.triangles[3 * t];
    off << "3 " << c[0] << " " << c[1] << " " << c[2] << "\n";
    stl << "facet normal 0 0 0\n outer loop\n";
    float record[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const double* p = &m.vertices[3 * c[k]];
      stl << "  vertex " << p[0] << " " << p[1] << " " << p[2] << "\n";
      for (int d = 0; d < 3; ++d) record[3 + 3 * k + d] = static_cast<float>(p[d]);
    }
    stl << " endloop\nendfacet\n";
    binary.append(reinterpret_cast<const char*>(record), 48);
    binary.append(2, '\0');
  }
  stl << "endsolid torus\n";

  SurfaceMesh a = fw::read_surface(write("torus.off", off.str()));
  SurfaceMesh b = fw::read_surface(write("torus.stl", stl.str()));
  SurfaceMesh c = fw::read_surface(write("torus_binary.STL", binary));
  EXPECT_EQ(a.vertices, m.vertices);
  EXPECT_EQ(a.triangles, m.triangles);
  // STL repeats each corner once per facet; merged back, the corners are the mesh's vertices.
  for (const SurfaceMesh* s : {&b, &c}) {
    EXPECT_EQ(s->num_vertices(), m.num_vertices());
    EXPECT_EQ(s->num_triangles(), m.num_triangles());
    fw::check_closed_surface(*s);
  }
  EXPECT_NEAR(volume(b), v, 1e-14);
  EXPECT_NEAR(volume(c), v, 1e-6 * v);  // float32 coordinates
}

TEST(Readers, Msh41And22) {
  // Two triangles and a quad closing a square pyramid... here: a tetrahedron's four faces,
  // one of them given as part of a line/point/volume element mix that must be skipped.
  std::string v41 =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$Entities\n0 0 1 0\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
      "$Nodes\n2 4 1 40\n"
      "2 1 0 3\n10\n20\n30\n0 0 0\n1 0 0\n0 1 0\n"
      "0 7 0 1\n40\n0 0 1\n"
      "$EndNodes\n"
      "$Elements\n3 6 1 6\n"
      "1 1 1 1\n1 10 20\n"
      "2 1 2 4\n2 10 30 20\n3 10 20 40\n4 20 30 40\n5 30 10 40\n"
      "3 1 4 1\n6 10 20 30 40\n"
      "$EndElements\n";
  SurfaceMesh a = fw::read_surface(write("tet41.msh", v41));
  EXPECT_EQ(a.num_vertices(), 4);
  EXPECT_EQ(a.num_triangles(), 4);
  fw::check_closed_surface(a);
  EXPECT_NEAR(volume(a), 1.0 / 6.0, 1e-15);

  std::string v22 =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
      "$Nodes\n4\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 0 1\n$EndNodes\n"
      "$Elements\n6\n1 15 2 0 1 10\n"
      "2 2 2 0 1 10 30 20\n3 2 2 0 1 10 20 40\n4 2 2 0 1 20 30 40\n5 2 2 0 1 30 10 40\n"
      "6 4 2 0 1 10 20 30 40\n$EndElements\n";
  SurfaceMesh b = fw::read_surface(write("tet22.msh", v22));
  EXPECT_EQ(b.vertices, a.vertices);
  EXPECT_EQ(b.triangles, a.triangles);
}

TEST(Readers, ErrorsNameTheFileAndLine) {
  std::string obj = write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_EQ(expect_error(obj), obj + ":4: face corner '4' refers to no vertex (3 defined so far)");
  std::string off = write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(expect_error(off), off + ":4: vertex coordinate 'x' is not a number");
  std::string msh = write("bad.msh", "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n");
  EXPECT_EQ(expect_error(msh), msh + ":2: binary .msh files are not supported: save as ASCII");
  std::string stl = write("bad.stl", "not an stl");
  EXPECT_EQ(expect_error(stl), stl +
                                   ": neither a binary STL (10 bytes, fewer than the 84 of its "
                                   "header and facet count) nor an ASCII one (no leading "
                                   "'solid')");
  // A binary STL whose size disagrees with its facet count (one facet's 50 bytes missing).
  std::string binary(80, ' ');
  const uint32_t two = 2;
  binary.append(reinterpret_cast<const char*>(&two), 4);
  binary.append(50, '\0');
  stl = write("short.stl", binary);
  EXPECT_EQ(expect_error(stl), stl +
                                   ": neither a binary STL (134 bytes, but its facet count 2 "
                                   "needs 84 + 50 x 2 = 184) nor an ASCII one (no leading "
                                   "'solid')");
  EXPECT_EQ(expect_error(temp_path("missing.obj")),
            temp_path("missing.obj") + ": cannot open the file");
  EXPECT_NE(expect_error(write("mesh.ply", "")).find("unknown mesh format '.ply'"),
            std::string::npos);
}

namespace {

// A fresh folder for one test's files, removed with the object.
class TempFolder {
 public:
  TempFolder() {
    std::string pattern = scratch_folder() + "untrusted_XXXXXX";
    path_ = mkdtemp(pattern.data());
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ + "/" + name, std::ios::binary) << text;
    return path_ + "/" + name;
  }

 private:
  std::string path_;
};

}  // namespace

// Counts are checked against the file's size before anything is allocated for them: these
// files once took 16.8 GB (2^31 nodes in 330 bytes) or ended in std::bad_alloc and
// std::length_error. Each error names the file, the line and the count.
TEST(UntrustedReaders, CountsBeyondTheFilesSizeAreRefused) {
  TempFolder dir;
  const std::string tail = "1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n";
  const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n";
  std::string msh = dir.write("claim.msh", head + "1 2147483648 1 2147483648\n2 1 0 3\n" + tail);
  EXPECT_EQ(expect_error(msh).rfind(msh + ":5: claims 2147483648 nodes, more than the ", 0), 0u)
      << expect_error(msh);
  msh = dir.write("block.msh", head + "1 3 1 3\n2 1 0 2147483648\n" + tail);
  EXPECT_NE(expect_error(msh).find(":6: claims 2147483648 nodes in entity block 1"),
            std::string::npos);
  msh = dir.write("negative.msh", head + "1 3 1 3\n2 1 0 -3\n" + tail);
  EXPECT_NE(expect_error(msh).find(":6: claims -3 nodes in entity block 1: a count cannot be "
                                   "negative"),
            std::string::npos);
  msh = dir.write("v22.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n268435456\n");
  EXPECT_NE(expect_error(msh).find(":5: claims 268435456 nodes"), std::string::npos);

  const std::string faces = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  std::string off = dir.write("claim.off", "OFF\n715000000 1 0\n" + faces);
  EXPECT_NE(expect_error(off).find(off + ":2: claims 715000000 vertices"), std::string::npos);
  off = dir.write("negative.off", "OFF\n-5 1 0\n" + faces);
  EXPECT_EQ(expect_error(off), off + ":2: claims -5 vertices: a count cannot be negative");
  off = dir.write("faces.off", "OFF\n3 100000000 0\n" + faces);
  EXPECT_NE(expect_error(off).find(":2: claims 100000000 faces"), std::string::npos);
}

TEST(UntrustedReaders, NonFiniteCoordinatesAreRefused) {
  TempFolder dir;
  const std::string faces = "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";
  for (const std::string value : {"nan", "inf", "-inf", "1e999"}) {
    SCOPED_TRACE(value);
    const std::string obj =
        dir.write("bad.obj", "v 0 0 0\nv " + value + " 0 0\nv 0 1 0\nv 0 0 1\n" + faces);
    EXPECT_EQ(expect_error(obj), obj + ":2: coordinate '" + value + "' is not a finite number");
    const std::string off =
        dir.write("bad.off", "OFF\n4 1 0\n0 0 0\n" + value + " 0 0\n0 1 0\n0 0 1\n3 0 1 2\n");
    EXPECT_EQ(expect_error(off),
              off + ":4: vertex coordinate '" + value + "' is not a finite number");
    const std::string msh =
        dir.write("bad.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 " +
                                 value + " 0 0\n3 0 1 0\n$EndNodes\n");
    EXPECT_EQ(expect_error(msh), msh + ":7: x coordinate '" + value + "' is not a finite number");
    const std::string stl =
        dir.write("bad.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex " +
                                 value + " 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n");
    EXPECT_EQ(expect_error(stl),
              stl + ":5: vertex coordinate '" + value + "' is not a finite number");
  }
  // A binary STL with a NaN corner.
  std::string binary(80, ' ');
  const uint32_t one = 1;
  binary.append(reinterpret_cast<const char*>(&one), 4);
  float record[12] = {0, 0, 1, 0, 0, 0, std::nanf(""), 0, 0, 0, 1, 0};
  binary.append(reinterpret_cast<const char*>(record), 48);
  binary.append(2, '\0');
  const std::string stl = dir.write("bad_binary.stl", binary);
  EXPECT_EQ(expect_error(stl), stl + ": facet 1: a corner coordinate is not a finite number");
}

// Found by fuzzing surfaces (tests/fuzz/surface_mutations.py, docs/reliability.md): strtod and
// strtoll stop at a NUL, and the rest of the token was ignored: "-0.3\0" "09017" read as -0.3.
TEST(UntrustedReaders, ANulInsideANumberIsRefused) {
  TempFolder dir;
  const std::string nul("\0", 1);
  const std::string faces = "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";
  std::string obj =
      dir.write("nul.obj", "v 0 0 0\nv -0.3" + nul + "09017 0 0\nv 0 1 0\nv 0 0 1\n" + faces);
  EXPECT_EQ(expect_error(obj), obj + ":2: coordinate '-0.3\\x0009017' is not a number");
  std::string off =
      dir.write("nul.off", "OFF\n4 1 0\n0 0 0\n1 0 3." + nul + "5\n0 1 0\n0 0 1\n3 0 1 2\n");
  EXPECT_EQ(expect_error(off), off + ":4: vertex coordinate '3.\\x005' is not a number");
  std::string msh = dir.write("nul.msh",
                              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n"
                              "3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 1" +
                                  nul + " 1 1 2 3\n$EndElements\n");
  EXPECT_EQ(expect_error(msh), msh + ":12: expected an integer (element tag value), got '1\\x00'");
  std::string stl = dir.write("nul.stl",
                              "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                              "vertex 1 0 0" +
                                  nul + "7\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n");
  EXPECT_EQ(expect_error(stl), stl + ":5: vertex coordinate '0\\x007' is not a number");
}

// A token quoted by an error message had its bytes as they were: a \x1c or \x85 split the
// message's line, an escape sequence reached the terminal, a 1 MB token made a 1 MB message.
TEST(UntrustedReaders, MessagesWriteOutControlBytesAndShortenLongTokens) {
  TempFolder dir;
  std::string msh = dir.write("ctrl.msh",
                              "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n"
                              "1 0.5\x1c\x85\x1b[2J 0 0\n$EndNodes\n");
  EXPECT_EQ(expect_error(msh), msh + ":6: x coordinate '0.5\\x1c\\x85\\x1b[2J' is not a number");
  std::string off = dir.write("long.off", std::string(1000000, '9') + "\n");
  const std::string e = expect_error(off);
  EXPECT_EQ(e, off + ":1: expected the header 'OFF', got '" + std::string(40, '9') +
                   "' (1000000 characters)");
}

namespace {

// A tetrahedron of side s (volume s^3 / 6), its second vertex's x given as text if odd_x is.
std::string tetrahedron_obj(double s, const std::string& odd_x = "") {
  std::ostringstream out;
  out.precision(17);
  out << "v 0 0 0\nv ";
  if (odd_x.empty()) {
    out << s;
  } else {
    out << odd_x;
  }
  out << " 0 0\nv 0 " << s << " 0\nv 0 0 " << s << "\n";
  out << "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  return out.str();
}

}  // namespace

// Coordinates up to 1e308 were read, and the volume, the weight and the forces came out inf
// or NaN (printed "null", exit 0); a surface scaled by 1e-150 gave a weight of exactly 0.
TEST(UntrustedReaders, CoordinatesBeyond1e30AndSurfacesBelow1e30AreRefused) {
  TempFolder dir;
  std::string big = dir.write("big.obj", tetrahedron_obj(1, "1e31"));
  EXPECT_EQ(expect_error(big), big +
                                   ":2: coordinate '1e31' is beyond 1e30 in magnitude (the "
                                   "volume and the weight would overflow)");
  std::string off = dir.write("big.off", "OFF\n4 1 0\n0 0 0\n1 -1e308 0\n0 1 0\n0 0 1\n3 0 1 2\n");
  EXPECT_NE(expect_error(off).find(":4: vertex coordinate '-1e308' is beyond 1e30"),
            std::string::npos);
  // A binary STL's float32 reaches 3.4e38.
  std::string binary(80, ' ');
  const uint32_t one = 1;
  binary.append(reinterpret_cast<const char*>(&one), 4);
  float record[12] = {0, 0, 1, 0, 0, 0, 1e38f, 0, 0, 0, 1, 0};
  binary.append(reinterpret_cast<const char*>(record), 48);
  binary.append(2, '\0');
  std::string stl = dir.write("big.stl", binary);
  EXPECT_NE(expect_error(stl).find(stl + ": facet 1: corner coordinate 1e+38 is beyond 1e30"),
            std::string::npos)
      << expect_error(stl);

  // At the bounds: read, with the volume s^3 / 6 of the tetrahedron.
  for (double s : {1e30, 1e-29}) {
    SurfaceMesh m = fw::read_surface(dir.write("edge.obj", tetrahedron_obj(s)));
    fw::check_closed_surface(m);
    EXPECT_NEAR(volume(m), s * s * s / 6, 1e-14 * s * s * s);
  }
  std::string small = dir.write("small.obj", tetrahedron_obj(1e-150));
  EXPECT_EQ(expect_error(small), small +
                                     ": the surface spans only 1e-150 (the largest side of "
                                     "its bounding box): below 1e-30 its volume and weight "
                                     "underflow");
  std::string point = dir.write("point.off", "OFF\n3 1 0\n5 5 5\n5 5 5\n5 5 5\n3 0 1 2\n");
  EXPECT_NE(expect_error(point).find(": the surface spans only 0 "), std::string::npos);
}
