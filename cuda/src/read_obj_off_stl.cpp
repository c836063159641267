// Readers for .obj, .off and .stl surfaces, and the dispatch by extension.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>

#include "fluidweight/mesh_io.hpp"
#include "text_reader.hpp"

namespace fluidweight {
namespace {

// Appends the fan (c0, c_k, c_k+1) of a polygon.
void add_fan(const std::vector<int>& corners, SurfaceMesh& mesh) {
  for (size_t k = 1; k + 1 < corners.size(); ++k) {
    mesh.triangles.insert(mesh.triangles.end(), {corners[0], corners[k], corners[k + 1]});
  }
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

}  // namespace

SurfaceMesh read_obj(const std::string& path) {
  detail::TextReader in(path, detail::read_file(path));
  SurfaceMesh mesh;
  while (!in.at_end()) {
    int line_number = in.line_number();
    std::vector<std::string> t = split(in.line());
    auto fail = [&](const std::string& why) {
      throw InputError(path + ":" + std::to_string(line_number) + ": " + why);
    };
    if (t.empty()) continue;
    if (t[0] == "v") {
      if (t.size() < 4) fail("a vertex needs 3 coordinates");
      for (int d = 1; d <= 3; ++d) {
        double x = 0;
        std::string problem = detail::coordinate_problem(t[d], x);
        if (!problem.empty()) fail("coordinate " + detail::quoted(t[d]) + " " + problem);
        mesh.vertices.push_back(x);
      }
    } else if (t[0] == "f") {
      if (t.size() < 4) fail("a face needs at least 3 corners");
      std::vector<int> corners;
      for (size_t k = 1; k < t.size(); ++k) {
        // "v", "v/vt", "v//vn" or "v/vt/vn"; negative indices count back from the last vertex.
        char* end = nullptr;
        long index = std::strtol(t[k].c_str(), &end, 10);
        const char* stop = t[k].c_str() + t[k].size();
        if (end == t[k].c_str() || (end != stop && *end != '/')) {
          fail("bad face corner " + detail::quoted(t[k]));
        }
        long nv = mesh.num_vertices();
        long v = index > 0 ? index - 1 : nv + index;
        if (index == 0 || v < 0 || v >= nv) {
          fail("face corner " + detail::quoted(t[k]) + " refers to no vertex (" +
               std::to_string(nv) + " defined so far)");
        }
        corners.push_back(static_cast<int>(v));
      }
      add_fan(corners, mesh);
    }
    // Normals, texture coordinates, groups, materials and lines carry no geometry we need.
  }
  return mesh;
}

SurfaceMesh read_off(const std::string& path) {
  detail::TextReader in(path, detail::read_file(path));
  in.set_comments(true);
  std::string header = in.token();
  if (header != "OFF") in.fail("expected the header 'OFF', got " + detail::quoted(header));
  long long nv = in.integer("vertex count"), nf = in.integer("face count");
  in.integer("edge count");
  // Checked against the file's size before anything is allocated for them: a vertex takes at
  // least "0 0 0\n", a face "3 0 1 2\n".
  in.check_count(nv, 6, "vertices");
  in.check_count(nf, 8, "faces");
  if (nv > INT32_MAX / 3) in.fail("more than " + std::to_string(INT32_MAX / 3) + " vertices");
  in.line();
  SurfaceMesh mesh;
  mesh.vertices.reserve(3 * nv);
  for (long long v = 0; v < nv; ++v) {
    for (int d = 0; d < 3; ++d) mesh.vertices.push_back(in.coordinate("vertex coordinate"));
    in.line();  // optional colour values
  }
  for (long long f = 0; f < nf; ++f) {
    long long count = in.integer("corner count");
    if (count < 3) in.fail("face " + std::to_string(f) + " has fewer than 3 corners");
    std::vector<int> corners;
    for (long long k = 0; k < count; ++k) {
      long long v = in.integer("vertex index");
      if (v < 0 || v >= nv) {
        in.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                ", outside [0, " + std::to_string(nv) + ")");
      }
      corners.push_back(static_cast<int>(v));
    }
    add_fan(corners, mesh);
    // Optional colour values end the face's line.
    in.line();
  }
  return mesh;
}

namespace {

// Merges equal corners of STL facets, in order of first appearance.
struct CornerMerger {
  SurfaceMesh mesh;
  std::map<std::array<double, 3>, int> ids;
  void facet(const std::array<std::array<double, 3>, 3>& c) {
    int v[3];
    for (int k = 0; k < 3; ++k) {
      auto [it, inserted] = ids.emplace(c[k], static_cast<int>(ids.size()));
      if (inserted) mesh.vertices.insert(mesh.vertices.end(), c[k].begin(), c[k].end());
      v[k] = it->second;
    }
    if (v[0] != v[1] && v[1] != v[2] && v[2] != v[0]) {
      mesh.triangles.insert(mesh.triangles.end(), {v[0], v[1], v[2]});
    }
  }
};

SurfaceMesh read_stl_binary(const std::string& path, const std::string& bytes) {
  uint32_t count;
  std::memcpy(&count, bytes.data() + 80, 4);
  CornerMerger merger;
  for (uint32_t f = 0; f < count; ++f) {
    const char* facet = bytes.data() + 84 + 50 * static_cast<size_t>(f) + 12;  // after normal
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k) {
      for (int d = 0; d < 3; ++d) {
        float x;
        std::memcpy(&x, facet + 4 * (3 * k + d), 4);
        if (!std::isfinite(x)) {
          throw InputError(path + ": facet " + std::to_string(f + 1) +
                           ": a corner coordinate is not a finite number");
        }
        if (std::fabs(x) > kMaxCoordinate) {
          std::ostringstream msg;
          msg << path << ": facet " << f + 1 << ": corner coordinate " << x
              << " is beyond 1e30 in magnitude (the volume and the weight would overflow)";
          throw InputError(msg.str());
        }
        c[k][d] = x;
      }
    }
    merger.facet(c);
  }
  return std::move(merger.mesh);
}

SurfaceMesh read_stl_ascii(const std::string& path, std::string text) {
  detail::TextReader in(path, std::move(text));
  CornerMerger merger;
  if (in.token() != "solid") in.fail("an ASCII STL starts with 'solid'");
  in.line();  // the solid's name
  for (;;) {
    std::string word = in.token();
    if (word == "endsolid") break;
    if (word != "facet") in.fail("expected 'facet' or 'endsolid', got " + detail::quoted(word));
    in.line();  // normal: recomputed from the corners
    if (in.token() != "outer" || in.token() != "loop") in.fail("expected 'outer loop'");
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k) {
      if (in.token() != "vertex") in.fail("expected 'vertex' (facets must be triangles)");
      for (int d = 0; d < 3; ++d) c[k][d] = in.coordinate("vertex coordinate");
    }
    if (in.token() != "endloop") in.fail("expected 'endloop' (facets must be triangles)");
    if (in.token() != "endfacet") in.fail("expected 'endfacet'");
    merger.facet(c);
  }
  return std::move(merger.mesh);
}

}  // namespace

SurfaceMesh read_stl(const std::string& path) {
  std::string bytes = detail::read_file(path);
  // Binary: an 80-byte header, a facet count, 50 bytes a facet. Some binary files start with
  // "solid" too, so the size decides first.
  if (bytes.size() >= 84) {
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * static_cast<size_t>(count)) return read_stl_binary(path, bytes);
  }
  if (bytes.compare(0, 5, "solid") == 0) return read_stl_ascii(path, std::move(bytes));
  std::ostringstream msg;
  msg << path << ": neither a binary STL (";
  if (bytes.size() < 84) {
    msg << bytes.size() << " bytes, fewer than the 84 of its header and facet count";
  } else {
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    msg << bytes.size() << " bytes, but its facet count " << count << " needs 84 + 50 x " << count
        << " = " << 84 + 50 * static_cast<uint64_t>(count);
  }
  msg << ") nor an ASCII one (no leading 'solid')";
  throw InputError(msg.str());
}

namespace {

// A surface smaller than kMinExtent has a volume and nodal weights below a double's range.
void check_extent(const SurfaceMesh& mesh, const std::string& path) {
  if (mesh.vertices.empty()) return;  // no triangles either: the closed-surface check says so
  double largest = 0;
  for (int d = 0; d < 3; ++d) {
    double lo = mesh.vertices[d], hi = lo;
    for (size_t k = d; k < mesh.vertices.size(); k += 3) {
      lo = std::min(lo, mesh.vertices[k]);
      hi = std::max(hi, mesh.vertices[k]);
    }
    largest = std::max(largest, hi - lo);
  }
  if (largest < kMinExtent) {
    std::ostringstream msg;
    msg << path << ": the surface spans only " << largest
        << " (the largest side of its bounding box): below 1e-30 its volume and weight "
           "underflow";
    throw InputError(msg.str());
  }
}

SurfaceMesh read_by_extension(const std::string& path) {
  std::string ext;
  size_t dot = path.find_last_of('.');
  if (dot != std::string::npos) ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "obj") return read_obj(path);
  if (ext == "off") return read_off(path);
  if (ext == "stl") return read_stl(path);
  if (ext == "msh") return read_msh(path);
  throw InputError(path + ": unknown mesh format " + detail::quoted("." + ext) +
                   " (expected .obj, .off, .stl, .msh)");
}

}  // namespace

SurfaceMesh read_surface(const std::string& path) {
  SurfaceMesh mesh = read_by_extension(path);
  check_extent(mesh, path);
  return mesh;
}

}  // namespace fluidweight
