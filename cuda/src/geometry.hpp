// Steps 1-2 of the column method and the fill rule, shared by the CPU and CUDA code so that
// every implementation covers exactly the same columns.
//
// Step 1, to grid space. The columns are parallel to gravity. The frame (e1, e2, up) is
// right-handed with up = -g/|g|; for g along -y it is (z, x, y), so the grid lies in the XZ
// plane as in the paper. The N x N grid covers the box of the vertices projected on (e1, e2)
// exactly; column (i, j) has its centre at the centre of its cell. Projected coordinates are
// snapped to integers, 2^s units a column (s = sub_bits_for(N), at least 9), as rasterizers
// snap to sub-pixels. Edge functions of snapped points are then exact in 64-bit integers, so
// the fill rule below decides every column without round-off.
//
// Fill rule (watertightness). A column centre p is inside a counter-clockwise snapped triangle
// when every edge function E_k(p) > 0, or E_k(p) = 0 on a top or left edge. That equals testing
// p moved by (eps, -eps^2), the same move for every triangle: a column through a shared edge or
// vertex is counted by exactly one triangle of each layer, and along every column of a closed
// surface the floors (bottom triangles) and ceilings (top triangles) come in equal numbers.
// Triangles whose snapped projection has no area (vertical ones) cover nothing.
//
// Step 2, top and bottom. With the surface oriented outward (positive signed volume), a
// triangle whose projection is counter-clockwise seen from above has its normal up: a ceiling.
// Clockwise ones are floors. An inward surface swaps the two.
#pragma once

#include <cmath>
#include <cstdint>

#if defined(__CUDACC__)
#define FW_HD __host__ __device__ inline
#else
#define FW_HD inline
#endif

namespace fluidweight::detail {

struct Vec3 {
  double x, y, z;
};

// Products and sums rounded one by one (no fused multiply-add), so that the host and the
// device compute bit-identical snapped coordinates.
FW_HD double mul_rn(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dmul_rn(a, b);
#else
  return a * b;
#endif
}

FW_HD double add_rn(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dadd_rn(a, b);
#else
  return a + b;
#endif
}

FW_HD double dot_rn(Vec3 a, Vec3 b) {
  return add_rn(add_rn(mul_rn(a.x, b.x), mul_rn(a.y, b.y)), mul_rn(a.z, b.z));
}

FW_HD Vec3 load_vec3(const double* xyz, int vertex) {
  return Vec3{xyz[3 * vertex], xyz[3 * vertex + 1], xyz[3 * vertex + 2]};
}

struct Frame {
  Vec3 e1, e2, up;
};

// The grid of one cavity, computed from the projected box (Step 1).
struct GridParams {
  double a0 = 0, b0 = 0;            // box minimum along e1 and e2
  double scale_a = 0, scale_b = 0;  // snapped units per length along e1 and e2
  double u0 = 0, u1 = 0;            // lowest and highest vertex along up
  double cell_area = 0;             // w * d of one column
  int n = 0;                        // N
  int sub_bits = 0;                 // s
  int orientation = 1;              // +1 outward, -1 inward (sign of the signed volume)
  int empty = 1;                    // 1 when the projected box has no area
};

// Largest s with N 2^s <= 2^25, at most 16: snapped coordinates and their differences then
// lie within +-2^25 (int32) and edge functions within +-2^51 (exact in int64).
FW_HD int sub_bits_for(int n) {
  int log2n = 0;
  while ((1 << log2n) < n) ++log2n;
  int s = 25 - log2n;
  return s > 16 ? 16 : s;
}

constexpr int kMaxGrid = 1 << 16;

FW_HD GridParams make_grid(double amin, double amax, double bmin, double bmax, double umin,
                           double umax, int n, double signed_volume) {
  GridParams g;
  g.n = n;
  g.sub_bits = sub_bits_for(n);
  g.a0 = amin;
  g.b0 = bmin;
  g.u0 = umin;
  g.u1 = umax;
  g.orientation = signed_volume < 0 ? -1 : 1;
  g.empty = !(amax > amin && bmax > bmin);
  if (!g.empty) {
    double units = static_cast<double>(n) * static_cast<double>(1 << g.sub_bits);
    g.scale_a = units / add_rn(amax, -amin);
    g.scale_b = units / add_rn(bmax, -bmin);
    g.cell_area = mul_rn(add_rn(amax, -amin) / n, add_rn(bmax, -bmin) / n);
  }
  return g;
}

// Snapped coordinate of a projected coordinate, in [0, N 2^s].
FW_HD int snap(double coord, double origin, double scale, int max_units) {
  double v = rint(mul_rn(add_rn(coord, -origin), scale));
  if (v < 0) v = 0;
  if (v > max_units) v = max_units;
  return static_cast<int>(v);
}

// Edge function of the directed edge a->b at p: positive when p is on its left.
FW_HD int64_t edge_function(int ax, int ay, int bx, int by, int px, int py) {
  return static_cast<int64_t>(bx - ax) * (py - ay) - static_cast<int64_t>(by - ay) * (px - ax);
}

// Snapped centre of column i (or row j).
FW_HD int column_centre(int i, int sub_bits) { return (i << sub_bits) + (1 << (sub_bits - 1)); }

// One triangle after Steps 1-2: counter-clockwise snapped corners, the fill-rule thresholds of
// its edges, floor or ceiling, and the columns whose centres lie in its box.
struct SnappedTriangle {
  int x[3], y[3];      // snapped corners, counter-clockwise
  int corner[3];       // which input corner (0..2) each counter-clockwise corner is
  int64_t area2;       // twice the snapped area, > 0
  int64_t e_min[3];    // edge k (opposite corner k) covers p when E_k(p) >= e_min[k]
  bool bottom;         // a floor: the section above it is given to its nodes
  int i0, i1, j0, j1;  // columns whose centres lie in the box (empty when i0 > i1 or j0 > j1)
};

// Sets up a triangle from its snapped corners (input order). Returns false when its snapped
// projection has no area: such a triangle covers no column.
FW_HD bool setup_triangle(const int sx[3], const int sy[3], int orientation, int n, int sub_bits,
                          SnappedTriangle* t) {
  int64_t area2 = edge_function(sx[0], sy[0], sx[1], sy[1], sx[2], sy[2]);
  if (area2 == 0) return false;
  bool ceiling = (area2 > 0) == (orientation > 0);
  t->bottom = !ceiling;
  // Counter-clockwise order: swap corners 1 and 2 of a clockwise triangle (no arrays indexed
  // at run time, so that the device keeps everything in registers).
  const bool flip = area2 < 0;
  t->area2 = flip ? -area2 : area2;
  t->corner[0] = 0;
  t->corner[1] = flip ? 2 : 1;
  t->corner[2] = flip ? 1 : 2;
  t->x[0] = sx[0];
  t->y[0] = sy[0];
  t->x[1] = flip ? sx[2] : sx[1];
  t->y[1] = flip ? sy[2] : sy[1];
  t->x[2] = flip ? sx[1] : sx[2];
  t->y[2] = flip ? sy[1] : sy[2];
  for (int k = 0; k < 3; ++k) {
    int a = (k + 1) % 3, b = (k + 2) % 3;
    int dx = t->x[b] - t->x[a], dy = t->y[b] - t->y[a];
    // Top edge: horizontal, going left (interior below). Left edge: going down.
    bool top_left = dy < 0 || (dy == 0 && dx < 0);
    t->e_min[k] = top_left ? 0 : 1;
  }
  int xmin = t->x[0], xmax = t->x[0], ymin = t->y[0], ymax = t->y[0];
  for (int k = 1; k < 3; ++k) {
    xmin = t->x[k] < xmin ? t->x[k] : xmin;
    xmax = t->x[k] > xmax ? t->x[k] : xmax;
    ymin = t->y[k] < ymin ? t->y[k] : ymin;
    ymax = t->y[k] > ymax ? t->y[k] : ymax;
  }
  // Smallest i with centre >= xmin, largest with centre <= xmax (arithmetic shifts floor).
  int half = 1 << (sub_bits - 1);
  t->i0 = -((half - xmin) >> sub_bits);
  t->i1 = (xmax - half) >> sub_bits;
  t->j0 = -((half - ymin) >> sub_bits);
  t->j1 = (ymax - half) >> sub_bits;
  if (t->i0 < 0) t->i0 = 0;
  if (t->j0 < 0) t->j0 = 0;
  if (t->i1 > n - 1) t->i1 = n - 1;
  if (t->j1 > n - 1) t->j1 = n - 1;
  return true;
}

// Edge functions at a column centre; true when the fill rule puts the centre inside.
FW_HD bool covers(const SnappedTriangle& t, int px, int py, int64_t e[3]) {
  e[0] = edge_function(t.x[1], t.y[1], t.x[2], t.y[2], px, py);
  e[1] = edge_function(t.x[2], t.y[2], t.x[0], t.y[0], px, py);
  e[2] = edge_function(t.x[0], t.y[0], t.x[1], t.y[1], px, py);
  return e[0] >= t.e_min[0] && e[1] >= t.e_min[1] && e[2] >= t.e_min[2];
}

}  // namespace fluidweight::detail
