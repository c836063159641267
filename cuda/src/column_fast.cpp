// Column method, CPU fast path: the same columns, pairs and weights as column_reference, by row
// sweeps over bands of rows on worker threads.
//
// A band of rows keeps the triangles that cross the current row (an active list, as scanline
// rasterizers do). A triangle is set up when it becomes active: its snapped edge functions at
// its first column and their steps along a row and a column, its height plane. On each row it
// finds its covered columns (exactly, with the fill rule) and drops one hit per column into
// per-column buffers. The row's columns are then resolved: a floor and a ceiling (the usual
// case) make one section; more hits are sorted and paired as in the reference. A section's
// height goes into three moments of its floor triangle (sum h, sum h di, sum h dj, held in the
// active entry); barycentric coordinates are linear in the column indices, so when the triangle
// leaves the band its nodal weights follow from the moments.
//
// Layout, for one core (measured: bench/fluidweight/NOTES.md, CPU rows). The sweep touches, per
// row, every active entry and every covered column, so both are kept small and dense: active
// entries in one array (a retired one is replaced by the last), hits in planes of one value per
// column (the first floor of every column side by side, then the second...), so that the usual
// row touches a few kilobytes. Spans and hits are found and written without data-dependent
// branches (bit masks, fixed chunks, a sorting network), which mispredicted a few times a row.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>

#include "cpu.hpp"
#include "thread_pool.hpp"

namespace fluidweight::detail {
namespace {

constexpr int kPlanes = 4;     // hits of each kind a column keeps in the row buffer; more spill
constexpr int kPrefetch = 8;   // triangles whose vertices are asked for ahead of activation
constexpr int kScanWidth = 8;  // boxes up to this wide test every column; wider ones divide

// A vertex after Step 1: snapped coordinates and height above the lowest vertex.
struct SnappedVertex {
  int x, y;
  double z;
};

// A triangle with columns after Step 2, in first-row order: its vertices counter-clockwise and
// flags. 16 bytes: the sweep reads them one after another and gathers the vertices (a
// triangle's vertices are near each other in memory, and there are half as many).
struct SortedTriangle {
  int vertex[3];
  unsigned flags;  // bit k (0-2): e_min[k] = 1, the edge is neither top nor left; bit 3: a floor
};

// A triangle crossing the current row. E_k(i, j) = e[k] + di[k] (i - i0) + dj[k] (j - row) +
// e_min[k]: the fill-rule thresholds are folded into e, so a centre is covered when all three
// are >= 0.
struct Active {
  int64_t e[3], di[3], dj[3];
  double z, dzi, dzj;     // height at (i0, current row) and its steps
  double m0, mi, mj;      // sum h, sum h (i - i0), sum h (j - j_ref) over the sections it floors
  int i0, i1, j1, j_ref;  // its columns, last row, and the row where it became active
  int triangle;           // input index, of its record
  bool bottom;
};

struct Spilled {
  int column;
  double z;
  int index;
};

// Hits of the current row, of one kind (floors or ceilings), unsorted: the c-th hit of column i
// is at c stride + i (planes, so that the first hits of a row's columns lie side by side), or
// in `spill` beyond kPlanes.
struct RowHits {
  int stride = 0;
  std::vector<int> count;
  std::vector<double> z;
  std::vector<int> index;  // of the active entry
  std::vector<Spilled> spill;

  void resize(int columns) {
    stride = columns;
    count.assign(stride, 0);
    z.resize(static_cast<size_t>(stride) * kPlanes);
    index.resize(static_cast<size_t>(stride) * kPlanes);
    spill.clear();
  }
  // Column i's hits into z_out and index_out (count[i] of them), sorted by height.
  void gather(int i, double* z_out, int* index_out) const {
    const int m = count[i];
    for (int c = 0; c < std::min(m, kPlanes); ++c) {
      z_out[c] = z[static_cast<size_t>(c) * stride + i];
      index_out[c] = index[static_cast<size_t>(c) * stride + i];
    }
    if (m > kPlanes) {
      int c = kPlanes;
      for (const Spilled& s : spill) {
        if (s.column == i) {
          z_out[c] = s.z;
          index_out[c++] = s.index;
        }
      }
    }
    // Insertion sort: a column has a few hits.
    for (int c = 1; c < m; ++c) {
      const double zc = z_out[c];
      const int ic = index_out[c];
      int d = c;
      for (; d > 0 && z_out[d - 1] > zc; --d) {
        z_out[d] = z_out[d - 1];
        index_out[d] = index_out[d - 1];
      }
      z_out[d] = zc;
      index_out[d] = ic;
    }
  }
};

// Buffers of one worker thread, kept between calls.
struct Worker {
  RowHits floors, ceilings;
  std::vector<Active> active;  // the first `live` entries are the active triangles
  int live = 0;
  std::vector<double> weights;      // one per vertex
  std::vector<double> column_z[2];  // a column's floors (0) or ceilings (1), sorted
  std::vector<int> column_index[2];
  double sum_heights = 0.0;
  long long unmatched = 0;
};

void prefetch(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

// Lowest and highest set bit of a non-zero mask.
int lowest_bit(uint64_t m) {
#if defined(__GNUC__)
  return __builtin_ctzll(m);
#else
  int b = 0;
  while (!((m >> b) & 1)) ++b;
  return b;
#endif
}
int highest_bit(uint64_t m) {
#if defined(__GNUC__)
  return 63 - __builtin_clzll(m);
#else
  int b = 63;
  while (!((m >> b) & 1)) --b;
  return b;
#endif
}

// Sorts four heights (and their indices, when given) by a sorting network: compare-exchanges
// without branches, whose outcome depends on the data.
static_assert(kPlanes == 4, "sort4 sorts a column's planes");
void sort4(double* z, int* index) {
  auto exchange = [&](int a, int b) {
    const bool swap = z[b] < z[a];
    const double za = z[a], zb = z[b];
    z[a] = swap ? zb : za;
    z[b] = swap ? za : zb;
    if (index) {
      const int ia = index[a], ib = index[b];
      index[a] = swap ? ib : ia;
      index[b] = swap ? ia : ib;
    }
  };
  exchange(0, 1);
  exchange(2, 3);
  exchange(0, 2);
  exchange(1, 3);
  exchange(1, 2);
}

// Floor division for the span bounds (b > 0).
int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

struct FastColumn::Impl {
  explicit Impl(int threads)
      : pool(threads), workers(pool.size()), automatic_threads(threads == 0) {}

  void sweep_band(int band, Worker& w);
  void activate(int t, int j, Worker& w);
  void retire(const Active& a, int j, Worker& w);
  void raster_row(const Active& a, int k, int& lo, int& hi, Worker& w);
  void resolve_row(int j, int lo, int hi, Worker& w);

  ThreadPool pool;
  std::vector<Worker> workers;
  // The call's grid, and per vertex its snapped coordinates and height.
  GridParams grid;
  double rho_g = 0.0;
  std::vector<SnappedVertex> vertices;
  std::vector<int> row0;        // first row of each triangle's box, -1: no column
  std::vector<unsigned> flags;  // SortedTriangle::flags, and bit 4: corners 1 and 2 swapped
  // Triangles with columns by first row: those of row j are sorted[row_start[j] ..
  // row_start[j + 1]).
  std::vector<int> row_start;
  std::vector<SortedTriangle> sorted;
  // Bands: rows [b band_rows, (b + 1) band_rows); triangles starting in an earlier band and
  // reaching band b are carried[carried_start[b] .. carried_start[b + 1]).
  std::vector<int> carried_start, carried;
  int band_rows = 1, num_bands = 1;
  bool automatic_threads;  // threads = 0: all of them, but one for small problems
};

FastColumn::FastColumn(int threads) : impl_(std::make_unique<Impl>(threads)) {}
FastColumn::~FastColumn() = default;

// Sets up triangle t on row j (its first row, or the first row of the band): its box as
// setup_triangle finds it, its edge functions at (i0, j) and their steps, its height plane.
void FastColumn::Impl::activate(int t, int j, Worker& w) {
  const SortedTriangle& st = sorted[t];
  struct {
    int x[3], y[3];
    double z[3];
    unsigned flags;
  } r;
  for (int k = 0; k < 3; ++k) {
    const SnappedVertex& p = vertices[st.vertex[k]];
    r.x[k] = p.x;
    r.y[k] = p.y;
    r.z[k] = p.z;
  }
  r.flags = st.flags;
  if (w.live == static_cast<int>(w.active.size())) w.active.emplace_back();
  Active& a = w.active[w.live++];
  const int s = grid.sub_bits, half = 1 << (s - 1);
  const int xmin = std::min({r.x[0], r.x[1], r.x[2]}), xmax = std::max({r.x[0], r.x[1], r.x[2]});
  a.i0 = std::max(0, -((half - xmin) >> s));
  a.i1 = std::min(grid.n - 1, (xmax - half) >> s);
  a.j1 = std::min(grid.n - 1, (std::max({r.y[0], r.y[1], r.y[2]}) - half) >> s);
  a.j_ref = j;
  a.triangle = t;
  a.bottom = (r.flags >> 3) & 1;
  const int px = column_centre(a.i0, s), py = column_centre(j, s);
  const int64_t unit = int64_t{1} << s;
  int64_t area2 = 0;
  double z0 = 0, dzi = 0, dzj = 0;
  auto edge = [&](int k, int p, int q) {  // edge k goes from corner p to corner q
    const int64_t dx = r.x[q] - r.x[p], dy = r.y[q] - r.y[p];
    const int64_t e = dx * (py - r.y[p]) - dy * (px - r.x[p]);
    a.e[k] = e - ((r.flags >> k) & 1);
    a.di[k] = -dy * unit;
    a.dj[k] = dx * unit;
    area2 += e;
    z0 += static_cast<double>(e) * r.z[k];
    dzi += static_cast<double>(a.di[k]) * r.z[k];
    dzj += static_cast<double>(a.dj[k]) * r.z[k];
  };
  edge(0, 1, 2);
  edge(1, 2, 0);
  edge(2, 0, 1);
  const double inv = 1.0 / static_cast<double>(area2);  // the edge functions sum to 2 area
  a.z = z0 * inv;
  a.dzi = dzi * inv;
  a.dzj = dzj * inv;
  a.m0 = a.mi = a.mj = 0.0;
}

// Gives a floor's sections to its nodes; j is the row its edge functions are at. The edge
// functions at (i0, j_ref) are those of barycentric coordinates times twice the area, which
// is their sum at any point.
void FastColumn::Impl::retire(const Active& a, int j, Worker& w) {
  if (!a.bottom || a.m0 == 0.0) return;
  const SortedTriangle& r = sorted[a.triangle];
  int64_t e_ref[3], area2 = 0;
  for (int k = 0; k < 3; ++k) {
    e_ref[k] = a.e[k] + ((r.flags >> k) & 1) - a.dj[k] * (j - a.j_ref);
    area2 += e_ref[k];
  }
  const double scale = rho_g * grid.cell_area / static_cast<double>(area2);
  for (int k = 0; k < 3; ++k) {
    w.weights[r.vertex[k]] +=
        scale * (static_cast<double>(e_ref[k]) * a.m0 + static_cast<double>(a.di[k]) * a.mi +
                 static_cast<double>(a.dj[k]) * a.mj);
  }
}

// Drops the hits of active entry k on the current row.
void FastColumn::Impl::raster_row(const Active& a, int k, int& lo, int& hi, Worker& w) {
  RowHits& hits = a.bottom ? w.floors : w.ceilings;
  int* count = hits.count.data();
  double* zs = hits.z.data();
  int* index = hits.index.data();
  const size_t stride = hits.stride;
  int first, last;
  if (a.i1 - a.i0 < kScanWidth) {
    // Narrow box: its kScanWidth columns tested without branches, as a bit mask. A centre is
    // covered when its edge functions are all >= 0, i.e. when their bitwise or is not
    // negative; the covered columns of a row are contiguous. Measured against a scan for the
    // span ends (mispredicted exits) and against the divisions below (armadillo 1000^2: boxes
    // ~7 columns wide), and against masks of up to 64 columns (slower on wider boxes).
    const int64_t di0 = a.di[0], di1 = a.di[1], di2 = a.di[2];
    int64_t e0 = a.e[0], e1 = a.e[1], e2 = a.e[2];
    uint64_t mask = 0;
    for (int u = 0; u < kScanWidth; ++u) {
      mask |= (static_cast<uint64_t>(~(e0 | e1 | e2)) >> 63) << u;
      e0 += di0;
      e1 += di1;
      e2 += di2;
    }
    if (mask == 0) return;
    first = a.i0 + lowest_bit(mask);
    last = a.i0 + highest_bit(mask);
  } else {
    // Wide boxes: the span edge by edge, E_k(i) = e[k] + di[k] (i - i0) >= 0.
    first = a.i0;
    last = a.i1;
    for (int q = 0; q < 3 && first <= last; ++q) {
      if (a.di[q] > 0) {
        if (a.e[q] < 0) first = std::max<int64_t>(first, a.i0 - floor_div(a.e[q], a.di[q]));
      } else if (a.di[q] < 0) {
        last = std::min<int64_t>(last, a.i0 + floor_div(a.e[q], -a.di[q]));
      } else if (a.e[q] < 0) {
        last = first - 1;
      }
    }
    if (first > last) return;
  }
  double zi = a.z + a.dzi * (first - a.i0);
  for (int i = first; i <= last; ++i, zi += a.dzi) {
    const int n = count[i]++;
    if (n < kPlanes) {
      zs[n * stride + i] = zi;
      index[n * stride + i] = k;
    } else {
      hits.spill.push_back({i, zi, k});
    }
  }
  lo = std::min(lo, first);
  hi = std::max(hi, last);
}

void FastColumn::Impl::sweep_band(int band, Worker& w) {
  const int ja = band * band_rows, jb = std::min(grid.n, ja + band_rows);
  w.live = 0;
  for (int c = carried_start[band]; c < carried_start[band + 1]; ++c) activate(carried[c], ja, w);
  for (int j = ja; j < jb; ++j) {
    for (int c = row_start[j]; c < row_start[j + 1]; ++c) {
      // Vertices are read at random in memory: ask for them ahead.
      if (c + kPrefetch < static_cast<int>(sorted.size())) {
        for (int v : sorted[c + kPrefetch].vertex) prefetch(&vertices[v]);
      }
      activate(c, j, w);
    }
    int lo = grid.n, hi = -1;
    for (int k = 0; k < w.live;) {
      Active& a = w.active[k];
      if (a.j1 < j) {
        retire(a, j, w);
        a = w.active[--w.live];
        continue;
      }
      raster_row(a, k, lo, hi, w);
      for (int q = 0; q < 3; ++q) a.e[q] += a.dj[q];
      a.z += a.dzj;
      ++k;
    }
    resolve_row(j, lo, hi, w);
  }
  for (int k = 0; k < w.live; ++k) retire(w.active[k], jb, w);
  w.live = 0;
}

void FastColumn::Impl::resolve_row(int j, int lo, int hi, Worker& w) {
  auto add_section = [&](int k, double h, int i) {
    Active& a = w.active[k];
    a.m0 += h;
    a.mi += h * (i - a.i0);
    a.mj += h * (j - a.j_ref);
    w.sum_heights += h;
  };
  RowHits &floors = w.floors, &ceilings = w.ceilings;
  for (int i = lo; i <= hi; ++i) {
    const int nf = floors.count[i], nc = ceilings.count[i];
    if (nf == 1 && nc == 1) {  // the usual column: one section
      floors.count[i] = ceilings.count[i] = 0;
      add_section(floors.index[i], ceilings.z[i] - floors.z[i], i);
      continue;
    }
    if (nf == 0 && nc == 0) continue;
    if (nf != nc) ++w.unmatched;
    // The k-th lowest floor pairs with the k-th lowest ceiling.
    if (nf <= kPlanes && nc <= kPlanes) {
      // A few hits: padded to kPlanes with infinite heights and sorted by a fixed network.
      const double inf = std::numeric_limits<double>::infinity();
      double fz[kPlanes], cz[kPlanes];
      int fk[kPlanes];
      for (int c = 0; c < kPlanes; ++c) {
        const size_t at = static_cast<size_t>(c) * floors.stride + i;
        fz[c] = c < nf ? floors.z[at] : inf;
        fk[c] = floors.index[at];
        cz[c] = c < nc ? ceilings.z[at] : inf;
      }
      sort4(fz, fk);
      sort4(cz, nullptr);
      floors.count[i] = ceilings.count[i] = 0;
      for (int k = 0; k < std::min(nf, nc); ++k) add_section(fk[k], cz[k] - fz[k], i);
      continue;
    }
    for (int kind = 0; kind < 2; ++kind) {
      const int m = std::max(nf, nc);
      if (static_cast<int>(w.column_z[kind].size()) < m) {
        w.column_z[kind].resize(m);
        w.column_index[kind].resize(m);
      }
      (kind == 0 ? floors : ceilings)
          .gather(i, w.column_z[kind].data(), w.column_index[kind].data());
    }
    floors.count[i] = ceilings.count[i] = 0;
    const double *fz = w.column_z[0].data(), *cz = w.column_z[1].data();
    const int* fk = w.column_index[0].data();
    for (int k = 0; k < std::min(nf, nc); ++k) add_section(fk[k], cz[k] - fz[k], i);
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
  // snapped vertices and each triangle's rows.
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
  m.grid = make_grid(box[0], box[1], box[2], box[3], box[4], box[5], n, volume);
  const GridParams& grid = m.grid;
  if (grid.empty) return;
  m.rho_g = rho_g;
  const int s = grid.sub_bits, units = n << s;
  m.vertices.resize(nv);
  parallel([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    for (int v = begin; v < end; ++v) {
      Vec3 p = load_vec3(cavity.xyz, v);
      m.vertices[v] = {snap(dot_rn(p, frame.e1), grid.a0, grid.scale_a, units),
                       snap(dot_rn(p, frame.e2), grid.b0, grid.scale_b, units),
                       dot_rn(p, frame.up) - grid.u0};
    }
  });
  // Step 2 per triangle, in input order: its first row (or none) and flags.
  m.row0.resize(nt);
  m.flags.resize(nt);
  parallel([&](int index) {
    int begin, end;
    slice(nt, index, begin, end);
    for (int t = begin; t < end; ++t) {
      const int* v = cavity.triangles + 3 * t;
      const SnappedVertex &a = m.vertices[v[0]], &b = m.vertices[v[1]], &c = m.vertices[v[2]];
      const int x[3] = {a.x, b.x, c.x}, y[3] = {a.y, b.y, c.y};
      // Most triangles cover no column at coarse grids: a box test first, then the setup.
      const int half = 1 << (s - 1);
      const int xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
      const int ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
      m.row0[t] = -1;
      if (((xmax - half) >> s) < -((half - xmin) >> s) ||
          ((ymax - half) >> s) < -((half - ymin) >> s)) {
        continue;
      }
      SnappedTriangle tri{};
      if (!setup_triangle(x, y, grid.orientation, n, s, &tri) || tri.i0 > tri.i1 ||
          tri.j0 > tri.j1) {
        continue;
      }
      m.row0[t] = tri.j0;
      unsigned f = (tri.bottom ? 8u : 0u) | (tri.corner[1] == 2 ? 16u : 0u);
      for (int k = 0; k < 3; ++k) f |= static_cast<unsigned>(tri.e_min[k]) << k;
      m.flags[t] = f;
    }
  });
  // Triangles with columns by first row (a counting sort).
  m.row_start.assign(n + 1, 0);
  for (int t = 0; t < nt; ++t) {
    if (m.row0[t] >= 0) ++m.row_start[m.row0[t] + 1];
  }
  for (int j = 0; j < n; ++j) m.row_start[j + 1] += m.row_start[j];
  m.sorted.resize(m.row_start[n]);
  {
    std::vector<int> fill(m.row_start.begin(), m.row_start.end() - 1);
    for (int t = 0; t < nt; ++t) {
      if (m.row0[t] < 0) continue;
      const int* v = cavity.triangles + 3 * t;
      const bool flip = m.flags[t] & 16u;
      m.sorted[fill[m.row0[t]]++] = {{v[0], flip ? v[2] : v[1], flip ? v[1] : v[2]},
                                     m.flags[t] & 15u};
    }
  }
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

  // Steps 2-5, band by band.
  std::atomic<int> next_band{0};
  parallel([&](int index) {
    Worker& w = m.workers[index];
    w.floors.resize(n);
    w.ceilings.resize(n);
    w.weights.assign(nv, 0.0);
    w.sum_heights = 0.0;
    w.unmatched = 0;
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
    sum_heights += m.workers[k].sum_heights;
    out.unmatched_columns += m.workers[k].unmatched;
  }
  out.column_volume = grid.cell_area * sum_heights;
}

}  // namespace fluidweight::detail
