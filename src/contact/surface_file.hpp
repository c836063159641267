// A surface obstacle's file (`obstacles[i].file`), read as untrusted input (docs/reliability.md,
// "Obstacle surfaces"): STL, ASCII or binary, or Wavefront OBJ, through the fluid-weight
// module's hardened readers (counts checked against the file's size, coordinates finite, OBJ
// indices in range, negative ones counted back from the last vertex), then checked here for
// what an obstacle needs: a bounded size, coordinates within kMaxSurfaceCoordinate m, no
// triangle of zero area, every edge shared by exactly two triangles in opposite directions,
// and a positive enclosed volume (triangles facing out). Every error is an InputError that
// names the file, the triangle, edge or vertex, and the reason. Pure.
#pragma once

#include <memory>
#include <string>

#include "contact/triangle_surface.hpp"

namespace hs {

constexpr size_t kMaxSurfaceBytes = size_t{512} << 20;  // a binary STL of 10.7M triangles
constexpr size_t kMaxSurfaceTriangles = 2'000'000;      // each rank holds the whole tree
constexpr double kMaxSurfaceCoordinate = 1e6;           // m, after `scale`

// The surface in metres: the file's coordinates times `scale`. `max_triangles`: lower for
// the tests of the limit.
std::shared_ptr<const TriangleSurface> read_obstacle_surface(
    const std::string& path, double scale, size_t max_triangles = kMaxSurfaceTriangles);

}  // namespace hs
