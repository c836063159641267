// Host side of Step 1: the columns' frame, the signed volume and the grid of a cavity.
#include <algorithm>
#include <cmath>
#include <limits>

#include "cpu.hpp"

namespace fluidweight::detail {

Frame make_frame(const std::array<double, 3>& gravity) {
  double norm =
      std::sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    throw InputError("gravity: the vector must be finite and non-zero");
  }
  Vec3 up{-gravity[0] / norm, -gravity[1] / norm, -gravity[2] / norm};
  // e1 is the axis after the one most aligned with up (cyclically), made orthogonal to up, and
  // e2 = up x e1: gravity along -y gives (e1, e2, up) = (z, x, y), exactly.
  double c[3] = {std::fabs(up.x), std::fabs(up.y), std::fabs(up.z)};
  int m = static_cast<int>(std::max_element(c, c + 3) - c);
  double a[3] = {0, 0, 0};
  a[(m + 1) % 3] = 1.0;
  Vec3 axis{a[0], a[1], a[2]};
  double along = dot_rn(axis, up);
  Vec3 e1{axis.x - along * up.x, axis.y - along * up.y, axis.z - along * up.z};
  double n1 = std::sqrt(dot_rn(e1, e1));
  e1 = Vec3{e1.x / n1, e1.y / n1, e1.z / n1};
  Vec3 e2{up.y * e1.z - up.z * e1.y, up.z * e1.x - up.x * e1.z, up.x * e1.y - up.y * e1.x};
  return Frame{e1, e2, up};
}

double signed_volume(const CavityView& cavity) {
  if (cavity.num_vertices == 0) return 0.0;
  Vec3 o = load_vec3(cavity.xyz, 0);
  double sum = 0.0;
  for (int t = 0; t < cavity.num_triangles; ++t) {
    const int* v = cavity.triangles + 3 * t;
    Vec3 a = load_vec3(cavity.xyz, v[0]), b = load_vec3(cavity.xyz, v[1]),
         c = load_vec3(cavity.xyz, v[2]);
    double ax = a.x - o.x, ay = a.y - o.y, az = a.z - o.z;
    double bx = b.x - o.x, by = b.y - o.y, bz = b.z - o.z;
    double cx = c.x - o.x, cy = c.y - o.y, cz = c.z - o.z;
    sum += ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
  }
  return sum / 6.0;
}

GridParams grid_for(const CavityView& cavity, const Frame& frame, int n, double volume) {
  double inf = std::numeric_limits<double>::infinity();
  double amin = inf, amax = -inf, bmin = inf, bmax = -inf, umin = inf, umax = -inf;
  for (int v = 0; v < cavity.num_vertices; ++v) {
    Vec3 p = load_vec3(cavity.xyz, v);
    double a = dot_rn(p, frame.e1), b = dot_rn(p, frame.e2), u = dot_rn(p, frame.up);
    amin = std::min(amin, a);
    amax = std::max(amax, a);
    bmin = std::min(bmin, b);
    bmax = std::max(bmax, b);
    umin = std::min(umin, u);
    umax = std::max(umax, u);
  }
  return make_grid(amin, amax, bmin, bmax, umin, umax, n, volume);
}

}  // namespace fluidweight::detail
