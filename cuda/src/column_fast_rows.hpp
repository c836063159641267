// Column method, CPU fast path: Steps 3-5 on a ring of rows (used by column_fast.cpp only).
//
// A triangle is rasterized a block of rows at a time (all its rows when it spans no more rows
// than the ring holds), in 8-column chunks whose covered columns come out as a bit mask of the
// signs of the three edge functions. Its hits go into the ring row of each covered row: a count
// per column and kind (floors, ceilings) and kPlanes planes of heights (and, for floors, of
// floor records), so that the c-th hit of column i is at [c][i]; further hits spill into a list.
// A row is resolved once no triangle can still reach it (every triangle whose first row is at
// or above it has been rasterized): its columns' floors and ceilings are sorted (a sorting
// network over the planes) and paired, and each section's
// height goes into three moments of its floor record. Barycentric coordinates are linear in
// the column indices, so the floor's nodal weights follow from the moments once, at the end.
//
// This header: the ring, and the portable kernels. column_fast_avx512.hpp has their AVX-512
// forms, chosen at run time where the processor has them; both cover the same columns (integer
// edge functions) and give the same sections (heights differ in rounding only).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

namespace fluidweight::detail::rows {

constexpr int kPlanes = 4;  // hits of each kind a column keeps in its planes; more spill
constexpr int kChunk = 8;   // columns tested together
constexpr int kWide = 24;   // boxes this wide or wider find their span by division first

// A triangle being rasterized. E_k(i, row) = e[k] + di[k] (i - i0) with the fill-rule
// thresholds folded into e, so a centre is covered when the three are >= 0.
struct Raster {
  int64_t e[3], di[3], dj[3];
  double z, dzi, dzj;  // height at (i0, row) and its steps
  int i0, i1, j1;      // box columns and last row
  int row;             // the row e and z are at
  int floor;           // its floor record, or -1 for a ceiling
};

// A floor's sections: sum h, sum h i, sum h j (column indices from the grid's corner, so that
// a section's update needs nothing of its floor but the record: one 32-byte add with AVX-512);
// the fourth is padding.
struct alignas(32) FloorMoments {
  double m0, mi, mj, pad;
};

struct Spilled {
  int column, floor;
  double z;
};

// Vectors whose data starts on a cache line, so that aligned chunks of columns do not split
// lines.
template <class T>
struct LineAllocator {
  using value_type = T;
  LineAllocator() = default;
  template <class U>
  LineAllocator(const LineAllocator<U>&) {}
  T* allocate(size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64)));
  }
  void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(64)); }
  bool operator==(const LineAllocator&) const { return true; }
  bool operator!=(const LineAllocator&) const { return false; }
};
template <class T>
using LineVector = std::vector<T, LineAllocator<T>>;

// The rows not yet resolved, in `rows` slots (a power of two; row j in slot j & (rows - 1)).
struct RowRing {
  int rows = 0, width = 0;       // width: columns, padded for whole chunks
  LineVector<uint8_t> count[2];  // [slot width + i]; kind 0 floors, 1 ceilings; saturates
  LineVector<double> z[2];       // [(slot kPlanes + c) width + i]
  LineVector<int> floor;         // floor records, laid out as z[0]
  std::vector<int> lo, hi;       // columns that may hold hits, per slot (not kept by AVX-512)
  std::vector<std::vector<Spilled>> spill[2];

  void resize(int num_rows, int n) {
    rows = num_rows;
    width = (n + 2 * kChunk - 1) / kChunk * kChunk;
    for (int kind = 0; kind < 2; ++kind) {
      count[kind].assign(static_cast<size_t>(rows) * width, 0);
      z[kind].resize(static_cast<size_t>(rows) * kPlanes * width);
      spill[kind].resize(rows);
      for (auto& s : spill[kind]) s.clear();
    }
    floor.resize(static_cast<size_t>(rows) * kPlanes * width);
    lo.assign(rows, std::numeric_limits<int>::max());
    hi.assign(rows, -1);
  }
};

// The ring's arrays of one slot, for one kind of hits.
struct SlotView {
  uint8_t* count;
  double* z;
  int* floor;
};

// What resolving rows adds up.
struct RowTotals {
  double sum_heights = 0.0;
  long long unmatched = 0;
};

inline int lowest_bit(uint64_t m) {
#if defined(__GNUC__)
  return __builtin_ctzll(m);
#else
  int b = 0;
  while (!((m >> b) & 1)) ++b;
  return b;
#endif
}
inline int highest_bit(uint64_t m) {
#if defined(__GNUC__)
  return 63 - __builtin_clzll(m);
#else
  int b = 63;
  while (!((m >> b) & 1)) --b;
  return b;
#endif
}

// Floor division for the span bounds (b > 0).
inline int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// The covered columns [first, last] of a wide box on the raster's row, edge by edge.
inline bool wide_span(const Raster& r, int& first, int& last) {
  int64_t f = r.i0, l = r.i1;
  for (int q = 0; q < 3 && f <= l; ++q) {
    if (r.di[q] > 0) {
      if (r.e[q] < 0) f = std::max<int64_t>(f, r.i0 - floor_div(r.e[q], r.di[q]));
    } else if (r.di[q] < 0) {
      l = std::min<int64_t>(l, r.i0 + floor_div(r.e[q], -r.di[q]));
    } else if (r.e[q] < 0) {
      l = f - 1;
    }
  }
  first = static_cast<int>(f);
  last = static_cast<int>(l);
  return f <= l;
}

inline void add_section(FloorMoments& f, double h, int i, int j) {
  f.m0 += h;
  f.mi += h * i;
  f.mj += h * j;
}

// Portable raster: `rows` rows from r.row, advancing r. Boxes narrower than 8 columns test all
// 8 (a loop of fixed length, without branches), wider ones divide. The raster's fields are
// copied into locals: stores through the byte counts could alias them.
inline void raster_portable(Raster& r, int rows, RowRing& ring) {
  const int kind = r.floor < 0 ? 1 : 0;
  const size_t w = ring.width;
  const int64_t di0 = r.di[0], di1 = r.di[1], di2 = r.di[2];
  const int i0 = r.i0, floor = r.floor;
  const double dzi = r.dzi;
  const bool narrow = r.i1 - r.i0 < kChunk;
  for (int q = 0; q < rows; ++q, ++r.row) {
    int first = 0, last = -1;
    if (narrow) {
      uint64_t mask = 0;
      int64_t e0 = r.e[0], e1 = r.e[1], e2 = r.e[2];
      for (int u = 0; u < kChunk; ++u, e0 += di0, e1 += di1, e2 += di2) {
        mask |= (static_cast<uint64_t>(~(e0 | e1 | e2)) >> 63) << u;
      }
      if (mask) {
        first = i0 + lowest_bit(mask);
        last = i0 + highest_bit(mask);
      }
    } else if (!wide_span(r, first, last)) {
      last = first - 1;
    }
    if (first <= last) {
      const int slot = r.row & (ring.rows - 1);
      uint8_t* count = ring.count[kind].data() + slot * w;
      double* zs = ring.z[kind].data() + slot * kPlanes * w;
      int* fl = ring.floor.data() + slot * kPlanes * w;
      const double z = r.z;
      for (int i = first; i <= last; ++i) {
        const double zi = z + dzi * (i - i0);
        const int c = count[i];
        if (c < kPlanes) {
          zs[c * w + i] = zi;
          if (kind == 0) fl[c * w + i] = floor;
        } else {
          ring.spill[kind][slot].push_back({i, floor, zi});
        }
        count[i] = static_cast<uint8_t>(c + (c < 255));
      }
      ring.lo[slot] = std::min(ring.lo[slot], first);
      ring.hi[slot] = std::max(ring.hi[slot], last);
    }
    for (int k = 0; k < 3; ++k) r.e[k] += r.dj[k];
    r.z += r.dzj;
  }
}

// Sorts four heights (and their floor records, when given) by a sorting network:
// compare-exchanges without branches, whose outcome depends on the data.
static_assert(kPlanes == 4, "sort4 sorts a column's planes");
inline void sort4(double* z, int* floor) {
  auto exchange = [&](int a, int b) {
    const bool swap = z[b] < z[a];
    const double za = z[a], zb = z[b];
    z[a] = swap ? zb : za;
    z[b] = swap ? za : zb;
    if (floor) {
      const int fa = floor[a], fb = floor[b];
      floor[a] = swap ? fb : fa;
      floor[b] = swap ? fa : fb;
    }
  };
  exchange(0, 1);
  exchange(2, 3);
  exchange(0, 2);
  exchange(1, 3);
  exchange(1, 2);
}

// Column i of a slot (planes and spilled hits, `at` the next spilled entry of each kind in
// column order): its floors and ceilings sorted, the k-th lowest of each paired.
struct ColumnScratch {
  std::vector<double> z[2];
  std::vector<int> floor;
};
inline void resolve_column(int slot, int i, int j, RowRing& ring, size_t at[2],
                           FloorMoments* moments, ColumnScratch& s, RowTotals& totals) {
  const size_t w = ring.width;
  int n[2];
  for (int kind = 0; kind < 2; ++kind) {
    uint8_t& count = ring.count[kind][slot * w + i];
    const int planes = std::min<int>(count, kPlanes);
    count = 0;
    const std::vector<Spilled>& spill = ring.spill[kind][slot];
    size_t& a = at[kind];
    while (a < spill.size() && spill[a].column < i) ++a;
    size_t b = a;
    while (b < spill.size() && spill[b].column == i) ++b;
    n[kind] = planes + static_cast<int>(b - a);
    if (static_cast<int>(s.z[kind].size()) < n[kind]) {
      s.z[kind].resize(n[kind]);
      s.floor.resize(std::max<size_t>(s.floor.size(), n[kind]));
    }
    double* z = s.z[kind].data();
    int* f = s.floor.data();
    for (int c = 0; c < planes; ++c) {
      z[c] = ring.z[kind][(slot * kPlanes + c) * w + i];
      if (kind == 0) f[c] = ring.floor[(slot * kPlanes + c) * w + i];
    }
    for (int c = planes; a < b; ++a, ++c) {
      z[c] = spill[a].z;
      if (kind == 0) f[c] = spill[a].floor;
    }
    // Insertion sort: a column has a few hits.
    for (int c = 1; c < n[kind]; ++c) {
      const double zc = z[c];
      const int fc = kind == 0 ? f[c] : 0;
      int d = c;
      for (; d > 0 && z[d - 1] > zc; --d) {
        z[d] = z[d - 1];
        if (kind == 0) f[d] = f[d - 1];
      }
      z[d] = zc;
      if (kind == 0) f[d] = fc;
    }
  }
  if (n[0] != n[1]) ++totals.unmatched;
  for (int k = 0; k < std::min(n[0], n[1]); ++k) {
    const double h = s.z[1][k] - s.z[0][k];
    add_section(moments[s.floor[k]], h, i, j);
    totals.sum_heights += h;
  }
}

// Spilled hits in column order, so that columns can find theirs in one pass.
inline void sort_spill(RowRing& ring, int slot) {
  for (int kind = 0; kind < 2; ++kind) {
    std::vector<Spilled>& s = ring.spill[kind][slot];
    if (s.size() > 1) {
      std::stable_sort(s.begin(), s.end(),
                       [](const Spilled& a, const Spilled& b) { return a.column < b.column; });
    }
  }
}

// Column i of a slot resolved alone (the portable resolution's loop body; `at` as for
// resolve_column).
inline void resolve_one(int slot, int i, int j, RowRing& ring, size_t at[2], FloorMoments* moments,
                        ColumnScratch& s, RowTotals& totals) {
  const size_t w = ring.width;
  uint8_t& fcount = ring.count[0][slot * w + i];
  uint8_t& ccount = ring.count[1][slot * w + i];
  const int nf = fcount, nc = ccount;
  const double* fz = ring.z[0].data() + slot * kPlanes * w + i;
  const double* cz = ring.z[1].data() + slot * kPlanes * w + i;
  const int* fl = ring.floor.data() + slot * kPlanes * w + i;
  if (nf == 1 && nc == 1) {  // the usual column: one section
    fcount = ccount = 0;
    const double h = cz[0] - fz[0];
    add_section(moments[fl[0]], h, i, j);
    totals.sum_heights += h;
  } else if (nf <= kPlanes && nc <= kPlanes && (nf | nc)) {
    // A few hits: padded to kPlanes with infinite heights and sorted by a fixed network.
    fcount = ccount = 0;
    const double inf = std::numeric_limits<double>::infinity();
    double a[kPlanes], b[kPlanes];
    int f[kPlanes];
    for (int c = 0; c < kPlanes; ++c) {
      a[c] = c < nf ? fz[c * w] : inf;
      f[c] = fl[c * w];
      b[c] = c < nc ? cz[c * w] : inf;
    }
    sort4(a, f);
    sort4(b, nullptr);
    if (nf != nc) ++totals.unmatched;
    for (int k = 0; k < std::min(nf, nc); ++k) {
      add_section(moments[f[k]], b[k] - a[k], i, j);
      totals.sum_heights += b[k] - a[k];
    }
  } else if (nf | nc) {
    resolve_column(slot, i, j, ring, at, moments, s, totals);
  }
}

// Takes row j's columns [lo, hi] off the ring (false when it has none), its spilled hits
// sorted: the start of every resolution kernel.
inline bool take_row(int j, RowRing& ring, int& slot, int& lo, int& hi) {
  slot = j & (ring.rows - 1);
  lo = ring.lo[slot];
  hi = ring.hi[slot];
  ring.lo[slot] = std::numeric_limits<int>::max();
  ring.hi[slot] = -1;
  if (lo > hi) return false;
  sort_spill(ring, slot);
  return true;
}

// Portable resolution of row j.
inline void resolve_portable(int j, RowRing& ring, FloorMoments* moments, ColumnScratch& s,
                             RowTotals& totals) {
  int slot, lo, hi;
  if (!take_row(j, ring, slot, lo, hi)) return;
  size_t at[2] = {0, 0};
  for (int i = lo; i <= hi; ++i) resolve_one(slot, i, j, ring, at, moments, s, totals);
  ring.spill[0][slot].clear();
  ring.spill[1][slot].clear();
}

}  // namespace fluidweight::detail::rows
