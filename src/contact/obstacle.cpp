// Signed distances of the obstacle shapes (obstacle.hpp). Where the closest point is a
// single point of the surface (a box's corner, the whole sphere) d = |x - c| - r and
// H = (I - n n^T) / |x - c|; along an edge or a cylinder the same in the plane normal to
// the axis; flat parts have H = 0.
#include "contact/obstacle.hpp"

#include <algorithm>
#include <cmath>

#include "contact/triangle_surface.hpp"

namespace hs {
namespace {

using Point = Eigen::Vector3d;

Point vec(const std::array<double, 3>& a) { return Point(a[0], a[1], a[2]); }

// Distance r from a point at offset v from the closest point set, curving in the subspace P
// (a projector): d = |P v| - radius.
SignedDistance round_distance(const Point& v, const Eigen::Matrix3d& P, double radius) {
  SignedDistance out;
  const Point w = P * v;
  const double r = w.norm();
  out.d = r - radius;
  if (r == 0) return out;  // on the axis or the centre: no direction (d = -radius, inside)
  out.gradient = w / r;
  out.hessian = (P - out.gradient * out.gradient.transpose()) / r;
  return out;
}

SignedDistance box_distance(const Point& x, const Point& center, const Point& half) {
  const Point v = x - center;
  Point q;
  for (int i = 0; i < 3; ++i) q(i) = std::abs(v(i)) - half(i);
  SignedDistance out;
  if (q.maxCoeff() <= 0) {  // inside: the nearest face
    int i = 0;
    q.maxCoeff(&i);
    out.d = q(i);
    out.gradient(i) = v(i) >= 0 ? 1 : -1;
    return out;
  }
  // Outside: the nearest point clamps the coordinates beyond the box; those axes curve.
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  Point w = Point::Zero();
  for (int i = 0; i < 3; ++i)
    if (q(i) > 0) {
      P(i, i) = 1;
      w(i) = v(i) >= 0 ? q(i) : -q(i);
    }
  return round_distance(w, P, 0.0);
}

// How far along x + t step (t <= 1) a node can go with a gap of at least a tenth of its gap
// d0 to a surface obstacle, which need not be convex: no point of the surface is nearer x
// than its unsigned distance, so a move shorter than that cannot reach it. Advanced by that
// bound again and again (conservative advancement), it stops where the gap nears a tenth of
// d0: at once for a node moving straight at a face (the plane's own bound), after a few
// queries for one that slides along the surface or leaves it.
double surface_advance(const ObstacleShape& o, const Eigen::Vector3d& x,
                       const Eigen::Vector3d& step, double s, double d0) {
  const double length = step.norm(), keep = 0.1 * d0;
  if (!(length > 0)) return 1;
  double t = 0, gap = d0;
  for (int k = 0; k < 32 && t < 1; ++k) {
    const double advance = (gap - keep) / length;
    if (advance <= 1e-3 * (gap / length)) break;  // within a thousandth of the keep gap
    t += advance;
    if (t >= 1) return 1;
    gap = std::abs(signed_distance(o, x + t * step, s).d);
  }
  return std::min(t, 1.0);
}

// The distance from the shape as the deck gives it, unmoved and unturned.
SignedDistance shape_distance(const ObstacleShape& o, const Point& x) {
  switch (o.type) {
    case ObstacleType::plane: {
      SignedDistance out;
      out.gradient = vec(o.normal);
      out.d = out.gradient.dot(x - vec(o.point));
      return out;
    }
    case ObstacleType::sphere:
      return round_distance(x - vec(o.center), Eigen::Matrix3d::Identity(), o.radius);
    case ObstacleType::cylinder: {
      const Point a = vec(o.axis);
      return round_distance(x - vec(o.center), Eigen::Matrix3d::Identity() - a * a.transpose(),
                            o.radius);
    }
    case ObstacleType::box:
      return box_distance(x, vec(o.center), 0.5 * vec(o.size));
    case ObstacleType::surface:
      return o.surface ? o.surface->distance(x) : SignedDistance{};
  }
  return {};
}

Eigen::Matrix3d rotation_matrix(const std::array<double, 3>& degrees, double s) {
  const Point v = s * M_PI / 180 * vec(degrees);
  const double angle = v.norm();
  if (angle == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

}  // namespace

Point pivot(const ObstacleShape& o) {
  switch (o.type) {
    case ObstacleType::plane:
      return vec(o.point);
    case ObstacleType::surface:
      return vec(o.pivot);
    default:
      return vec(o.center);
  }
}

Eigen::Matrix3d orientation(const ObstacleShape& o, double s) {
  return rotation_matrix(o.turn, s) * rotation_matrix(o.rotation, 1);
}

// The point x taken back to the shape's own frame (x = p + s move + Q (X - p)), its distance
// there, and the gradient and Hessian turned back: Q g, Q H Q^T.
SignedDistance signed_distance(const ObstacleShape& o, const Point& x, double s) {
  const Eigen::Matrix3d Q = orientation(o, s);
  const Point p = pivot(o);
  SignedDistance out = shape_distance(o, p + Q.transpose() * (x - p - s * vec(o.move)));
  out.gradient = Q * out.gradient;
  out.hessian = Q * out.hessian * Q.transpose();
  return out;
}

double step_bound(const ObstacleShape& o, const Point& x, const Point& step, double s) {
  const SignedDistance sd = signed_distance(o, x, s);
  if (!(sd.d > 0)) return 1;
  if (o.type == ObstacleType::surface) return surface_advance(o, x, step, s, sd.d);
  const double approach = -sd.gradient.dot(step);
  return approach > 0 ? std::min(1.0, 0.9 * sd.d / approach) : 1.0;
}

}  // namespace hs
