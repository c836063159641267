// Column method, CPU fast path: the sweep of a band of rows (column_fast.cpp describes the
// method). Triangles are set up on their first row and rasterized into the ring of pending
// rows; a row no later triangle reaches is resolved into its floors' moments, which become
// nodal weights at the end of the band.
#include "column_fast_impl.hpp"

namespace fluidweight::detail {

// Sets up triangle t on row j (its first row, or the first row of the band): its box as
// setup_triangle finds it, its edge functions at (i0, j) and their steps, its height plane;
// a floor gets a record for its moments. Then rasterizes it.
void FastColumn::Impl::start(int t, int j, int jb, Worker& w) {
  const SortedTriangle& st = sorted[t];
  int x[3], y[3];
  double z[3];
  for (int k = 0; k < 3; ++k) {
    const SnappedVertex& p = vertices[st.vertex[k]];
    x[k] = p.x;
    y[k] = p.y;
    z[k] = p.z;
  }
  Raster r;
  const int s = grid.sub_bits, half = 1 << (s - 1);
  const int xmin = std::min({x[0], x[1], x[2]}), xmax = std::max({x[0], x[1], x[2]});
  r.i0 = std::max(0, -((half - xmin) >> s));
  r.i1 = std::min(grid.n - 1, (xmax - half) >> s);
  r.j1 = std::min(grid.n - 1, (std::max({y[0], y[1], y[2]}) - half) >> s);
  r.row = j;
  const int px = column_centre(r.i0, s), py = column_centre(j, s);
  const int64_t unit = int64_t{1} << s;
  int64_t area2 = 0, e[3];
  int dx[3], dy[3];
  double z0 = 0, dzi = 0, dzj = 0;
  for (int k = 0; k < 3; ++k) {  // edge k goes from corner k + 1 to corner k + 2
    const int p = k == 2 ? 0 : k + 1, q = k == 0 ? 2 : k - 1;
    dx[k] = x[q] - x[p];
    dy[k] = y[q] - y[p];
    e[k] = int64_t{dx[k]} * (py - y[p]) - int64_t{dy[k]} * (px - x[p]);
    r.e[k] = e[k] - ((st.flags >> k) & 1);
    r.di[k] = -dy[k] * unit;
    r.dj[k] = dx[k] * unit;
    area2 += e[k];
    z0 += static_cast<double>(e[k]) * z[k];
    dzi += static_cast<double>(r.di[k]) * z[k];
    dzj += static_cast<double>(r.dj[k]) * z[k];
  }
  const double inv = 1.0 / static_cast<double>(area2);  // the edge functions sum to 2 area
  r.z = z0 * inv;
  r.dzi = dzi * inv;
  r.dzj = dzj * inv;
  r.floor = -1;
  if ((st.flags >> 3) & 1) {
    r.floor = w.floors++;
    w.moments[r.floor] = {0.0, 0.0, 0.0, 0.0};
    w.setups[r.floor] = {
        {e[0], e[1], e[2]}, {dx[0], dx[1], dx[2]}, {dy[0], dy[1], dy[2]}, t, r.i0, j};
  }
  raster_block(r, jb, w);
}

// Starts the triangles whose first row is j: 8 set up together with AVX-512, else one by one.
void FastColumn::Impl::start_row(int j, int jb, Worker& w) {
  const int begin = row_start[j], end = row_start[j + 1];
#if defined(FLUIDWEIGHT_AVX512)
  if (avx512) {
    static_assert(sizeof(SortedTriangle) == 16 && sizeof(SnappedVertex) == 16,
                  "setup_avx512 reads 16-byte records");
    rows::SetupBatch& b = w.batch;
    const int s = grid.sub_bits;
    for (int c = begin; c < end; c += rows::kChunk) {
      const int lanes = std::min(rows::kChunk, end - c);
      for (int u = 0; u < lanes && c + kPrefetch + u < static_cast<int>(sorted.size()); ++u) {
        for (int v : sorted[c + kPrefetch + u].vertex) prefetch(&vertices[v]);
      }
      rows::setup_avx512(reinterpret_cast<const int*>(sorted.data() + c), lanes,
                         reinterpret_cast<const int*>(vertices.data()), j, s, grid.n, b);
      for (int u = 0; u < lanes; ++u) {
        // A Raster from the batch, `rows` rows on: for boxes of more than two chunks and for
        // triangles going on later only.
        auto raster_at = [&](int rows, int floor) {
          Raster r;
          for (int k = 0; k < 3; ++k) {
            r.e[k] = b.e[k][u] + b.dj[k][u] * rows;
            r.di[k] = b.di[k][u];
            r.dj[k] = b.dj[k][u];
          }
          r.z = b.z[u] + b.dzj[u] * rows;
          r.dzi = b.dzi[u];
          r.dzj = b.dzj[u];
          r.i0 = b.i0[u];
          r.i1 = b.i1[u];
          r.j1 = b.j1[u];
          r.row = j + rows;
          r.floor = floor;
          return r;
        };
        int floor = -1;
        const unsigned flags = b.flags[u];
        if ((flags >> 3) & 1) {
          floor = w.floors++;
          w.moments[floor] = {0.0, 0.0, 0.0, 0.0};
          FloorSetup& f = w.setups[floor];
          f.i0 = b.i0[u];
          f.j0 = j;
          for (int k = 0; k < 3; ++k) {
            f.e[k] = b.e[k][u] + ((flags >> k) & 1);
            f.dx[k] = static_cast<int>(b.dj[k][u] >> s);
            f.dy[k] = static_cast<int>(-b.di[k][u] >> s);
          }
          f.triangle = c + u;
        }
        if (b.i1[u] - b.i0[u] >= 2 * rows::kChunk) {
          Raster r = raster_at(0, floor);
          raster_block(r, jb, w, rows::raster_avx512);
          continue;
        }
        const int j1 = b.j1[u], last = std::min({j1, j + ring_rows - 1, jb - 1});
        rows::raster_lane_avx512(b, u, j, floor, last - j + 1, w.ring);
        if (last < j1 && last + 1 < jb) {
          w.pending[(last + 1) & (ring_rows - 1)].push_back(raster_at(last - j + 1, floor));
        }
      }
    }
    return;
  }
#endif
  for (int c = begin; c < end; ++c) {
    // Vertices are read at random in memory: ask for them ahead.
    if (c + kPrefetch < static_cast<int>(sorted.size())) {
      for (int v : sorted[c + kPrefetch].vertex) prefetch(&vertices[v]);
    }
    start(c, j, jb, w);
  }
}

// Rasterizes the rows of r from r.row that the ring holds, up to the band's end; a triangle
// with rows left goes on when the sweep reaches them.
template <class Kernel>
inline void FastColumn::Impl::raster_block(Raster& r, int jb, Worker& w, Kernel kernel) {
  const int last = std::min({r.j1, r.row + ring_rows - 1, jb - 1});
  kernel(r, last - r.row + 1, w.ring);
  if (r.row <= r.j1 && r.row < jb) w.pending[r.row & (ring_rows - 1)].push_back(r);
}

// Gives each floor's sections to its nodes: the edge functions at (i0 + di, j0 + dj) are
// e + di (i step) + dj (j step), barycentric coordinates times twice the area.
void FastColumn::Impl::finish_floors(Worker& w) {
  const int64_t unit = int64_t{1} << grid.sub_bits;
  for (int f = 0; f < w.floors; ++f) {
    // The nodes' weights are updated at random (the armadillo lists its vertices in random
    // order): asked for ahead.
    if (f + kPrefetchAhead < w.floors) {
      for (int v : sorted[w.setups[f + kPrefetchAhead].triangle].vertex) prefetch(&w.weights[v]);
    }
    const FloorMoments& m = w.moments[f];
    if (m.m0 == 0.0 && m.mi == 0.0 && m.mj == 0.0) continue;
    const FloorSetup& st = w.setups[f];
    const double scale = rho_g * grid.cell_area / static_cast<double>(st.e[0] + st.e[1] + st.e[2]);
    const int* v = sorted[st.triangle].vertex;
    // The moments about the floor's origin.
    const double mi = m.mi - st.i0 * m.m0, mj = m.mj - st.j0 * m.m0;
    for (int k = 0; k < 3; ++k) {
      w.weights[v[k]] +=
          scale * (static_cast<double>(st.e[k]) * m.m0 - static_cast<double>(st.dy[k] * unit) * mi +
                   static_cast<double>(st.dx[k] * unit) * mj);
    }
  }
  w.floors = 0;
}

void FastColumn::Impl::sweep_band(int band, Worker& w) {
  const int ja = band * band_rows, jb = std::min(grid.n, ja + band_rows);
  const size_t most = carried_start[band + 1] - carried_start[band] + row_start[jb] - row_start[ja];
  if (w.moments.size() < most) {
    w.moments.resize(most);
    w.setups.resize(most);
  }
  for (int j = ja; j < jb; ++j) {
    // Triangles going on at row j first: those started below queue for row j + ring_rows, in
    // the same slot.
    std::vector<Raster>& going_on = w.pending[j & (ring_rows - 1)];
    if (!going_on.empty()) {
      w.taken.swap(going_on);
      for (Raster& r : w.taken) raster_block(r, jb, w);
      w.taken.clear();
    }
    if (j == ja) {
      for (int c = carried_start[band]; c < carried_start[band + 1]; ++c) {
        start(carried[c], ja, jb, w);
      }
    }
    start_row(j, jb, w);
    resolve(j, w.ring, w.moments.data(), w.scratch, w.totals);
  }
  finish_floors(w);
}

}  // namespace fluidweight::detail
