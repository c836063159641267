// Column method, CPU fast path: the same columns, pairs and weights as column_reference, by
// sweeps over bands of rows on worker threads.
//
// Step 1 and Step 2 run over the vertices and triangles; the triangles with columns are then
// sorted by first row (a counting sort). A band is swept row by row: the triangles whose first
// row is the current one are rasterized (all their rows at once, into a ring of pending rows:
// column_fast_rows.hpp), then the current row, which no later triangle reaches, is resolved:
// its columns' floors and ceilings are sorted and paired, and each section's height goes into
// three moments of its floor triangle (sum h, sum h i, sum h j). Barycentric coordinates are
// linear in the column indices, so each floor's nodal weights follow from its moments once, at
// the end of the band.
//
// Layout, for one core (docs/fluidweight.md, "What was tried and dropped"). Each triangle is set
// up once and its rows are visited in one go, so nothing is kept or updated per row for it;
// hits go into planes of one value per column (the first floor of every column side by side,
// then the second...), written and resolved 8 columns at a time without data-dependent
// branches (AVX-512 where the processor has it).
#include "column_fast_impl.hpp"

namespace fluidweight::detail {

namespace {

// The kernels' instruction set: 512 (AVX-512), 2 (AVX2) or 0 (portable), at most what was
// asked for and what the processor has.
int simd_level(CpuKernels kernels) {
  const int asked = kernels == CpuKernels::widest ? 512 : kernels == CpuKernels::avx2 ? 2 : 0;
#if defined(FLUIDWEIGHT_AVX512)
  if (asked >= 512 && rows::avx512_available()) return 512;
#endif
#if defined(FLUIDWEIGHT_AVX2)
  if (asked >= 2 && rows::avx2_available()) return 2;
#endif
  (void)asked;
  return 0;
}

}  // namespace

FastColumn::Impl::Impl(int threads, CpuKernels kernels)
    : pool(threads), workers(pool.size()), automatic_threads(threads == 0) {
  const int level = simd_level(kernels);
#if defined(FLUIDWEIGHT_AVX512)
  if (level == 512) {
    avx512 = true;
    raster = rows::raster_avx512;
    resolve = rows::resolve_avx512;
  }
#endif
#if defined(FLUIDWEIGHT_AVX2)
  if (level == 2) {
    raster = rows::raster_avx2;
    resolve = rows::resolve_avx2;
  }
#endif
  (void)level;
}

FastColumn::FastColumn(int threads, CpuKernels kernels)
    : impl_(std::make_unique<Impl>(threads, kernels)) {}
FastColumn::~FastColumn() = default;

void FastColumn::run(const CavityView& cavity, const Frame& frame, int n, double rho_g,
                     CavityOutput& out, double& volume) {
  Impl& m = *impl_;
  const int nv = cavity.num_vertices, nt = cavity.num_triangles;
  // Waking the workers costs tens of microseconds a phase: with the thread count left
  // automatic, small problems run on the calling thread alone.
  const bool small =
      m.automatic_threads && static_cast<long long>(nt) + static_cast<long long>(n) * n < 200000;
  const int threads = small ? 1 : m.pool.size();
  auto parallel = [&](const std::function<void(int)>& task) {
    if (threads == 1) {
      task(0);
    } else {
      m.pool.run(task);
    }
  };
  auto slice = [threads](int count, int index, int& begin, int& end) {
    begin = static_cast<int>(static_cast<long long>(count) * index / threads);
    end = static_cast<int>(static_cast<long long>(count) * (index + 1) / threads);
  };
  out.values.assign(nv, 0.0);
  out.column_volume = 0.0;
  out.unmatched_columns = 0;

  // Step 1: the projected box, then the snapped vertices and each triangle's rows; the signed
  // volume (its sign is the orientation) is summed in Step 2.
  std::vector<std::array<double, 6>> partial(threads);
  parallel([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    double inf = std::numeric_limits<double>::infinity();
    std::array<double, 6> box{inf, -inf, inf, -inf, inf, -inf};
    for (int v = begin; v < end; ++v) {
      Vec3 p = load_vec3(cavity.xyz, v);
      double c[3] = {dot_rn(p, frame.e1), dot_rn(p, frame.e2), dot_rn(p, frame.up)};
      for (int d = 0; d < 3; ++d) {
        box[2 * d] = std::min(box[2 * d], c[d]);
        box[2 * d + 1] = std::max(box[2 * d + 1], c[d]);
      }
    }
    partial[index] = box;
  });
  std::array<double, 6> box = partial[0];
  for (int k = 1; k < threads; ++k) {
    for (int d = 0; d < 6; d += 2) {
      box[d] = std::min(box[d], partial[k][d]);
      box[d + 1] = std::max(box[d + 1], partial[k][d + 1]);
    }
  }
  int& orientation = m.orientation_of(cavity.triangles);
  m.grid = make_grid(box[0], box[1], box[2], box[3], box[4], box[5], n, orientation);
  GridParams& grid = m.grid;
  if (grid.empty) {
    volume = signed_volume(cavity);
    return;
  }
  m.rho_g = rho_g;
  const int s = grid.sub_bits, units = n << s;
  m.vertices.resize(nv);
  m.step2_vertices.resize(nv);
  parallel([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    for (int v = begin; v < end; ++v) {
      Vec3 p = load_vec3(cavity.xyz, v);
      const double a = dot_rn(p, frame.e1), b = dot_rn(p, frame.e2),
                   u = dot_rn(p, frame.up) - grid.u0;
      const int x = snap(a, grid.a0, grid.scale_a, units),
                y = snap(b, grid.b0, grid.scale_b, units);
      m.vertices[v] = {x, y, u};
      m.step2_vertices[v] = {x, y, a - grid.a0, b - grid.b0, u};
    }
  });
  // Step 2 per triangle, in input order: its first row (or none) and flags; and the signed
  // volume.
  m.row0.resize(nt);
  m.flags.resize(nt);
  std::vector<int> tallest(threads, 1);  // rows of the tallest box
  std::vector<double> volume6(threads, 0.0);
  auto step2 = [&](int index) {
    int begin, end;
    slice(nt, index, begin, end);
#if defined(FLUIDWEIGHT_AVX512)
    if (m.avx512) {
      static_assert(sizeof(Step2Vertex) == 32, "step2_avx512 reads 32-byte records");
      tallest[index] = rows::step2_avx512(
          cavity.triangles, begin, end, reinterpret_cast<const int*>(m.step2_vertices.data()), s,
          grid.orientation, m.row0.data(), m.flags.data(), volume6[index]);
      return;
    }
#endif
    int tall = 1;
    double sum = 0.0;
    for (int t = begin; t < end; ++t) {
      // setup_triangle's box, orientation and fill-rule thresholds without branches: floors and
      // ceilings, flipped or not, come in random order and mispredicted a few times a triangle.
      // Meshes may list their vertices in any order: those of later triangles are asked for
      // ahead.
      if (t + kPrefetchAhead < end) {
        for (int k = 0; k < 3; ++k)
          prefetch(&m.step2_vertices[cavity.triangles[3 * (t + kPrefetchAhead) + k]]);
      }
      const int* v = cavity.triangles + 3 * t;
      const Step2Vertex &a = m.step2_vertices[v[0]], &b = m.step2_vertices[v[1]],
                        &c = m.step2_vertices[v[2]];
      sum += a.a * (b.b * c.u - b.u * c.b) + a.b * (b.u * c.a - b.a * c.u) +
             a.u * (b.a * c.b - b.b * c.a);
      const int half = 1 << (s - 1);
      const int xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
      const int ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
      // Snapped coordinates lie in [0, N 2^s]: the box needs no clamping to the grid.
      const int i0 = -((half - xmin) >> s), i1 = (xmax - half) >> s;
      const int j0 = -((half - ymin) >> s), j1 = (ymax - half) >> s;
      const int64_t area2 = edge_function(a.x, a.y, b.x, b.y, c.x, c.y);
      const bool covers = area2 != 0 && i0 <= i1 && j0 <= j1;
      m.row0[t] = covers ? j0 : -1;
      tall = std::max(tall, covers ? j1 - j0 + 1 : 1);
      // Counter-clockwise corners: 1 and 2 swapped when the input order is clockwise.
      const bool flip = area2 < 0;
      const bool bottom = (area2 > 0) != (grid.orientation > 0);
      const int x[3] = {a.x, flip ? c.x : b.x, flip ? b.x : c.x};
      const int y[3] = {a.y, flip ? c.y : b.y, flip ? b.y : c.y};
      unsigned f = (bottom ? 8u : 0u) | (flip ? 16u : 0u) |
                   (static_cast<unsigned>(std::min(2, std::max(0, i1 - i0) / rows::kChunk)) << 5);
      for (int k = 0; k < 3; ++k) {
        const int p = k == 2 ? 0 : k + 1, q = k == 0 ? 2 : k - 1;
        const int dx = x[q] - x[p], dy = y[q] - y[p];
        // Top edge: horizontal, going left (interior below). Left edge: going down.
        const unsigned top_left = (dy < 0) | ((dy == 0) & (dx < 0));
        f |= (top_left ^ 1u) << k;
      }
      m.flags[t] = f;
    }
    tallest[index] = tall;
    volume6[index] = sum;
  };
  parallel(step2);
  double sum6 = 0.0;
  for (double v : volume6) sum6 += v;
  volume = sum6 / 6.0;
  if ((volume < 0 ? -1 : 1) != grid.orientation) {
    orientation = grid.orientation = -grid.orientation;
    parallel(step2);
  }
  // Triangles by first row (a counting sort), and within a row by kind and width class, so
  // that the sweep's branches on them (floor or ceiling, which raster kernel) are predicted:
  // in input order they are random. Those without columns (row0 = -1) are sorted too, into
  // buckets before row 0, so that neither loop branches on them (at coarse grids half the
  // triangles have no column, in random order).
  constexpr int kClasses = 6;
  auto bucket = [&m](int t) {
    const unsigned f = m.flags[t];
    return (m.row0[t] + 1) * kClasses + static_cast<int>(((f >> 3) & 1u) * 3 + ((f >> 5) & 3u));
  };
  std::vector<int>& start = m.bucket_start;
  start.assign((n + 1) * kClasses + 1, 0);
  for (int t = 0; t < nt; ++t) ++start[bucket(t) + 1];
  for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  m.sorted.resize(nt);
  for (int t = 0; t < nt; ++t) {
    const int* v = cavity.triangles + 3 * t;
    const bool flip = m.flags[t] & 16u;
    m.sorted[start[bucket(t)]++] = {{v[0], flip ? v[2] : v[1], flip ? v[1] : v[2]},
                                    m.flags[t] & 15u};
  }
  // Each bucket's start moved to the next one's: row j is [row_start[j], row_start[j + 1]).
  m.row_start.resize(n + 1);
  for (int j = 0; j <= n; ++j) m.row_start[j] = start[(j + 1) * kClasses - 1];
  m.num_bands = threads == 1 ? 1 : std::min(n, 8 * threads);
  m.band_rows = (n + m.num_bands - 1) / m.num_bands;
  m.num_bands = (n + m.band_rows - 1) / m.band_rows;
  m.carried_start.assign(m.num_bands + 1, 0);
  m.carried.clear();
  if (m.num_bands > 1) {
    // Triangles reaching a later band than that of their first row, by band.
    const int half = 1 << (s - 1);
    auto last_row = [&](int c) {
      const int* v = m.sorted[c].vertex;
      const int ymax = std::max({m.vertices[v[0]].y, m.vertices[v[1]].y, m.vertices[v[2]].y});
      return std::min(n - 1, (ymax - half) >> s);
    };
    for (int j = 0; j < n; ++j) {
      for (int c = m.row_start[j]; c < m.row_start[j + 1]; ++c) {
        for (int b = j / m.band_rows + 1; b <= last_row(c) / m.band_rows; ++b) {
          ++m.carried_start[b + 1];
        }
      }
    }
    for (int b = 0; b < m.num_bands; ++b) m.carried_start[b + 1] += m.carried_start[b];
    m.carried.resize(m.carried_start[m.num_bands]);
    std::vector<int> fill(m.carried_start.begin(), m.carried_start.end() - 1);
    for (int j = 0; j < n; ++j) {
      for (int c = m.row_start[j]; c < m.row_start[j + 1]; ++c) {
        for (int b = j / m.band_rows + 1; b <= last_row(c) / m.band_rows; ++b) {
          m.carried[fill[b]++] = c;
        }
      }
    }
  }

  // The ring holds the rows of the tallest box, so that most triangles are rasterized at once,
  // within bounds that keep it in the cache; taller triangles go on in later blocks.
  const int tall = *std::max_element(tallest.begin(), tallest.end());
  m.ring_rows = 1;
  while (m.ring_rows < std::min(tall, kMaxRingRows)) m.ring_rows *= 2;
  const size_t row_bytes =
      (static_cast<size_t>(n) + 16) * (2 + 2 * 8 * rows::kPlanes + 4 * rows::kPlanes);
  while (m.ring_rows > 1 && m.ring_rows * row_bytes > kRingBytes) m.ring_rows /= 2;

  // Steps 3-5, band by band.
  std::atomic<int> next_band{0};
  parallel([&](int index) {
    Worker& w = m.workers[index];
    w.ring.resize(m.ring_rows, n);
    w.pending.resize(m.ring_rows);
    w.weights.assign(nv, 0.0);
    w.totals = rows::RowTotals();
    for (int b; (b = next_band++) < m.num_bands;) m.sweep_band(b, w);
  });
  if (threads == 1) {
    out.values.swap(m.workers[0].weights);
  } else {
    parallel([&](int index) {
      int begin, end;
      slice(nv, index, begin, end);
      for (int k = 0; k < threads; ++k) {
        for (int v = begin; v < end; ++v) out.values[v] += m.workers[k].weights[v];
      }
    });
  }
  double sum_heights = 0.0;
  for (int k = 0; k < threads; ++k) {
    sum_heights += m.workers[k].totals.sum_heights;
    out.unmatched_columns += m.workers[k].totals.unmatched;
  }
  out.column_volume = grid.cell_area * sum_heights;
}

}  // namespace fluidweight::detail
