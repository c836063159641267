// column_head, CPU fast path: the same columns as the reference, with no hit stored and no
// column sorted.
//
// With the head, a hit's load depends on its own height only: a floor at height z carries
// +rho |g| w d (top - z) and a ceiling -rho |g| w d (top - z), each spread by the barycentric
// coordinates of the column centre. Floors and ceilings need no pairing: the surface is closed
// (Context::set_cavities checks it) and the fill rule counts every column crossing once, so
// each column has as many floors as ceilings (the reference counts unmatched columns; here there
// are none by construction).
//
// On a triangle lambda_k and z are linear in the column indices (u, q) from its box corner, so
// its nodal loads are linear combinations of six moments of its covered columns: n, sum u,
// sum q, sum u^2, sum u q, sum q^2. A row's covered columns are one interval [a, b] (the
// rows:: span of the fast path), whose moments are closed forms. The cost is one span per
// covered row of each triangle, independent of the columns it covers.
#include "column_fast_rows.hpp"
#include "cpu.hpp"

namespace fluidweight::detail {
namespace {

// sum_{u=0}^{k} u^2, zero for k < 0.
double sum_squares(int64_t k) {
  if (k <= 0) return 0.0;
  const double x = static_cast<double>(k);
  return x * (x + 1) * (2 * x + 1) / 6;
}

struct Moments {
  double n = 0, su = 0, sq = 0, suu = 0, suq = 0, sqq = 0;
};

// The covered columns' moments of a set-up triangle, in u = i - i0 and q = j - j0. `e0` are the
// raw edge functions at the centre of column (i0, j0), `di` and `dj` their steps.
Moments covered_moments(const SnappedTriangle& tri, const int64_t e0[3], const int64_t di[3],
                        const int64_t dj[3]) {
  rows::Raster r{};
  for (int k = 0; k < 3; ++k) {
    r.e[k] = e0[k] - tri.e_min[k];
    r.di[k] = di[k];
    r.dj[k] = dj[k];
  }
  r.i0 = tri.i0;
  r.i1 = tri.i1;
  Moments m;
  for (int j = tri.j0; j <= tri.j1; ++j) {
    int a = 0, b = -1;
    if (rows::wide_span(r, a, b)) {
      const int64_t ua = a - tri.i0, ub = b - tri.i0;
      const double count = static_cast<double>(ub - ua + 1), q = j - tri.j0;
      const double su = 0.5 * static_cast<double>(ua + ub) * count;
      m.n += count;
      m.su += su;
      m.suu += sum_squares(ub) - sum_squares(ua - 1);
      m.sq += q * count;
      m.suq += q * su;
      m.sqq += q * q * count;
    }
    for (int k = 0; k < 3; ++k) r.e[k] += r.dj[k];
  }
  return m;
}

}  // namespace

void column_head_rows(const CavityView& cavity, const Frame& frame, const GridParams& grid,
                      double rho_g, CavityOutput& out) {
  out.values.assign(cavity.num_vertices, 0.0);
  out.column_volume = 0.0;
  out.unmatched_columns = 0;
  if (grid.empty) return;
  const int s = grid.sub_bits;
  const int64_t unit = int64_t{1} << s;
  const double top = grid.u1 - grid.u0;
  double volume = 0.0;
  for (int t = 0; t < cavity.num_triangles; ++t) {
    const int* v = cavity.triangles + 3 * t;
    SnappedTriangle tri;
    double z_in[3];
    if (!snap_triangle(cavity, frame, grid, t, &tri, z_in)) continue;
    if (tri.i0 > tri.i1 || tri.j0 > tri.j1) continue;

    // Edge k runs from counter-clockwise corner k + 1 to k + 2; lambda_k = E_k / area2.
    const int px = column_centre(tri.i0, s), py = column_centre(tri.j0, s);
    int64_t e0[3], di[3], dj[3];
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      e0[k] = edge_function(tri.x[a], tri.y[a], tri.x[b], tri.y[b], px, py);
      di[k] = -static_cast<int64_t>(tri.y[b] - tri.y[a]) * unit;
      dj[k] = static_cast<int64_t>(tri.x[b] - tri.x[a]) * unit;
    }
    const Moments m = covered_moments(tri, e0, di, dj);
    if (m.n == 0) continue;

    // lambda_k = la + lb u + lc q, z = z0 + dzi u + dzj q, T = top - z.
    const double inv = 1.0 / static_cast<double>(tri.area2);
    double la[3], lb[3], lc[3], z0 = 0, dzi = 0, dzj = 0;
    for (int k = 0; k < 3; ++k) {
      la[k] = static_cast<double>(e0[k]) * inv;
      lb[k] = static_cast<double>(di[k]) * inv;
      lc[k] = static_cast<double>(dj[k]) * inv;
      const double zk = z_in[tri.corner[k]];
      z0 += la[k] * zk;
      dzi += lb[k] * zk;
      dzj += lc[k] * zk;
    }
    const double t0 = top - z0;
    const double sign = tri.bottom ? 1.0 : -1.0, scale = sign * rho_g * grid.cell_area;
    for (int k = 0; k < 3; ++k) {
      const double sum_t_lambda = t0 * la[k] * m.n + (t0 * lb[k] - dzi * la[k]) * m.su +
                                  (t0 * lc[k] - dzj * la[k]) * m.sq - dzi * lb[k] * m.suu -
                                  (dzi * lc[k] + dzj * lb[k]) * m.suq - dzj * lc[k] * m.sqq;
      out.values[v[tri.corner[k]]] += scale * sum_t_lambda;
    }
    // Sections' heights: sum over floors and ceilings of -sign z (the head's top cancels, as
    // every column has as many floors as ceilings; leaving it out keeps the sum accurate).
    volume -= sign * (z0 * m.n + dzi * m.su + dzj * m.sq);
  }
  out.column_volume = grid.cell_area * volume;
}

}  // namespace fluidweight::detail
