// Column method, CPU fast path: the same columns, pairs and weights as column_reference, by row
// sweeps over bands of rows on worker threads.
//
// Each triangle is set up once (snapped corners, edge functions at its first column and their
// steps along a row and a column). A band of rows keeps the triangles that cross the current row
// (an active list, as scanline rasterizers do); each one walks its row span with three integer
// additions a column and drops its hits into a small per-column buffer. The row's columns are
// then resolved: a floor and a ceiling (the usual case) make one section; more hits are sorted
// and paired as in the reference. A section's height goes into three moments of its floor
// triangle (sum h, sum h di, sum h dj); the barycentric coordinates are linear in the column
// indices, so the nodal weights follow from the moments once per triangle at the end.
#include <algorithm>
#include <atomic>

#include "cpu.hpp"
#include "thread_pool.hpp"

namespace fluidweight::detail {
namespace {

constexpr int kSlots = 8;  // hits a column keeps in the row buffer before spilling

// A triangle ready for row sweeps; E_k(i, j) = e0[k] + di[k] (i - i0) + dj[k] (j - j0).
struct SweepTriangle {
  int64_t e0[3], di[3], dj[3], e_min[3];
  int64_t area2;
  double z0, dzi, dzj;  // height at (i0, j0) and its steps
  int i0, i1, j0, j1;
  int vertex[3];        // counter-clockwise corners' vertices
  bool bottom;
  bool valid;           // covers at least the box of one column centre
};

struct RowHit {
  double z;
  int tag;  // triangle index, bitwise-negated for floors
};

struct Active {
  int triangle;
  int64_t e[3];  // edge functions at (i0, current row)
  double z;      // height at (i0, current row)
};

// Buffers of one worker thread, kept between calls.
struct Worker {
  std::vector<int> count;
  std::vector<RowHit> slots;
  std::vector<std::pair<int, RowHit>> spill;
  std::vector<Active> active;
  std::vector<double> moments;  // 3 per triangle
  std::vector<RowHit> floors, ceilings;
  double sum_heights = 0.0;
  long long unmatched = 0;
};

bool by_height(const RowHit& a, const RowHit& b) {
  return a.z < b.z || (a.z == b.z && (a.tag < 0 ? ~a.tag : a.tag) < (b.tag < 0 ? ~b.tag : b.tag));
}

}  // namespace

struct FastColumn::Impl {
  explicit Impl(int threads) : pool(threads), workers(pool.size()) {}

  void sweep_band(const GridParams& grid, int band, Worker& w);
  void resolve_row(int j, int lo, int hi, Worker& w);
  void add_section(int triangle, double h, int i, int j, Worker& w) {
    const SweepTriangle& t = tris[triangle];
    double* m = &w.moments[3 * static_cast<size_t>(triangle)];
    m[0] += h;
    m[1] += h * (i - t.i0);
    m[2] += h * (j - t.j0);
    w.sum_heights += h;
  }

  ThreadPool pool;
  std::vector<Worker> workers;
  std::vector<int> sx, sy;
  std::vector<double> z;
  std::vector<SweepTriangle> tris;
  std::vector<int> by_row, band_start, band_list;
  int band_rows = 1, num_bands = 1;
};

FastColumn::FastColumn(int threads) : impl_(std::make_unique<Impl>(threads)) {}
FastColumn::~FastColumn() = default;

void FastColumn::Impl::sweep_band(const GridParams& grid, int band, Worker& w) {
  const int n = grid.n;
  const int ja = band * band_rows, jb = std::min(n, ja + band_rows);
  w.active.clear();
  int next = band_start[band];
  const int end = band_start[band + 1];
  for (int j = ja; j < jb; ++j) {
    while (next < end && tris[band_list[next]].j0 <= j) {
      int t = band_list[next++];
      const SweepTriangle& s = tris[t];
      if (s.j1 < j) continue;
      int64_t dj = j - s.j0;
      w.active.push_back(Active{t, {s.e0[0] + s.dj[0] * dj, s.e0[1] + s.dj[1] * dj,
                                    s.e0[2] + s.dj[2] * dj},
                                s.z0 + s.dzj * dj});
    }
    int lo = n, hi = -1;
    for (size_t a = 0; a < w.active.size();) {
      Active& act = w.active[a];
      const SweepTriangle& s = tris[act.triangle];
      if (s.j1 < j) {
        act = w.active.back();
        w.active.pop_back();
        continue;
      }
      int64_t e0 = act.e[0], e1 = act.e[1], e2 = act.e[2];
      const int tag = s.bottom ? ~act.triangle : act.triangle;
      bool inside = false;
      for (int i = s.i0; i <= s.i1; ++i, e0 += s.di[0], e1 += s.di[1], e2 += s.di[2]) {
        if (e0 >= s.e_min[0] && e1 >= s.e_min[1] && e2 >= s.e_min[2]) {
          inside = true;
          RowHit hit{act.z + s.dzi * (i - s.i0), tag};
          int c = w.count[i]++;
          if (c < kSlots) {
            w.slots[static_cast<size_t>(i) * kSlots + c] = hit;
          } else {
            w.spill.emplace_back(i, hit);
          }
          lo = std::min(lo, i);
          hi = std::max(hi, i);
        } else if (inside) {
          break;  // a row crosses a triangle in one span
        }
      }
      for (int k = 0; k < 3; ++k) act.e[k] += s.dj[k];
      act.z += s.dzj;
      ++a;
    }
    resolve_row(j, lo, hi, w);
  }
}

void FastColumn::Impl::resolve_row(int j, int lo, int hi, Worker& w) {
  for (int i = lo; i <= hi; ++i) {
    int c = w.count[i];
    if (c == 0) continue;
    w.count[i] = 0;
    const RowHit* hits = &w.slots[static_cast<size_t>(i) * kSlots];
    if (c == 2 && ((hits[0].tag < 0) != (hits[1].tag < 0))) {
      const RowHit& floor = hits[0].tag < 0 ? hits[0] : hits[1];
      const RowHit& ceiling = hits[0].tag < 0 ? hits[1] : hits[0];
      add_section(~floor.tag, ceiling.z - floor.z, i, j, w);
      continue;
    }
    // Several sections (or an odd column): sort floors and ceilings, pair the k-th of each.
    w.floors.clear();
    w.ceilings.clear();
    for (int k = 0; k < std::min(c, kSlots); ++k) {
      (hits[k].tag < 0 ? w.floors : w.ceilings).push_back(hits[k]);
    }
    if (c > kSlots) {
      for (const auto& [col, hit] : w.spill) {
        if (col == i) (hit.tag < 0 ? w.floors : w.ceilings).push_back(hit);
      }
    }
    std::sort(w.floors.begin(), w.floors.end(), by_height);
    std::sort(w.ceilings.begin(), w.ceilings.end(), by_height);
    if (w.floors.size() != w.ceilings.size()) ++w.unmatched;
    for (size_t r = 0; r < std::min(w.floors.size(), w.ceilings.size()); ++r) {
      add_section(~w.floors[r].tag, w.ceilings[r].z - w.floors[r].z, i, j, w);
    }
  }
  w.spill.clear();
}

void FastColumn::run(const CavityView& cavity, const Frame& frame, const GridParams& grid,
                     double rho_g, CavityOutput& out) {
  Impl& m = *impl_;
  out.values.assign(cavity.num_vertices, 0.0);
  out.column_volume = 0.0;
  out.unmatched_columns = 0;
  if (grid.empty) return;
  const int n = grid.n, s = grid.sub_bits, units = n << s;
  const int64_t column_units = int64_t{1} << s;
  const int nv = cavity.num_vertices, nt = cavity.num_triangles;
  const int threads = m.pool.size();
  m.sx.resize(nv);
  m.sy.resize(nv);
  m.z.resize(nv);
  m.tris.resize(nt);

  // Steps 1-2 for vertices, then triangles, in slices over the threads.
  auto slice = [threads](int count, int index, int& begin, int& end) {
    begin = static_cast<int>(static_cast<long long>(count) * index / threads);
    end = static_cast<int>(static_cast<long long>(count) * (index + 1) / threads);
  };
  m.pool.run([&](int index) {
    int begin, end;
    slice(nv, index, begin, end);
    for (int v = begin; v < end; ++v) {
      Vec3 p = load_vec3(cavity.xyz, v);
      m.sx[v] = snap(dot_rn(p, frame.e1), grid.a0, grid.scale_a, units);
      m.sy[v] = snap(dot_rn(p, frame.e2), grid.b0, grid.scale_b, units);
      m.z[v] = dot_rn(p, frame.up) - grid.u0;
    }
  });
  m.pool.run([&](int index) {
    int begin, end;
    slice(nt, index, begin, end);
    for (int t = begin; t < end; ++t) {
      const int* v = cavity.triangles + 3 * t;
      int sx[3] = {m.sx[v[0]], m.sx[v[1]], m.sx[v[2]]};
      int sy[3] = {m.sy[v[0]], m.sy[v[1]], m.sy[v[2]]};
      SnappedTriangle tri;
      SweepTriangle& st = m.tris[t];
      st.valid = setup_triangle(sx, sy, grid.orientation, n, s, &tri) && tri.i0 <= tri.i1 &&
                 tri.j0 <= tri.j1;
      if (!st.valid) continue;
      int64_t e[3];
      covers(tri, column_centre(tri.i0, s), column_centre(tri.j0, s), e);
      double z0 = 0, dzi = 0, dzj = 0;
      for (int k = 0; k < 3; ++k) {
        int a = (k + 1) % 3, b = (k + 2) % 3;
        st.e0[k] = e[k];
        st.di[k] = -static_cast<int64_t>(tri.y[b] - tri.y[a]) * column_units;
        st.dj[k] = static_cast<int64_t>(tri.x[b] - tri.x[a]) * column_units;
        st.e_min[k] = tri.e_min[k];
        st.vertex[k] = v[tri.corner[k]];
        double zk = m.z[st.vertex[k]];
        z0 += static_cast<double>(st.e0[k]) * zk;
        dzi += static_cast<double>(st.di[k]) * zk;
        dzj += static_cast<double>(st.dj[k]) * zk;
      }
      double inv = 1.0 / static_cast<double>(tri.area2);
      st.z0 = z0 * inv;
      st.dzi = dzi * inv;
      st.dzj = dzj * inv;
      st.area2 = tri.area2;
      st.i0 = tri.i0;
      st.i1 = tri.i1;
      st.j0 = tri.j0;
      st.j1 = tri.j1;
      st.bottom = tri.bottom;
    }
  });

  // Triangles by first row (counting sort), then into bands of rows, each band's list in
  // first-row order.
  std::vector<int> first(n + 1, 0);
  for (int t = 0; t < nt; ++t) {
    if (m.tris[t].valid) ++first[m.tris[t].j0 + 1];
  }
  for (int j = 0; j < n; ++j) first[j + 1] += first[j];
  m.by_row.resize(first[n]);
  for (int t = 0; t < nt; ++t) {
    if (m.tris[t].valid) m.by_row[first[m.tris[t].j0]++] = t;
  }
  m.num_bands = threads == 1 ? 1 : std::min(n, 8 * threads);
  m.band_rows = (n + m.num_bands - 1) / m.num_bands;
  m.num_bands = (n + m.band_rows - 1) / m.band_rows;
  m.band_start.assign(m.num_bands + 1, 0);
  for (int t : m.by_row) {
    for (int b = m.tris[t].j0 / m.band_rows; b <= m.tris[t].j1 / m.band_rows; ++b) {
      ++m.band_start[b + 1];
    }
  }
  for (int b = 0; b < m.num_bands; ++b) m.band_start[b + 1] += m.band_start[b];
  m.band_list.resize(m.band_start[m.num_bands]);
  {
    std::vector<int> fill(m.band_start.begin(), m.band_start.end() - 1);
    for (int t : m.by_row) {
      for (int b = m.tris[t].j0 / m.band_rows; b <= m.tris[t].j1 / m.band_rows; ++b) {
        m.band_list[fill[b]++] = t;
      }
    }
  }

  // Steps 3-5, band by band.
  std::atomic<int> next_band{0};
  m.pool.run([&](int index) {
    Worker& w = m.workers[index];
    w.count.assign(n, 0);
    w.slots.resize(static_cast<size_t>(n) * kSlots);
    w.moments.assign(3 * static_cast<size_t>(nt), 0.0);
    w.sum_heights = 0.0;
    w.unmatched = 0;
    for (int b; (b = next_band++) < m.num_bands;) m.sweep_band(grid, b, w);
  });

  // Nodal weights from the floor triangles' moments.
  std::vector<double> weights(3 * static_cast<size_t>(nt), 0.0);
  const double scale = rho_g * grid.cell_area;
  m.pool.run([&](int index) {
    int begin, end;
    slice(nt, index, begin, end);
    for (int t = begin; t < end; ++t) {
      const SweepTriangle& st = m.tris[t];
      if (!st.valid || !st.bottom) continue;
      double s0 = 0, si = 0, sj = 0;
      for (const Worker& w : m.workers) {
        s0 += w.moments[3 * t];
        si += w.moments[3 * t + 1];
        sj += w.moments[3 * t + 2];
      }
      double c = scale / static_cast<double>(st.area2);
      for (int k = 0; k < 3; ++k) {
        weights[3 * t + k] = c * (static_cast<double>(st.e0[k]) * s0 +
                                  static_cast<double>(st.di[k]) * si +
                                  static_cast<double>(st.dj[k]) * sj);
      }
    }
  });
  for (int t = 0; t < nt; ++t) {
    const SweepTriangle& st = m.tris[t];
    if (!st.valid || !st.bottom) continue;
    for (int k = 0; k < 3; ++k) out.values[st.vertex[k]] += weights[3 * t + k];
  }
  double sum_heights = 0.0;
  for (const Worker& w : m.workers) {
    sum_heights += w.sum_heights;
    out.unmatched_columns += w.unmatched;
  }
  out.column_volume = grid.cell_area * sum_heights;
}

}  // namespace fluidweight::detail
