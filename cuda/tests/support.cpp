#include "support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <random>

namespace fwtest {

Options options(fluidweight::Implementation implementation, int n, Vec3 gravity) {
  Options o;
  o.implementation = implementation;
  o.grid = n;
  o.rho = 1000.0;
  o.gravity = gravity;
  return o;
}

std::vector<bool> e_shape_voxels() {
  // x: 0..4 along the arms, y: 0..4 up, z: 0..2. The bar is x = 0; arms at y = 0, 2, 4.
  const int nx = 5, ny = 5, nz = 3;
  std::vector<bool> occ(nx * ny * nz, false);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        bool bar = i == 0, arm = j % 2 == 0;
        occ[(k * ny + j) * nx + i] = bar || arm;
      }
    }
  }
  return occ;
}

SurfaceMesh e_shape() { return fluidweight::shapes::voxels(5, 5, 3, e_shape_voxels()); }

SurfaceMesh comb(int teeth) {
  const int nx = 4, ny = 2 * teeth - 1, nz = 2;
  std::vector<bool> occ(nx * ny * nz, false);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) occ[(k * ny + j) * nx + i] = i == 0 || j % 2 == 0;
    }
  }
  return fluidweight::shapes::voxels(nx, ny, nz, occ, {1.0, 0.25, 1.0});
}

SurfaceMesh box(Vec3 size, int sub) {
  std::vector<bool> occ(sub * sub * sub, true);
  return fluidweight::shapes::voxels(sub, sub, sub, occ,
                                     {size[0] / sub, size[1] / sub, size[2] / sub});
}

SurfaceMesh octahedron(Vec3 c, double h) {
  SurfaceMesh m;
  m.vertices = {c[0] + h, c[1],     c[2], c[0] - h, c[1], c[2],     c[0], c[1] + h, c[2],
                c[0],     c[1] - h, c[2], c[0],     c[1], c[2] + h, c[0], c[1],     c[2] - h};
  // Outward: x+ y+ z+ is counter-clockwise seen from outside.
  m.triangles = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return m;
}

SurfaceMesh translated(const SurfaceMesh& mesh, Vec3 shift) {
  SurfaceMesh m = mesh;
  for (size_t v = 0; v < m.vertices.size(); ++v) m.vertices[v] += shift[v % 3];
  return m;
}

Vec3 apply(const Mat3& r, Vec3 v) {
  Vec3 out{0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out[i] += r[i][j] * v[j];
  }
  return out;
}

SurfaceMesh transformed(const SurfaceMesh& mesh, const Mat3& rotation) {
  SurfaceMesh m = mesh;
  for (size_t v = 0; v < m.vertices.size(); v += 3) {
    Vec3 p = apply(rotation, {mesh.vertices[v], mesh.vertices[v + 1], mesh.vertices[v + 2]});
    for (int d = 0; d < 3; ++d) m.vertices[v + d] = p[d];
  }
  return m;
}

SurfaceMesh flipped(const SurfaceMesh& mesh) {
  SurfaceMesh m = mesh;
  for (size_t t = 0; t < m.triangles.size(); t += 3)
    std::swap(m.triangles[t + 1], m.triangles[t + 2]);
  return m;
}

SurfaceMesh shuffled(const SurfaceMesh& mesh, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<int> order(mesh.num_triangles());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  SurfaceMesh m = mesh;
  m.triangles.clear();
  for (int t : order) {
    int start = static_cast<int>(rng() % 3);
    for (int k = 0; k < 3; ++k) m.triangles.push_back(mesh.triangles[3 * t + (start + k) % 3]);
  }
  return m;
}

Mat3 rotation(Vec3 a, double angle) {
  double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  double x = a[0] / n, y = a[1] / n, z = a[2] / n;
  return Mat3{{{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
               {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
               {t * x * z - s * y, t * y * z + s * x, t * z * z + c}}};
}

double volume(const SurfaceMesh& m) {
  double v = 0;
  for (size_t t = 0; t < m.triangles.size(); t += 3) {
    const double* a = &m.vertices[3 * m.triangles[t]];
    const double* b = &m.vertices[3 * m.triangles[t + 1]];
    const double* c = &m.vertices[3 * m.triangles[t + 2]];
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v / 6;
}

Vec3 centroid(const SurfaceMesh& m) {
  // Each tetrahedron (origin, a, b, c) has signed volume a.(b x c)/6 and centroid (a+b+c)/4.
  Vec3 sum{0, 0, 0};
  double vol = 0;
  for (size_t t = 0; t < m.triangles.size(); t += 3) {
    const double* a = &m.vertices[3 * m.triangles[t]];
    const double* b = &m.vertices[3 * m.triangles[t + 1]];
    const double* c = &m.vertices[3 * m.triangles[t + 2]];
    double v = (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                a[2] * (b[0] * c[1] - b[1] * c[0])) /
               6;
    for (int d = 0; d < 3; ++d) sum[d] += v * (a[d] + b[d] + c[d]) / 4;
    vol += v;
  }
  return {sum[0] / vol, sum[1] / vol, sum[2] / vol};
}

Vec3 total_force(const Result& r) {
  Vec3 f{0, 0, 0};
  for (size_t i = 0; i < r.forces.size(); ++i) f[i % 3] += r.forces[i];
  return f;
}

Vec3 total_moment(const SurfaceMesh& mesh, const Result& r) {
  Vec3 m{0, 0, 0};
  for (size_t v = 0; v < r.forces.size(); v += 3) {
    const double* x = &mesh.vertices[v];
    const double* f = &r.forces[v];
    m[0] += x[1] * f[2] - x[2] * f[1];
    m[1] += x[2] * f[0] - x[0] * f[2];
    m[2] += x[0] * f[1] - x[1] * f[0];
  }
  return m;
}

double force_difference(const Result& f, const Result& g) {
  double worst = 0, scale = 0;
  for (size_t v = 0; v < g.forces.size(); v += 3) {
    double d = 0, s = 0;
    for (int k = 0; k < 3; ++k) {
      d += std::pow(f.forces[v + k] - g.forces[v + k], 2);
      s += std::pow(g.forces[v + k], 2);
    }
    worst = std::max(worst, std::sqrt(d));
    scale = std::max(scale, std::sqrt(s));
  }
  return scale > 0 ? worst / scale : worst;
}

namespace {

struct ScratchFolder {
  std::string path;
  ScratchFolder() {
    std::string pattern = testing::TempDir() + "fluidweight_test_XXXXXX";
    if (mkdtemp(pattern.data())) path = pattern + "/";
  }
  ~ScratchFolder() {
    std::error_code ignored;
    if (!path.empty()) std::filesystem::remove_all(path, ignored);
  }
};

}  // namespace

const std::string& scratch_folder() {
  static const ScratchFolder folder;
  return folder.path;
}

}  // namespace fwtest
