// Column method, CPU fast path: the same columns, pairs and weights as column_reference, by row
// sweeps over bands of rows on worker threads.
//
// A band of rows keeps the triangles that cross the current row (an active list, as scanline
// rasterizers do). A triangle is set up when it becomes active: its snapped edge functions at
// its first column and their steps along a row and a column, its height plane. On each row it
// finds its span of covered columns (exactly, with the fill rule) and drops one hit per column
// into a small per-column buffer. The row's columns are then resolved: a floor and a ceiling
// (the usual case) make one section; more hits are sorted and paired as in the reference. A
// section's height goes into three moments of its floor triangle (sum h, sum h di, sum h dj,
// held in the active entry); barycentric coordinates are linear in the column indices, so when
// the triangle leaves the band its nodal weights follow from the moments.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>

#include "cpu.hpp"
#include "thread_pool.hpp"

namespace fluidweight::detail {
namespace {

constexpr int kSlots = 6;        // floors (and ceilings) a column keeps sorted before spilling
constexpr int kNarrowSpan = 12;  // rows of a narrower box are scanned column by column

// A triangle crossing the current row. E_k(i, j) = e[k] + di[k] (i - i0) + dj[k] (j - row).
struct Active {
  int64_t e[3], di[3], dj[3], e_min[3];
  int64_t e_ref[3];     // E_k at (i0, j_ref), the row where the moments start
  double z, dzi, dzj;   // height at (i0, current row) and its steps
  double m0, mi, mj;    // sum h, sum h (i - i0), sum h (j - j_ref) over this band's sections
  double weight_scale;  // rho |g| cell area / twice the snapped area
  int i0, i1, j1, j_ref;
  int vertex[3];  // counter-clockwise corners' vertices
  bool bottom;
};

// A triangle after Step 1, stored in order of its first row.
struct TriangleRecord {
  int x[3], y[3];  // snapped corners, input order
  int vertex[3];
  int row0, row1;  // rows of its box (row0 > row1: it covers no column)
  double z[3];     // heights above the lowest vertex
};

struct RowHit {
  double z;
  int slot;  // index of the active entry
};

// Per-column hits of the current row, floors and ceilings apart, each kept sorted by height.
struct RowBuffer {
  std::vector<int> count;
  std::vector<RowHit> slots;
  std::vector<std::pair<int, RowHit>> spill;  // beyond kSlots in a column (rare)

  void resize(int n) {
    count.assign(n, 0);
    slots.resize(static_cast<size_t>(n) * kSlots);
    spill.clear();
  }
  void add(int i, RowHit hit) {
    int c = count[i]++;
    if (c >= kSlots) {
      spill.emplace_back(i, hit);
      return;
    }
    RowHit* s = &slots[static_cast<size_t>(i) * kSlots];
    while (c > 0 && s[c - 1].z > hit.z) {
      s[c] = s[c - 1];
      --c;
    }
    s[c] = hit;
  }
  // The column's hits, sorted, in `out` (only needed when it spilled).
  void gather(int i, std::vector<RowHit>& out) const {
    out.assign(&slots[static_cast<size_t>(i) * kSlots],
               &slots[static_cast<size_t>(i) * kSlots] + kSlots);
    for (const auto& [col, hit] : spill) {
      if (col == i) out.push_back(hit);
    }
    std::sort(out.begin(), out.end(), [](const RowHit& a, const RowHit& b) { return a.z < b.z; });
  }
};

// Buffers of one worker thread, kept between calls.
struct Worker {
  RowBuffer floors, ceilings;
  std::vector<Active> pool;  // active entries stay in place while active
  std::vector<int> live, free;
  std::vector<double> weights;  // one per vertex
  std::vector<RowHit> spilled_floors, spilled_ceilings;
  double sum_heights = 0.0;
  long long unmatched = 0;
};

// Floor division for the span bounds (b > 0).
int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

struct FastColumn::Impl {
  explicit Impl(int threads)
      : pool(threads), workers(pool.size()), automatic_threads(threads == 0) {}

  void sweep_band(const GridParams& grid, double rho_g, int band, Worker& w);
  void activate(const GridParams& grid, double rho_g, const TriangleRecord& r, int j, Worker& w);
  void retire(int slot, Worker& w);
  void raster_row(Active& a, int& lo, int& hi, Worker& w, int slot);
  void resolve_row(int j, int lo, int hi, Worker& w);

  ThreadPool pool;
  std::vector<Worker> workers;
  std::vector<int> sx, sy;
  std::vector<double> z;
  std::vector<int> row0, row1;             // rows of each triangle's box (row0 > row1: no column)
  std::vector<int> order;                  // triangles with columns, by first row
  std::vector<TriangleRecord> sorted;      // their records, in that order
  std::vector<int> band_start, band_list;  // indices into `sorted`
  int band_rows = 1, num_bands = 1;
  bool automatic_threads;  // threads = 0: all of them, but one for small problems
};

FastColumn::FastColumn(int threads) : impl_(std::make_unique<Impl>(threads)) {}
FastColumn::~FastColumn() = default;

void FastColumn::Impl::activate(const GridParams& grid, double rho_g, const TriangleRecord& r,
                                int j, Worker& w) {
  SnappedTriangle tri{};
  setup_triangle(r.x, r.y, grid.orientation, grid.n, grid.sub_bits, &tri);
  int slot;
  if (w.free.empty()) {
    slot = static_cast<int>(w.pool.size());
    w.pool.emplace_back();
  } else {
    slot = w.free.back();
    w.free.pop_back();
  }
  Active& a = w.pool[slot];
  const int s = grid.sub_bits;
  int64_t e[3];
  covers(tri, column_centre(tri.i0, s), column_centre(j, s), e);
  const int64_t unit = int64_t{1} << s;
  double z0 = 0, dzi = 0, dzj = 0;
  for (int k = 0; k < 3; ++k) {
    int p = (k + 1) % 3, q = (k + 2) % 3;
    a.e[k] = a.e_ref[k] = e[k];
    a.di[k] = -static_cast<int64_t>(tri.y[q] - tri.y[p]) * unit;
    a.dj[k] = static_cast<int64_t>(tri.x[q] - tri.x[p]) * unit;
    a.e_min[k] = tri.e_min[k];
    const int c = tri.corner[k];  // 0, 1 or 2
    a.vertex[k] = c == 0 ? r.vertex[0] : c == 1 ? r.vertex[1] : r.vertex[2];
    double zk = c == 0 ? r.z[0] : c == 1 ? r.z[1] : r.z[2];
    z0 += static_cast<double>(e[k]) * zk;
    dzi += static_cast<double>(a.di[k]) * zk;
    dzj += static_cast<double>(a.dj[k]) * zk;
  }
  double inv = 1.0 / static_cast<double>(tri.area2);
  a.z = z0 * inv;
  a.dzi = dzi * inv;
  a.dzj = dzj * inv;
  a.m0 = a.mi = a.mj = 0.0;
  a.weight_scale = rho_g * grid.cell_area * inv;
  a.i0 = tri.i0;
  a.i1 = tri.i1;
  a.j1 = tri.j1;
  a.j_ref = j;
  a.bottom = tri.bottom;
  w.live.push_back(slot);
}

void FastColumn::Impl::retire(int slot, Worker& w) {
  const Active& a = w.pool[slot];
  if (a.bottom && a.m0 != 0.0) {
    for (int k = 0; k < 3; ++k) {
      w.weights[a.vertex[k]] += a.weight_scale * (static_cast<double>(a.e_ref[k]) * a.m0 +
                                                  static_cast<double>(a.di[k]) * a.mi +
                                                  static_cast<double>(a.dj[k]) * a.mj);
    }
  }
  w.free.push_back(slot);
}

// Drops the hits of one active triangle on the current row.
void FastColumn::Impl::raster_row(Active& a, int& lo, int& hi, Worker& w, int slot) {
  int first = a.i0, last = a.i1;
  if (last - first >= kNarrowSpan) {
    // The span, edge by edge: E_k(i) = e[k] + di[k] (i - i0) >= e_min[k].
    for (int k = 0; k < 3 && first <= last; ++k) {
      int64_t need = a.e_min[k] - a.e[k];
      if (a.di[k] > 0) {
        if (need > 0) first = std::max<int64_t>(first, a.i0 - floor_div(-need, a.di[k]));
      } else if (a.di[k] < 0) {
        last = std::min<int64_t>(last, a.i0 + floor_div(-need, -a.di[k]));
      } else if (need > 0) {
        last = first - 1;
      }
    }
  } else {
    // Narrow: find the span by testing the columns.
    int64_t e0 = a.e[0], e1 = a.e[1], e2 = a.e[2];
    int i = a.i0;
    for (; i <= a.i1; ++i, e0 += a.di[0], e1 += a.di[1], e2 += a.di[2]) {
      if (e0 >= a.e_min[0] && e1 >= a.e_min[1] && e2 >= a.e_min[2]) break;
    }
    first = i;
    for (; i <= a.i1; ++i, e0 += a.di[0], e1 += a.di[1], e2 += a.di[2]) {
      if (!(e0 >= a.e_min[0] && e1 >= a.e_min[1] && e2 >= a.e_min[2])) break;
    }
    last = i - 1;
  }
  if (first > last) return;
  RowBuffer& buffer = a.bottom ? w.floors : w.ceilings;
  double zi = a.z + a.dzi * (first - a.i0);
  for (int i = first; i <= last; ++i, zi += a.dzi) buffer.add(i, RowHit{zi, slot});
  lo = std::min(lo, first);
  hi = std::max(hi, last);
}

void FastColumn::Impl::sweep_band(const GridParams& grid, double rho_g, int band, Worker& w) {
  const int n = grid.n;
  const int ja = band * band_rows, jb = std::min(n, ja + band_rows);
  w.live.clear();
  int next = band_start[band];
  const int end = band_start[band + 1];
  for (int j = ja; j < jb; ++j) {
    while (next < end && sorted[band_list[next]].row0 <= j) {
      const TriangleRecord& r = sorted[band_list[next++]];
      if (r.row1 >= j) activate(grid, rho_g, r, j, w);
    }
    int lo = n, hi = -1;
    for (size_t k = 0; k < w.live.size();) {
      int slot = w.live[k];
      Active& a = w.pool[slot];
      if (a.j1 < j) {
        retire(slot, w);
        w.live[k] = w.live.back();
        w.live.pop_back();
        continue;
      }
      raster_row(a, lo, hi, w, slot);
      for (int q = 0; q < 3; ++q) a.e[q] += a.dj[q];
      a.z += a.dzj;
      ++k;
    }
    resolve_row(j, lo, hi, w);
  }
  for (int slot : w.live) retire(slot, w);
  w.live.clear();
}

void FastColumn::Impl::resolve_row(int j, int lo, int hi, Worker& w) {
  auto add_section = [&](int slot, double h, int i) {
    Active& a = w.pool[slot];
    a.m0 += h;
    a.mi += h * (i - a.i0);
    a.mj += h * (j - a.j_ref);
    w.sum_heights += h;
  };
  RowBuffer &floors = w.floors, &ceilings = w.ceilings;
  for (int i = lo; i <= hi; ++i) {
    const int nf = floors.count[i], nc = ceilings.count[i];
    if (nf == 0 && nc == 0) continue;
    floors.count[i] = ceilings.count[i] = 0;
    if (nf != nc) ++w.unmatched;
    const RowHit* f = &floors.slots[static_cast<size_t>(i) * kSlots];
    const RowHit* c = &ceilings.slots[static_cast<size_t>(i) * kSlots];
    if (nf > kSlots || nc > kSlots) {
      floors.gather(i, w.spilled_floors);
      ceilings.gather(i, w.spilled_ceilings);
      f = w.spilled_floors.data();
      c = w.spilled_ceilings.data();
    }
    // The k-th lowest floor pairs with the k-th lowest ceiling.
    for (int k = 0; k < std::min(nf, nc); ++k) add_section(f[k].slot, c[k].z - f[k].z, i);
  }
  floors.spill.clear();
  ceilings.spill.clear();
}

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

  // Step 1: the projected box and the signed volume (its sign is the orientation), then the
  // snapped vertices and the triangles' records.
  std::vector<std::array<double, 7>> partial(threads);
  parallel([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    double inf = std::numeric_limits<double>::infinity();
    std::array<double, 7> box{inf, -inf, inf, -inf, inf, -inf, 0.0};
    for (int v = begin; v < end; ++v) {
      Vec3 p = load_vec3(cavity.xyz, v);
      double c[3] = {dot_rn(p, frame.e1), dot_rn(p, frame.e2), dot_rn(p, frame.up)};
      for (int d = 0; d < 3; ++d) {
        box[2 * d] = std::min(box[2 * d], c[d]);
        box[2 * d + 1] = std::max(box[2 * d + 1], c[d]);
      }
    }
    slice(nt, index, begin, end);
    Vec3 o = load_vec3(cavity.xyz, 0);
    for (int t = begin; t < end; ++t) {
      const int* v = cavity.triangles + 3 * t;
      Vec3 a = load_vec3(cavity.xyz, v[0]), b = load_vec3(cavity.xyz, v[1]),
           c = load_vec3(cavity.xyz, v[2]);
      double ax = a.x - o.x, ay = a.y - o.y, az = a.z - o.z;
      double bx = b.x - o.x, by = b.y - o.y, bz = b.z - o.z;
      double cx = c.x - o.x, cy = c.y - o.y, cz = c.z - o.z;
      box[6] += ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
    }
    partial[index] = box;
  });
  std::array<double, 7> box = partial[0];
  for (int k = 1; k < threads; ++k) {
    for (int d = 0; d < 6; d += 2) {
      box[d] = std::min(box[d], partial[k][d]);
      box[d + 1] = std::max(box[d + 1], partial[k][d + 1]);
    }
    box[6] += partial[k][6];
  }
  volume = box[6] / 6.0;
  const GridParams grid = make_grid(box[0], box[1], box[2], box[3], box[4], box[5], n, volume);
  if (grid.empty) return;
  const int s = grid.sub_bits, units = n << s;
  m.sx.resize(nv);
  m.sy.resize(nv);
  m.z.resize(nv);
  parallel([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    for (int v = begin; v < end; ++v) {
      Vec3 p = load_vec3(cavity.xyz, v);
      m.sx[v] = snap(dot_rn(p, frame.e1), grid.a0, grid.scale_a, units);
      m.sy[v] = snap(dot_rn(p, frame.e2), grid.b0, grid.scale_b, units);
      m.z[v] = dot_rn(p, frame.up) - grid.u0;
    }
  });
  // Each triangle's rows (input order, where vertices are near each other in memory), then
  // the records built directly in first-row order (a counting sort of the indices).
  m.row0.resize(nt);
  m.row1.resize(nt);
  parallel([&](int index) {
    int begin, end;
    slice(nt, index, begin, end);
    const int half = 1 << (s - 1);
    for (int t = begin; t < end; ++t) {
      const int* v = cavity.triangles + 3 * t;
      int x0 = m.sx[v[0]], x1 = m.sx[v[1]], x2 = m.sx[v[2]];
      int y0 = m.sy[v[0]], y1 = m.sy[v[1]], y2 = m.sy[v[2]];
      int xmin = std::min({x0, x1, x2}), xmax = std::max({x0, x1, x2});
      int ymin = std::min({y0, y1, y2}), ymax = std::max({y0, y1, y2});
      bool has_columns = ((xmax - half) >> s) >= -((half - xmin) >> s) &&
                         edge_function(x0, y0, x1, y1, x2, y2) != 0;
      m.row0[t] = -((half - ymin) >> s);
      m.row1[t] = has_columns ? std::min(n - 1, (ymax - half) >> s) : -1;
    }
  });
  std::vector<int> first(n + 1, 0);
  for (int t = 0; t < nt; ++t) {
    if (m.row0[t] <= m.row1[t]) ++first[m.row0[t] + 1];
  }
  for (int j = 0; j < n; ++j) first[j + 1] += first[j];
  m.order.resize(first[n]);
  for (int t = 0; t < nt; ++t) {
    if (m.row0[t] <= m.row1[t]) m.order[first[m.row0[t]]++] = t;
  }
  m.sorted.resize(m.order.size());
  parallel([&](int index) {
    int begin, end;
    slice(static_cast<int>(m.order.size()), index, begin, end);
    for (int k = begin; k < end; ++k) {
      const int t = m.order[k];
      const int* v = cavity.triangles + 3 * t;
      TriangleRecord& r = m.sorted[k];
      for (int c = 0; c < 3; ++c) {
        r.x[c] = m.sx[v[c]];
        r.y[c] = m.sy[v[c]];
        r.z[c] = m.z[v[c]];
        r.vertex[c] = v[c];
      }
      r.row0 = m.row0[t];
      r.row1 = m.row1[t];
    }
  });
  const int count = static_cast<int>(m.sorted.size());
  m.num_bands = threads == 1 ? 1 : std::min(n, 8 * threads);
  m.band_rows = (n + m.num_bands - 1) / m.num_bands;
  m.num_bands = (n + m.band_rows - 1) / m.band_rows;
  m.band_start.assign(m.num_bands + 1, 0);
  for (const TriangleRecord& r : m.sorted) {
    for (int b = r.row0 / m.band_rows; b <= r.row1 / m.band_rows; ++b) ++m.band_start[b + 1];
  }
  for (int b = 0; b < m.num_bands; ++b) m.band_start[b + 1] += m.band_start[b];
  m.band_list.resize(m.band_start[m.num_bands]);
  {
    std::vector<int> fill(m.band_start.begin(), m.band_start.end() - 1);
    for (int k = 0; k < count; ++k) {
      const TriangleRecord& r = m.sorted[k];
      for (int b = r.row0 / m.band_rows; b <= r.row1 / m.band_rows; ++b) m.band_list[fill[b]++] = k;
    }
  }

  // Steps 2-5, band by band.
  std::atomic<int> next_band{0};
  parallel([&](int index) {
    Worker& w = m.workers[index];
    w.floors.resize(n);
    w.ceilings.resize(n);
    w.weights.assign(nv, 0.0);
    w.sum_heights = 0.0;
    w.unmatched = 0;
    for (int b; (b = next_band++) < m.num_bands;) m.sweep_band(grid, rho_g, b, w);
  });
  parallel([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    for (int k = 0; k < threads; ++k) {
      for (int v = begin; v < end; ++v) out.values[v] += m.workers[k].weights[v];
    }
  });
  double sum_heights = 0.0;
  for (int k = 0; k < threads; ++k) {
    sum_heights += m.workers[k].sum_heights;
    out.unmatched_columns += m.workers[k].unmatched;
  }
  out.column_volume = grid.cell_area * sum_heights;
}

}  // namespace fluidweight::detail
