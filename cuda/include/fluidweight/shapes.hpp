// Closed triangle surfaces generated in code, for the tests, the benchmark and examples: the
// paper's icosphere, a torus, voxel shapes (non-convex, vertical walls), a sphere with very
// uneven triangle sizes.
#pragma once

#include <array>
#include <vector>

#include "fluidweight/fluidweight.hpp"

namespace fluidweight::shapes {

// Icosahedron subdivided `levels` times (each triangle into 4, new vertices pushed to the
// sphere), 20 * 4^levels triangles, outward. levels = 4, radius = 1: the paper's 5120-triangle
// sphere, polyhedral volume 4.17974.
SurfaceMesh icosphere(int levels, double radius = 1.0);

// Torus around the y axis: tube radius r at distance R, nu x nv quads split in two, outward.
SurfaceMesh torus(double R, double r, int nu, int nv);

// Surface of the union of voxels: occupied[(k * ny + j) * nx + i] for voxel (i, j, k) of size
// `size`, the first at `origin`. Each face square is split along one diagonal. Voxels that
// touch only along an edge or at a corner make a non-manifold surface (check_closed_surface
// refuses it). Volume: the number of voxels times the voxel volume.
SurfaceMesh voxels(int nx, int ny, int nz, const std::vector<bool>& occupied,
                   const std::array<double, 3>& size = {1.0, 1.0, 1.0},
                   const std::array<double, 3>& origin = {0.0, 0.0, 0.0});

// A sphere of radius `radius` whose triangles shrink towards +y: the icosphere mapped by a
// stereographic projection from +y, a scaling by `factor` and back (conformal). Triangle
// areas then span about factor^4.
SurfaceMesh uneven_sphere(int levels, double factor, double radius = 1.0);

}  // namespace fluidweight::shapes
