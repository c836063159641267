// Meshes, transformations and comparisons shared by the fluid-weight tests.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "fluidweight/fluidweight.hpp"
#include "fluidweight/shapes.hpp"

namespace fwtest {

using fluidweight::Options;
using fluidweight::Result;
using fluidweight::SurfaceMesh;
using Mat3 = std::array<std::array<double, 3>, 3>;
using Vec3 = std::array<double, 3>;

// Options for one implementation at grid N (rho 1000, g = (0, -9.81, 0) unless changed).
Options options(fluidweight::Implementation implementation, int n,
                Vec3 gravity = {0.0, -9.81, 0.0});

// An "E" lying on its back, extruded along z: three horizontal arms joined by a vertical bar,
// so vertical columns cross it in up to three sections. Voxels of size 1, 5 x 5 x 3.
SurfaceMesh e_shape();
// A comb of `teeth` horizontal plates joined at one end: up to `teeth` sections per column.
SurfaceMesh comb(int teeth);
// A box of the given size, its faces split into unit-free voxel squares (sub x sub x sub).
SurfaceMesh box(Vec3 size, int sub = 1);
// A regular octahedron of half-diagonal `half`, centred at `centre` (8 triangles).
SurfaceMesh octahedron(Vec3 centre, double half);
// Number of voxels of a voxel shape above (i, k) along y, for the E shape.
std::vector<bool> e_shape_voxels();

SurfaceMesh translated(const SurfaceMesh& mesh, Vec3 shift);
SurfaceMesh transformed(const SurfaceMesh& mesh, const Mat3& rotation);
SurfaceMesh flipped(const SurfaceMesh& mesh);  // every triangle's orientation reversed
// Triangles in a random order, each starting at a random corner (same orientation).
SurfaceMesh shuffled(const SurfaceMesh& mesh, unsigned seed);
// Rotation by `angle` radians about the unit axis.
Mat3 rotation(Vec3 axis, double angle);
Vec3 apply(const Mat3& m, Vec3 v);

// Exact volume and centroid of a closed polyhedron (divergence theorem, tetrahedra fan).
double volume(const SurfaceMesh& mesh);
Vec3 centroid(const SurfaceMesh& mesh);
// Sum of the forces and their moment about the origin.
Vec3 total_force(const Result& r);
Vec3 total_moment(const SurfaceMesh& mesh, const Result& r);

// max_v |f_v - g_v| / max_v |g_v|.
double force_difference(const Result& f, const Result& g);

// A folder of this test process's own (made at first use under the test temp dir), with a
// trailing '/', removed with everything in it when the process exits: tests leave no files.
const std::string& scratch_folder();

}  // namespace fwtest
