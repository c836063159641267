#include "fluidweight/shapes.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace fluidweight::shapes {

SurfaceMesh icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                          {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                          {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  auto to_sphere = [](std::array<double, 3> q) {
    double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    return std::array<double, 3>{q[0] / n, q[1] / n, q[2] / n};
  };
  for (auto& q : p) q = to_sphere(q);
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back(
          to_sphere({(p[a][0] + p[b][0]) / 2, (p[a][1] + p[b][1]) / 2, (p[a][2] + p[b][2]) / 2}));
      return midpoint[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tri : f) {
      int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
      g.push_back({tri[0], ab, ca});
      g.push_back({tri[1], bc, ab});
      g.push_back({tri[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  SurfaceMesh mesh;
  for (const auto& q : p) {
    for (int d = 0; d < 3; ++d) mesh.vertices.push_back(radius * q[d]);
  }
  for (const auto& tri : f) mesh.triangles.insert(mesh.triangles.end(), tri.begin(), tri.end());
  return mesh;
}

SurfaceMesh torus(double R, double r, int nu, int nv) {
  SurfaceMesh mesh;
  const double pi = std::acos(-1.0);
  for (int a = 0; a < nu; ++a) {
    for (int b = 0; b < nv; ++b) {
      double u = 2 * pi * a / nu, v = 2 * pi * b / nv;
      mesh.vertices.push_back((R + r * std::cos(v)) * std::cos(u));
      mesh.vertices.push_back(r * std::sin(v));
      mesh.vertices.push_back((R + r * std::cos(v)) * std::sin(u));
    }
  }
  auto id = [&](int a, int b) { return (a % nu) * nv + (b % nv); };
  for (int a = 0; a < nu; ++a) {
    for (int b = 0; b < nv; ++b) {
      // Outward: d/dv x d/du points away from the tube's axis with this parametrization.
      int q0 = id(a, b), q1 = id(a + 1, b), q2 = id(a + 1, b + 1), q3 = id(a, b + 1);
      mesh.triangles.insert(mesh.triangles.end(), {q0, q2, q1, q0, q3, q2});
    }
  }
  return mesh;
}

SurfaceMesh voxels(int nx, int ny, int nz, const std::vector<bool>& occupied,
                   const std::array<double, 3>& size, const std::array<double, 3>& origin) {
  auto filled = [&](int i, int j, int k) {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return false;
    return static_cast<bool>(occupied[(static_cast<size_t>(k) * ny + j) * nx + i]);
  };
  SurfaceMesh mesh;
  std::map<std::array<int, 3>, int> ids;
  auto vertex = [&](std::array<int, 3> q) {
    auto it = ids.find(q);
    if (it != ids.end()) return it->second;
    for (int d = 0; d < 3; ++d) mesh.vertices.push_back(origin[d] + size[d] * q[d]);
    return ids[q] = static_cast<int>(ids.size());
  };
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        if (!filled(i, j, k)) continue;
        const int cell[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          for (int side = 0; side < 2; ++side) {
            int nb[3] = {i, j, k};
            nb[d] += side ? 1 : -1;
            if (filled(nb[0], nb[1], nb[2])) continue;
            // Corners (0,0), (1,0), (1,1), (0,1) along the axes d+1, d+2: normal +d.
            int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
            int c[4];
            const int steps[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int q = 0; q < 4; ++q) {
              std::array<int, 3> corner = {cell[0], cell[1], cell[2]};
              corner[d] += side;
              corner[d1] += steps[q][0];
              corner[d2] += steps[q][1];
              c[q] = vertex(corner);
            }
            if (side) {
              mesh.triangles.insert(mesh.triangles.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
            } else {
              mesh.triangles.insert(mesh.triangles.end(), {c[0], c[2], c[1], c[0], c[3], c[2]});
            }
          }
        }
      }
    }
  }
  return mesh;
}

SurfaceMesh uneven_sphere(int levels, double factor, double radius) {
  SurfaceMesh mesh = icosphere(levels, 1.0);
  for (size_t v = 0; v < mesh.vertices.size(); v += 3) {
    double x = mesh.vertices[v], y = mesh.vertices[v + 1], z = mesh.vertices[v + 2];
    if (y > 1.0 - 1e-12) {  // the projection's pole stays where it is
      for (int d = 0; d < 3; ++d) mesh.vertices[v + d] *= radius;
      continue;
    }
    double X = factor * x / (1.0 - y), Z = factor * z / (1.0 - y);
    double r2 = X * X + Z * Z;
    mesh.vertices[v] = radius * 2 * X / (r2 + 1);
    mesh.vertices[v + 1] = radius * (r2 - 1) / (r2 + 1);
    mesh.vertices[v + 2] = radius * 2 * Z / (r2 + 1);
  }
  return mesh;
}

}  // namespace fluidweight::shapes
