// Rigid obstacles as signed distance functions (docs/contact.md): the distance d(x) from a
// point to the obstacle's surface, positive outside it (where the body must stay), with its
// gradient and Hessian. The body's nodes are kept at d > 0 by the barrier of barrier.hpp;
// a convex obstacle's d is negative everywhere inside it, so a step that would carry a node
// through the obstacle is refused however large it is; a surface obstacle (a triangle mesh,
// triangle_surface.hpp) need not be convex, and the Newton step is bounded by its unsigned
// distance instead. Pure: no MPI, no PETSc.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace hs {

enum class ObstacleType { plane, sphere, box, cylinder, surface };
inline const std::vector<std::string> kObstacleTypeNames = {"plane", "sphere", "box", "cylinder",
                                                            "surface"};

class TriangleSurface;

// An obstacle as the deck gives it, in its place at load factor 0, turned by `rotation` about
// its pivot (pivot()); at load factor s it has moved by s * move and turned further by
// s * turn about the moved pivot (a prescribed rigid motion that follows the load, as a
// Dirichlet value does). Rotations are rotation vectors: the axis times the angle in degrees.
struct ObstacleShape {
  std::string name;
  ObstacleType type = ObstacleType::plane;
  std::array<double, 3> point{0, 0, 0};   // plane: a point of it
  std::array<double, 3> normal{0, 0, 1};  // plane: towards the body (unit after parsing)
  std::array<double, 3> center{0, 0, 0};  // sphere, box, cylinder (a point of its axis)
  double radius = 0;                      // sphere, cylinder
  std::array<double, 3> size{0, 0, 0};    // box: edge lengths along x, y, z (axis-aligned)
  std::array<double, 3> axis{0, 0, 1};    // cylinder: the axis (unit), infinitely long
  std::string file;                       // surface: its STL or OBJ file (resolved path)
  double scale = 1;                       // surface: the file's coordinates times this are m
  std::shared_ptr<const TriangleSurface> surface;  // surface: read from `file` with the deck
  std::array<double, 3> pivot{0, 0, 0};            // surface: the point it turns about (m)
  std::array<double, 3> move{0, 0, 0};             // translation at full load (m)
  std::array<double, 3> rotation{0, 0, 0};         // fixed rotation vector (degrees)
  std::array<double, 3> turn{0, 0, 0};             // rotation vector at full load (degrees)
  double friction = 0;  // Coulomb coefficient with the body (friction.hpp)
};

struct SignedDistance {
  double d = 0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();  // unit where d is smooth
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
};

// The point the obstacle turns about: a plane's point, the centre of a sphere, box or
// cylinder, a surface's pivot.
Eigen::Vector3d pivot(const ObstacleShape& obstacle);

// The obstacle's orientation at load factor s: exp(s turn) exp(rotation).
Eigen::Matrix3d orientation(const ObstacleShape& obstacle, double s);

// The signed distance of point x from the obstacle at load factor s.
SignedDistance signed_distance(const ObstacleShape& obstacle, const Eigen::Vector3d& x, double s);

// The largest fraction t <= 1 of a Newton step that keeps a node at x, outside the obstacle,
// at least a tenth of its gap d0 away from it along x + t step: by the gap's tangent
// d0 + t n . step, a lower bound of a convex obstacle's distance (exact for a plane); for a
// surface obstacle, which need not be convex, by its unsigned distance (a move shorter than
// it cannot reach the surface), advanced along the step. 1 for a node on or inside.
double step_bound(const ObstacleShape& obstacle, const Eigen::Vector3d& x,
                  const Eigen::Vector3d& step, double s);

}  // namespace hs
