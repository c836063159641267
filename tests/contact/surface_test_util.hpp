// Closed triangle surfaces for the tests of surface obstacles, and their files: an
// axis-aligned box of 12 triangles, an icosphere refined `level` times onto a sphere, written
// as binary or ASCII STL (every facet with its own corners, as STL repeats them) or OBJ.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace hs_test {

struct Surface {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside
};

inline Surface box_surface(const Eigen::Vector3d& center, const Eigen::Vector3d& size) {
  Surface s;
  for (int k = 0; k < 8; ++k)
    s.vertices.push_back(center + 0.5 * Eigen::Vector3d((k & 1) ? size(0) : -size(0),
                                                        (k & 2) ? size(1) : -size(1),
                                                        (k & 4) ? size(2) : -size(2)));
  // Corner k has x, y, z high where bits 0, 1, 2 are set.
  s.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

inline Surface icosphere(int level, double radius) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Surface s;
  for (auto p : std::vector<Eigen::Vector3d>{{-1, t, 0},
                                             {1, t, 0},
                                             {-1, -t, 0},
                                             {1, -t, 0},
                                             {0, -1, t},
                                             {0, 1, t},
                                             {0, -1, -t},
                                             {0, 1, -t},
                                             {t, 0, -1},
                                             {t, 0, 1},
                                             {-t, 0, -1},
                                             {-t, 0, 1}})
    s.vertices.push_back(radius * p.normalized());
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      s.vertices.push_back(radius * (s.vertices[a] + s.vertices[b]).normalized());
      return middle[key] = static_cast<int>(s.vertices.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : s.triangles) {
      const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
    }
    s.triangles = std::move(finer);
  }
  return s;
}

inline void write_stl_binary(const std::string& path, const Surface& s) {
  std::string bytes(80, ' ');
  const uint32_t count = static_cast<uint32_t>(s.triangles.size());
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : s.triangles) {
    float values[12] = {0, 0, 0};  // the normal: readers recompute it
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) values[3 + 3 * k + d] = static_cast<float>(s.vertices[f[k]](d));
    bytes.append(reinterpret_cast<const char*>(values), sizeof values);
    bytes.append(2, '\0');
  }
  std::ofstream(path, std::ios::binary) << bytes;
}

inline void write_stl_ascii(const std::string& path, const Surface& s) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid test\n";
  for (const auto& f : s.triangles) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k)
      out << "   vertex " << s.vertices[f[k]](0) << " " << s.vertices[f[k]](1) << " "
          << s.vertices[f[k]](2) << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid test\n";
}

// `relative`: faces by negative indices, counted back from the last vertex.
inline void write_obj(const std::string& path, const Surface& s, bool relative = false) {
  std::ofstream out(path);
  out.precision(17);
  out << "# a test surface\no test\n";
  for (const auto& v : s.vertices) out << "v " << v(0) << " " << v(1) << " " << v(2) << "\n";
  const int n = static_cast<int>(s.vertices.size());
  for (const auto& f : s.triangles) {
    out << "f";
    for (int k = 0; k < 3; ++k) out << " " << (relative ? f[k] - n : f[k] + 1);
    out << "\n";
  }
}

}  // namespace hs_test
