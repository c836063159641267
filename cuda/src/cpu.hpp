// The CPU implementations and the host side of Step 1, internal to the module.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "fluidweight/fluidweight.hpp"
#include "geometry.hpp"

namespace fluidweight::detail {

// One cavity's arrays, as the implementations read them.
struct CavityView {
  const double* xyz = nullptr;  // 3 per vertex
  int num_vertices = 0;
  const int* triangles = nullptr;  // 3 per triangle
  int num_triangles = 0;
};

// Frame of the columns for a gravity vector (throws InputError when it is zero or not finite).
Frame make_frame(const std::array<double, 3>& gravity);

// V = 1/6 sum_t a.(b x c), with coordinates relative to the first vertex for accuracy.
double signed_volume(const CavityView& cavity);

// Step 1: the grid of a cavity (projected box, snapping scale, orientation).
GridParams grid_for(const CavityView& cavity, const Frame& frame, int n, double signed_volume);

// What an implementation of the column method or the hydrostatic load returns for a cavity:
// a weight (a force along gravity) per vertex for the column method, a force 3-vector per
// vertex for the hydrostatic load.
struct CavityOutput {
  std::vector<double> values;
  double column_volume = 0.0;
  long long unmatched_columns = 0;
};

// Steps 1-2 for triangle t of a cavity: its corners snapped to the grid, their heights above
// the lowest vertex (input order) into z, the triangle set up. False when its snapped
// projection has no area (it covers no column).
inline bool snap_triangle(const CavityView& cavity, const Frame& frame, const GridParams& grid,
                          int t, SnappedTriangle* tri, double z[3]) {
  const int* v = cavity.triangles + 3 * t;
  const int units = grid.n << grid.sub_bits;
  int sx[3], sy[3];
  for (int k = 0; k < 3; ++k) {
    const Vec3 p = load_vec3(cavity.xyz, v[k]);
    sx[k] = snap(dot_rn(p, frame.e1), grid.a0, grid.scale_a, units);
    sy[k] = snap(dot_rn(p, frame.e2), grid.b0, grid.scale_b, units);
    z[k] = dot_rn(p, frame.up) - grid.u0;
  }
  return setup_triangle(sx, sy, grid.orientation, grid.n, grid.sub_bits, tri);
}

// Column method, CPU reference: every candidate column of every triangle is tested, every hit
// is stored, each column's floors and ceilings are sorted and paired. Simple, double precision.
// rho_g = rho |g|.
// head = false: the paper's Step 5; true: column_head (fluidweight.hpp's Method).
void column_reference(const CavityView& cavity, const Frame& frame, const GridParams& grid,
                      double rho_g, bool head, CavityOutput& out);

// column_head, CPU fast path: the reference's columns, each hit's load from its own height
// (no pairing), summed per triangle in closed form over its covered rows (column_head.cpp).
void column_head_rows(const CavityView& cavity, const Frame& frame, const GridParams& grid,
                      double rho_g, CavityOutput& out);

// Column method, CPU fast path: row sweeps over bands of rows, on worker threads. Computes
// the grid (Step 1) itself, on the threads, and returns the signed volume.
class FastColumn {
 public:
  FastColumn(int threads, CpuKernels kernels);
  ~FastColumn();
  void run(const CavityView& cavity, const Frame& frame, int n, double rho_g, CavityOutput& out,
           double& signed_volume);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Closed-form hydrostatic load: pressure rho |g| depth below the highest vertex, consistent
// nodal forces f_i = N (p_i + p_1 + p_2 + p_3) / 24 on each triangle (N = twice the area times
// the outward normal). Fills 3 values a vertex.
void hydrostatic(const CavityView& cavity, const Frame& frame, const GridParams& grid, double rho_g,
                 CavityOutput& out);

}  // namespace fluidweight::detail
