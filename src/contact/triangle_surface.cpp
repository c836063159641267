// The closest point of a triangle by its Voronoi regions (the face, three edges, three
// vertices), found through a tree of the triangles' boxes (box_tree.hpp),
// and the sign from the closest feature's pseudo-normal: the face's normal, an edge's the sum
// of its two faces' normals, a vertex's the sum of its faces' normals weighted by their
// angles there (the weights that make the sign right at a vertex, where the plain sum fails).
#include "contact/triangle_surface.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace hs {
namespace {

using Point = Eigen::Vector3d;

enum class Feature { face, edge, vertex };

struct Closest {
  Point point;
  Feature feature = Feature::face;
  int local = 0;  // vertex k, or edge k from vertex k to vertex k + 1
};

Closest closest_on_triangle(const Point& p, const Point& a, const Point& b, const Point& c) {
  const Point ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, Feature::vertex, 0};
  const Point bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, Feature::vertex, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {a + d1 / (d1 - d3) * ab, Feature::edge, 0};
  const Point cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, Feature::vertex, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {a + d2 / (d2 - d6) * ac, Feature::edge, 2};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return {b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b), Feature::edge, 1};
  const double scale = 1 / (va + vb + vc);
  return {a + ab * (vb * scale) + ac * (vc * scale), Feature::face, 0};
}

}  // namespace

TriangleSurface::TriangleSurface(std::vector<Point> vertices,
                                 std::vector<std::array<int, 3>> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  const size_t nt = triangles_.size();
  face_normal_.resize(nt);
  vertex_normal_.assign(vertices_.size(), Point::Zero());
  auto directed = [](int a, int b) { return uint64_t(uint32_t(a)) << 32 | uint32_t(b); };
  std::unordered_map<uint64_t, int> edge_owner;  // directed edge -> 3 t + k
  edge_owner.reserve(3 * nt);
  for (size_t t = 0; t < nt; ++t) {
    const auto& v = triangles_[t];
    face_normal_[t] =
        (vertices_[v[1]] - vertices_[v[0]]).cross(vertices_[v[2]] - vertices_[v[0]]).normalized();
    for (int k = 0; k < 3; ++k) {
      const Point u = vertices_[v[(k + 1) % 3]] - vertices_[v[k]],
                  w = vertices_[v[(k + 2) % 3]] - vertices_[v[k]];
      vertex_normal_[v[k]] += std::atan2(u.cross(w).norm(), u.dot(w)) * face_normal_[t];
      edge_owner[directed(v[k], v[(k + 1) % 3])] = static_cast<int>(3 * t + k);
    }
  }
  constexpr double kFlat = 1 - 1e-12;  // cosine of the angle between normals
  edge_normal_.assign(3 * nt, Point::Zero());
  flat_edge_.assign(3 * nt, 0);
  flat_vertex_.assign(vertices_.size(), 1);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto other = edge_owner.find(directed(triangles_[t][(k + 1) % 3], triangles_[t][k]));
      edge_normal_[3 * t + k] = face_normal_[t];
      if (other == edge_owner.end()) continue;
      const Point& n = face_normal_[other->second / 3];
      edge_normal_[3 * t + k] += n;
      flat_edge_[3 * t + k] = face_normal_[t].dot(n) >= kFlat;
      const int v = triangles_[t][k];
      if (face_normal_[t].dot(vertex_normal_[v].normalized()) < kFlat) flat_vertex_[v] = 0;
    }
  std::vector<Eigen::AlignedBox3d> boxes(nt);
  for (size_t t = 0; t < nt; ++t)
    for (int v : triangles_[t]) boxes[t].extend(vertices_[v]);
  tree_ = std::make_unique<BoxTree>(std::move(boxes));
}

SignedDistance TriangleSurface::distance(const Point& x) const {
  double best = std::numeric_limits<double>::infinity();
  int best_triangle = -1;
  Closest closest;
  tree_->nearest(x, best, [&](int t) {
    const auto& v = triangles_[t];
    const Closest c = closest_on_triangle(x, vertices_[v[0]], vertices_[v[1]], vertices_[v[2]]);
    const double squared = (x - c.point).squaredNorm();
    if (squared < best) {
      best = squared;
      best_triangle = t;
      closest = c;
    }
  });
  SignedDistance out;
  if (best_triangle < 0) return out;
  const Point v = x - closest.point;
  const auto& corners = triangles_[best_triangle];
  const bool flat =
      closest.feature == Feature::face ||
      (closest.feature == Feature::edge ? flat_edge_[3 * best_triangle + closest.local]
                                        : flat_vertex_[corners[closest.local]]);
  if (flat) {  // d along the face's normal
    out.gradient = face_normal_[best_triangle];
    out.d = out.gradient.dot(x - vertices_[triangles_[best_triangle][0]]);
    return out;
  }
  const Point pseudo = closest.feature == Feature::vertex
                           ? vertex_normal_[corners[closest.local]]
                           : edge_normal_[3 * best_triangle + closest.local];
  const double r = std::sqrt(best);
  if (r == 0) {  // on the surface: d = 0, the node is refused; a direction all the same
    out.gradient = pseudo.normalized();
    return out;
  }
  const double sign = pseudo.dot(v) >= 0 ? 1.0 : -1.0;
  out.d = sign * r;
  out.gradient = sign * v / r;
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  if (closest.feature == Feature::edge) {
    const Point t =
        (vertices_[corners[(closest.local + 1) % 3]] - vertices_[corners[closest.local]])
            .normalized();
    P -= t * t.transpose();
  }
  out.hessian = (P - out.gradient * out.gradient.transpose()) / out.d;
  return out;
}

}  // namespace hs
