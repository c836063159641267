// Triangle surfaces from files: Wavefront .obj, .off, .stl (ASCII and binary) and gmsh's ASCII
// .msh (versions 4.1 and 2.2). Polygons are split into fans of triangles. Errors throw
// InputError naming the file, the line and the reason. Files may be hostile: a count (of
// nodes, elements, vertices, faces) is checked against the rest of the file's size before
// anything is allocated for it; coordinates must be finite numbers (NaN, inf, numbers beyond
// a double and a token with anything after its number, a NUL say, are refused) within
// kMaxCoordinate, and the surface must span at least kMinExtent: beyond these its volume
// (a cube of its size) and the weight on its nodes overflow or underflow a double, and a
// weight of 0 or inf would be printed for a surface that holds liquid. Error messages quote a
// file's tokens with their control and non-ASCII bytes written out (\x00).
#pragma once

#include <string>

#include "fluidweight/fluidweight.hpp"

namespace fluidweight {

constexpr double kMaxCoordinate = 1e30;  // |x|, |y|, |z| of a vertex
constexpr double kMinExtent = 1e-30;     // the largest side of the surface's bounding box

// Reads by extension (case-insensitive). Vertices keep the file's order, except for STL,
// whose facets repeat their corners: equal corners are merged, in order of first appearance,
// and facets left with a repeated vertex (no area) are dropped.
SurfaceMesh read_surface(const std::string& path);

SurfaceMesh read_obj(const std::string& path);
SurfaceMesh read_off(const std::string& path);
SurfaceMesh read_stl(const std::string& path);
// Every node becomes a vertex (in file order); every 2D element a triangle or two (first-order
// corners of quadratic elements); points, lines and volume elements are skipped. Binary .msh
// is refused: this reader is hand-written because the module builds without gmsh.
SurfaceMesh read_msh(const std::string& path);

}  // namespace fluidweight
