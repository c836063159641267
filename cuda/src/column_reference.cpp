// Column method, CPU reference (double precision): the paper's Steps 1-5 written as plainly as
// possible, to check the fast paths and the CUDA kernels against.
#include <algorithm>
#include <tuple>

#include "cpu.hpp"

namespace fluidweight::detail {
namespace {

// A column-triangle intersection (Steps 3 and 4).
struct Hit {
  int64_t column;  // j * N + i
  bool bottom;     // floor or ceiling
  double z;        // height above the cavity's lowest vertex
  int triangle;
  double lambda[3];  // barycentric coordinates at the column centre, input corner order
};

}  // namespace

void column_reference(const CavityView& cavity, const Frame& frame, const GridParams& grid,
                      double rho_g, bool head, CavityOutput& out) {
  out.values.assign(cavity.num_vertices, 0.0);
  out.column_volume = 0.0;
  out.unmatched_columns = 0;
  if (grid.empty) return;
  const int n = grid.n, s = grid.sub_bits;

  // Steps 1-4: snap each triangle, test every column centre of its box, keep the hits.
  std::vector<Hit> hits;
  for (int t = 0; t < cavity.num_triangles; ++t) {
    SnappedTriangle tri;
    double z[3];
    if (!snap_triangle(cavity, frame, grid, t, &tri, z)) continue;
    for (int j = tri.j0; j <= tri.j1; ++j) {
      for (int i = tri.i0; i <= tri.i1; ++i) {
        int64_t e[3];
        if (!covers(tri, column_centre(i, s), column_centre(j, s), e)) continue;
        Hit hit{static_cast<int64_t>(j) * n + i, tri.bottom, 0.0, t, {0, 0, 0}};
        for (int k = 0; k < 3; ++k) {
          double lambda = static_cast<double>(e[k]) / static_cast<double>(tri.area2);
          hit.lambda[tri.corner[k]] = lambda;
          hit.z += lambda * z[tri.corner[k]];
        }
        hits.push_back(hit);
      }
    }
  }

  // Step 5: per column, the k-th lowest floor pairs with the k-th lowest ceiling; the section's
  // weight rho |g| w d h goes to the floor triangle's nodes by the barycentric coordinates.
  // With the head, the floor carries the pressure at its depth below the top, rho |g| w d
  // (top - z_floor), and the ceiling the pressure at its own depth upwards: the same net.
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
    return std::make_tuple(a.column, !a.bottom, a.z, a.triangle) <
           std::make_tuple(b.column, !b.bottom, b.z, b.triangle);
  });
  double sum_heights = 0.0;
  for (size_t first = 0; first < hits.size();) {
    size_t end = first;
    while (end < hits.size() && hits[end].column == hits[first].column) ++end;
    size_t tops = first;
    while (tops < end && hits[tops].bottom) ++tops;
    size_t num_bottoms = tops - first, num_tops = end - tops;
    if (num_bottoms != num_tops) ++out.unmatched_columns;
    for (size_t r = 0; r < std::min(num_bottoms, num_tops); ++r) {
      const Hit& floor = hits[first + r];
      const Hit& ceiling = hits[tops + r];
      const double h = ceiling.z - floor.z, top = grid.u1 - grid.u0;
      sum_heights += h;
      const double on_floor = head ? top - floor.z : h;
      const int* v = cavity.triangles + 3 * floor.triangle;
      for (int k = 0; k < 3; ++k)
        out.values[v[k]] += rho_g * grid.cell_area * on_floor * floor.lambda[k];
      if (!head) continue;
      const int* w = cavity.triangles + 3 * ceiling.triangle;
      for (int k = 0; k < 3; ++k)
        out.values[w[k]] -= rho_g * grid.cell_area * (top - ceiling.z) * ceiling.lambda[k];
    }
    first = end;
  }
  out.column_volume = grid.cell_area * sum_heights;
}

}  // namespace fluidweight::detail
