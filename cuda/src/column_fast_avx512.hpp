// Column method, CPU fast path: the AVX-512 forms of the kernels of column_fast_rows.hpp, and
// of Step 2, the set-up of a row's triangles and the signed volume, 8 triangles or columns at a
// time (used by column_fast.cpp only, which takes them where the processor has AVX-512).
#pragma once

#include "column_fast_rows.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && \
    !defined(FLUIDWEIGHT_NO_AVX512)
#define FLUIDWEIGHT_AVX512 1
#include <immintrin.h>

namespace fluidweight::detail::rows {

// GCC 12 warns inside its own intrinsics (several start from an undefined vector).
#if !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#define FW_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512dq,bmi,bmi2,popcnt")))

inline bool avx512_available() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
}

// Spilled hits of a chunk (lanes in `over`), kept out of line: rare.
__attribute__((noinline)) inline void spill_chunk(std::vector<Spilled>& spill, unsigned over,
                                                  int col, int floor, const double* z) {
  for (; over; over &= over - 1) {
    const int u = lowest_bit(over);
    spill.push_back({col + u, floor, z[u]});
  }
}

// Hits of the chunk of columns col .. col + 7 (covered where m is set) into the planes of one
// slot: lane u to the plane of its column's count, or to the spill list. Planes 0 and 1 are
// written without a branch (a second hit of a kind is common: non-convex meshes).
template <bool kFloor>
FW_AVX512 inline void write_chunk(const SlotView& v, size_t w, int col, __mmask8 m, __m512d z,
                                  __m256i floor_index, std::vector<Spilled>& spill, int floor,
                                  int column_offset = 0) {
  const __m128i c = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(v.count + col));
  const __mmask8 k0 = static_cast<__mmask8>(_mm_mask_cmpeq_epi8_mask(m, c, _mm_setzero_si128()));
  const __mmask8 k1 = static_cast<__mmask8>(_mm_mask_cmpeq_epi8_mask(m, c, _mm_set1_epi8(1)));
  _mm512_mask_storeu_pd(v.z + col, k0, z);
  _mm512_mask_storeu_pd(v.z + w + col, k1, z);
  if (kFloor) {
    _mm256_mask_storeu_epi32(v.floor + col, k0, floor_index);
    _mm256_mask_storeu_epi32(v.floor + w + col, k1, floor_index);
  }
  if (_mm_mask_cmpgt_epu8_mask(m, c, _mm_set1_epi8(1))) {
    for (int p = 2; p < kPlanes; ++p) {
      const __mmask8 k = static_cast<__mmask8>(_mm_mask_cmpeq_epi8_mask(m, c, _mm_set1_epi8(p)));
      _mm512_mask_storeu_pd(v.z + p * w + col, k, z);
      if (kFloor) _mm256_mask_storeu_epi32(v.floor + p * w + col, k, floor_index);
    }
    const unsigned over = _mm_mask_cmpge_epu8_mask(m, c, _mm_set1_epi8(kPlanes)) & 0xFFu;
    if (over) {
      alignas(64) double zl[kChunk];
      _mm512_store_pd(zl, z);
      spill_chunk(spill, over, column_offset + col, floor, zl);
    }
  }
  _mm_storel_epi64(reinterpret_cast<__m128i*>(v.count + col),
                   _mm_mask_adds_epu8(c, m, c, _mm_set1_epi8(1)));
}

// Rasterizes `rows` rows of r from r.row (kFloor: r is a floor), advancing r: the box's chunks
// of 8 columns from i0 (a number fixed for the triangle, so that the loop is predicted), each
// tested in registers, the covered lanes written with masks. Boxes of kWide columns or more
// find their span by division first. The raster's fields are copied into locals: stores
// through the byte counts could alias them.
template <bool kFloor>
FW_AVX512 void raster_avx512_kind(Raster& r, int rows, RowRing& ring) {
  constexpr int kind = kFloor ? 0 : 1;
  const size_t w = ring.width;
  const int mask_rows = ring.rows - 1;
  const __m512i iota = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
  const int64_t di0 = r.di[0], di1 = r.di[1], di2 = r.di[2];
  const int64_t dj0 = r.dj[0], dj1 = r.dj[1], dj2 = r.dj[2];
  const __m512i lane0 = _mm512_mullo_epi64(_mm512_set1_epi64(di0), iota);
  const __m512i lane1 = _mm512_mullo_epi64(_mm512_set1_epi64(di1), iota);
  const __m512i lane2 = _mm512_mullo_epi64(_mm512_set1_epi64(di2), iota);
  const __m512i step0 = _mm512_set1_epi64(kChunk * di0);
  const __m512i step1 = _mm512_set1_epi64(kChunk * di1);
  const __m512i step2 = _mm512_set1_epi64(kChunk * di2);
  const double dzi = r.dzi, dzj = r.dzj;
  const __m512d lane_z = _mm512_mul_pd(_mm512_set1_pd(dzi), _mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i floor_index = _mm256_set1_epi32(r.floor);
  const int i0 = r.i0, i1 = r.i1, floor = r.floor;
  const bool wide = i1 - i0 >= kWide;
  uint8_t* const count = ring.count[kind].data();
  double* const zs = ring.z[kind].data();
  int* const fl = ring.floor.data();
  int64_t e0 = r.e[0], e1 = r.e[1], e2 = r.e[2];
  double z = r.z;
  int row = r.row;
  for (int q = 0; q < rows; ++q, ++row, e0 += dj0, e1 += dj1, e2 += dj2, z += dzj) {
    const int slot = row & mask_rows;
    const SlotView v{count + slot * w, zs + slot * kPlanes * w, fl + slot * kPlanes * w};
    std::vector<Spilled>& spill = ring.spill[kind][slot];
    int first = i0, last = i1;
    int64_t f0 = e0, f1 = e1, f2 = e2;
    if (wide) {
      Raster at = r;
      at.e[0] = e0;
      at.e[1] = e1;
      at.e[2] = e2;
      if (!wide_span(at, first, last)) continue;
      f0 += di0 * (first - i0);
      f1 += di1 * (first - i0);
      f2 += di2 * (first - i0);
    }
    __m512i v0 = _mm512_add_epi64(_mm512_set1_epi64(f0), lane0);
    __m512i v1 = _mm512_add_epi64(_mm512_set1_epi64(f1), lane1);
    __m512i v2 = _mm512_add_epi64(_mm512_set1_epi64(f2), lane2);
    for (int col = first; col <= last; col += kChunk) {
      const __mmask8 m = static_cast<__mmask8>(
          ~_mm512_movepi64_mask(_mm512_or_si512(_mm512_or_si512(v0, v1), v2)));
      // Heights from the box's first column by one product (no sums drifting along a row).
      const __m512d zv = _mm512_add_pd(_mm512_set1_pd(z + dzi * (col - i0)), lane_z);
      write_chunk<kFloor>(v, w, col, m, zv, floor_index, spill, floor);
      v0 = _mm512_add_epi64(v0, step0);
      v1 = _mm512_add_epi64(v1, step1);
      v2 = _mm512_add_epi64(v2, step2);
    }
  }
  r.e[0] = e0;
  r.e[1] = e1;
  r.e[2] = e2;
  r.z = z;
  r.row = row;
}

constexpr int kAhead = 32;  // triangles whose vertices are asked for ahead in the passes below

// Step 2 of triangles [begin, end) (input order, `triangle` 3 vertex indices each), 8 at a
// time: as the portable loop in column_fast.cpp, the first row of each triangle's box, or -1
// when it covers no column, and its flags (fill-rule thresholds, floor, corners swapped), and
// six times their signed volume into `volume6`. `vertex` points to 32-byte records: snapped x
// and y, then the frame coordinates a, b, u (doubles, relative to the box's corner). Returns
// the most rows of a box.
FW_AVX512 inline int step2_avx512(const int* triangle, int begin, int end, const int* vertex, int s,
                                  int orientation, int* row0, unsigned* flags, double& volume6) {
  __m512d sum = _mm512_setzero_pd();
  const __m256i zero = _mm256_setzero_si256();
  const __m256i one = _mm256_set1_epi32(1);
  const __m256i half = _mm256_set1_epi32(1 << (s - 1));
  const __m128i shift = _mm_cvtsi32_si128(s);
  __m256i tall = one;
  for (int t = begin; t < end; t += kChunk) {
    for (int u = 3 * (t + kAhead); u < 3 * std::min(end, t + kAhead + kChunk); ++u) {
      __builtin_prefetch(vertex + 8 * triangle[u]);
    }
    const int lanes = std::min(kChunk, end - t);
    const __mmask8 live = static_cast<__mmask8>((1u << lanes) - 1);
    // The last chunk's missing triangles repeat its first, so that every load is valid.
    const int* tri = triangle + 3 * t;
    int padded[3 * kChunk];
    if (lanes < kChunk) {
      for (int u = 0; u < 3 * kChunk; ++u) padded[u] = tri[u < 3 * lanes ? u : u % 3];
      tri = padded;
    }
    // Each corner's 8 records loaded whole (a gather per field cost more than the loads'
    // misses) and transposed: (x y, a, b, u) of lanes 0-3 and 4-7, then the halves joined.
    __m256i x[3], y[3];
    __m512d p[3][3];  // p[corner][axis]
    for (int k = 0; k < 3; ++k) {
      __m512i two[4];
      for (int h = 0; h < 4; ++h) {
        const int* r0 = vertex + 8 * tri[3 * (2 * h) + k];
        const int* r1 = vertex + 8 * tri[3 * (2 * h + 1) + k];
        two[h] = _mm512_inserti64x4(
            _mm512_castsi256_si512(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(r0))),
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(r1)), 1);
      }
      const __m512i even = _mm512_setr_epi64(0, 4, 8, 12, 1, 5, 9, 13);
      const __m512i odd = _mm512_setr_epi64(2, 6, 10, 14, 3, 7, 11, 15);
      const __m512i lo0 = _mm512_permutex2var_epi64(two[0], even, two[1]);  // xy 0-3, a 0-3
      const __m512i lo1 = _mm512_permutex2var_epi64(two[0], odd, two[1]);   // b 0-3, u 0-3
      const __m512i hi0 = _mm512_permutex2var_epi64(two[2], even, two[3]);
      const __m512i hi1 = _mm512_permutex2var_epi64(two[2], odd, two[3]);
      const __m512i xy = _mm512_shuffle_i64x2(lo0, hi0, 0x44);
      x[k] = _mm512_cvtepi64_epi32(xy);
      y[k] = _mm512_cvtepi64_epi32(_mm512_srli_epi64(xy, 32));
      p[k][0] = _mm512_castsi512_pd(_mm512_shuffle_i64x2(lo0, hi0, 0xEE));
      p[k][1] = _mm512_castsi512_pd(_mm512_shuffle_i64x2(lo1, hi1, 0x44));
      p[k][2] = _mm512_castsi512_pd(_mm512_shuffle_i64x2(lo1, hi1, 0xEE));
    }
    {
      const __m512d(&a)[3] = p[0];
      const __m512d(&b)[3] = p[1];
      const __m512d(&c)[3] = p[2];
      // a.(b x c), of live lanes only.
      const __m512d t0 =
          _mm512_mul_pd(a[0], _mm512_sub_pd(_mm512_mul_pd(b[1], c[2]), _mm512_mul_pd(b[2], c[1])));
      const __m512d t1 =
          _mm512_mul_pd(a[1], _mm512_sub_pd(_mm512_mul_pd(b[2], c[0]), _mm512_mul_pd(b[0], c[2])));
      const __m512d t2 =
          _mm512_mul_pd(a[2], _mm512_sub_pd(_mm512_mul_pd(b[0], c[1]), _mm512_mul_pd(b[1], c[0])));
      sum = _mm512_mask_add_pd(sum, live, sum, _mm512_add_pd(_mm512_add_pd(t0, t1), t2));
    }
    const __m256i xmin = _mm256_min_epi32(_mm256_min_epi32(x[0], x[1]), x[2]);
    const __m256i xmax = _mm256_max_epi32(_mm256_max_epi32(x[0], x[1]), x[2]);
    const __m256i ymin = _mm256_min_epi32(_mm256_min_epi32(y[0], y[1]), y[2]);
    const __m256i ymax = _mm256_max_epi32(_mm256_max_epi32(y[0], y[1]), y[2]);
    const __m256i i0 =
        _mm256_sub_epi32(zero, _mm256_sra_epi32(_mm256_sub_epi32(half, xmin), shift));
    const __m256i i1 = _mm256_sra_epi32(_mm256_sub_epi32(xmax, half), shift);
    const __m256i j0 =
        _mm256_sub_epi32(zero, _mm256_sra_epi32(_mm256_sub_epi32(half, ymin), shift));
    const __m256i j1 = _mm256_sra_epi32(_mm256_sub_epi32(ymax, half), shift);
    // area2 = (x1 - x0)(y2 - y0) - (y1 - y0)(x2 - x0), exact in 64 bits.
    const __m512i area2 =
        _mm512_sub_epi64(_mm512_mul_epi32(_mm512_cvtepi32_epi64(_mm256_sub_epi32(x[1], x[0])),
                                          _mm512_cvtepi32_epi64(_mm256_sub_epi32(y[2], y[0]))),
                         _mm512_mul_epi32(_mm512_cvtepi32_epi64(_mm256_sub_epi32(y[1], y[0])),
                                          _mm512_cvtepi32_epi64(_mm256_sub_epi32(x[2], x[0]))));
    const __mmask8 positive = _mm512_cmpgt_epi64_mask(area2, _mm512_setzero_si512());
    const __mmask8 flip = _mm512_cmplt_epi64_mask(area2, _mm512_setzero_si512());
    const __mmask8 covers = static_cast<__mmask8>(
        (positive | flip) & ~_mm256_cmpgt_epi32_mask(i0, i1) & ~_mm256_cmpgt_epi32_mask(j0, j1));
    _mm256_mask_storeu_epi32(row0 + t, live,
                             _mm256_mask_blend_epi32(covers, _mm256_set1_epi32(-1), j0));
    tall = _mm256_mask_max_epi32(tall, covers & live, tall,
                                 _mm256_add_epi32(_mm256_sub_epi32(j1, j0), one));
    // Counter-clockwise corners: 1 and 2 swapped where the input order is clockwise.
    const __m256i cx[3] = {x[0], _mm256_mask_blend_epi32(flip, x[1], x[2]),
                           _mm256_mask_blend_epi32(flip, x[2], x[1])};
    const __m256i cy[3] = {y[0], _mm256_mask_blend_epi32(flip, y[1], y[2]),
                           _mm256_mask_blend_epi32(flip, y[2], y[1])};
    const __mmask8 bottom = orientation > 0 ? flip : positive;
    const __m256i chunks =
        _mm256_min_epi32(_mm256_set1_epi32(2),
                         _mm256_srli_epi32(_mm256_max_epi32(zero, _mm256_sub_epi32(i1, i0)), 3));
    __m256i f = _mm256_or_si256(_mm256_maskz_mov_epi32(bottom, _mm256_set1_epi32(8)),
                                _mm256_maskz_mov_epi32(flip, _mm256_set1_epi32(16)));
    f = _mm256_or_si256(f, _mm256_slli_epi32(chunks, 5));
    for (int k = 0; k < 3; ++k) {
      const int p = k == 2 ? 0 : k + 1, q = k == 0 ? 2 : k - 1;
      const __m256i dx = _mm256_sub_epi32(cx[q], cx[p]), dy = _mm256_sub_epi32(cy[q], cy[p]);
      // Top edge: horizontal, going left (interior below). Left edge: going down.
      const __mmask8 top_left =
          _mm256_cmpgt_epi32_mask(zero, dy) |
          (_mm256_cmpeq_epi32_mask(dy, zero) & _mm256_cmpgt_epi32_mask(zero, dx));
      f = _mm256_or_si256(
          f, _mm256_maskz_mov_epi32(static_cast<__mmask8>(~top_left), _mm256_set1_epi32(1 << k)));
    }
    _mm256_mask_storeu_epi32(flags + t, live, f);
  }
  volume6 = _mm512_reduce_add_pd(sum);
  alignas(32) int lanes_tall[kChunk];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes_tall), tall);
  return *std::max_element(lanes_tall, lanes_tall + kChunk);
}

// Step 2 set-ups of up to 8 triangles (the raster of each, as FastColumn's start() finds it)
// computed together: `triangle` points to 16-byte records (three counter-clockwise vertices and
// flags), `vertex` to 16-byte snapped vertices (x, y, then the height as a double).
struct SetupBatch {
  alignas(64) int64_t e[3][kChunk], di[3][kChunk], dj[3][kChunk];
  alignas(64) double z[kChunk], dzi[kChunk], dzj[kChunk];
  alignas(32) int i0[kChunk], i1[kChunk], j1[kChunk], flags[kChunk];
};

FW_AVX512 inline void setup_avx512(const int* triangle, int lanes, const int* vertex, int j, int s,
                                   int n, SetupBatch& b) {
  const __m256i zero = _mm256_setzero_si256();
  const __m128i shift = _mm_cvtsi32_si128(s);
  // Records loaded whole and transposed (a gather per field cost more): the lanes past
  // `lanes` read vertex 0, and their results are never read.
  alignas(64) int padded[4 * kChunk];
  if (lanes < kChunk) {
    for (int u = 0; u < 4 * kChunk; ++u) padded[u] = u < 4 * lanes ? triangle[u] : 0;
    triangle = padded;
  }
  const __m512i t0 = _mm512_loadu_si512(triangle), t1 = _mm512_loadu_si512(triangle + 16);
  const __m512i fields = _mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 0, 0, 0, 0, 0, 0, 0, 0);
  const __m256i flags = _mm512_castsi512_si256(
      _mm512_permutex2var_epi32(t0, _mm512_add_epi32(fields, _mm512_set1_epi32(3)), t1));
  __m256i x[3], y[3];
  __m512d z[3];
  for (int k = 0; k < 3; ++k) {
    auto record = [&](int u) {
      return _mm_loadu_si128(reinterpret_cast<const __m128i*>(vertex + 4 * triangle[4 * u + k]));
    };
    __m512i half_records[2];  // (x y, z) of lanes 0-3 and 4-7
    for (int h = 0; h < 2; ++h) {
      __m512i r = _mm512_castsi128_si512(record(4 * h));
      r = _mm512_inserti32x4(r, record(4 * h + 1), 1);
      r = _mm512_inserti32x4(r, record(4 * h + 2), 2);
      half_records[h] = _mm512_inserti32x4(r, record(4 * h + 3), 3);
    }
    const __m512i xy = _mm512_permutex2var_epi64(
        half_records[0], _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14), half_records[1]);
    x[k] = _mm512_cvtepi64_epi32(xy);
    y[k] = _mm512_cvtepi64_epi32(_mm512_srli_epi64(xy, 32));
    z[k] = _mm512_castsi512_pd(_mm512_permutex2var_epi64(
        half_records[0], _mm512_setr_epi64(1, 3, 5, 7, 9, 11, 13, 15), half_records[1]));
  }
  const __m256i half = _mm256_set1_epi32(1 << (s - 1));
  const __m256i xmin = _mm256_min_epi32(_mm256_min_epi32(x[0], x[1]), x[2]);
  const __m256i xmax = _mm256_max_epi32(_mm256_max_epi32(x[0], x[1]), x[2]);
  const __m256i ymax = _mm256_max_epi32(_mm256_max_epi32(y[0], y[1]), y[2]);
  const __m256i last = _mm256_set1_epi32(n - 1);
  const __m256i i0 = _mm256_max_epi32(
      zero, _mm256_sub_epi32(zero, _mm256_sra_epi32(_mm256_sub_epi32(half, xmin), shift)));
  _mm256_store_si256(reinterpret_cast<__m256i*>(b.i0), i0);
  _mm256_store_si256(reinterpret_cast<__m256i*>(b.i1),
                     _mm256_min_epi32(last, _mm256_sra_epi32(_mm256_sub_epi32(xmax, half), shift)));
  _mm256_store_si256(reinterpret_cast<__m256i*>(b.j1),
                     _mm256_min_epi32(last, _mm256_sra_epi32(_mm256_sub_epi32(ymax, half), shift)));
  _mm256_store_si256(reinterpret_cast<__m256i*>(b.flags), flags);
  const __m256i px = _mm256_add_epi32(_mm256_sll_epi32(i0, shift), half);
  const __m256i py = _mm256_set1_epi32((j << s) + (1 << (s - 1)));
  __m512i area2 = _mm512_setzero_si512();
  __m512d z0 = _mm512_setzero_pd(), dzi = _mm512_setzero_pd(), dzj = _mm512_setzero_pd();
  for (int k = 0; k < 3; ++k) {  // edge k goes from corner k + 1 to corner k + 2
    const int p = k == 2 ? 0 : k + 1, q = k == 0 ? 2 : k - 1;
    const __m512i dx = _mm512_cvtepi32_epi64(_mm256_sub_epi32(x[q], x[p]));
    const __m512i dy = _mm512_cvtepi32_epi64(_mm256_sub_epi32(y[q], y[p]));
    const __m512i e =
        _mm512_sub_epi64(_mm512_mul_epi32(dx, _mm512_cvtepi32_epi64(_mm256_sub_epi32(py, y[p]))),
                         _mm512_mul_epi32(dy, _mm512_cvtepi32_epi64(_mm256_sub_epi32(px, x[p]))));
    const __m512i fold =
        _mm512_cvtepi32_epi64(_mm256_and_si256(_mm256_srli_epi32(flags, k), _mm256_set1_epi32(1)));
    const __m512i di = _mm512_sub_epi64(_mm512_setzero_si512(), _mm512_sll_epi64(dy, shift));
    const __m512i dj = _mm512_sll_epi64(dx, shift);
    _mm512_store_si512(b.e[k], _mm512_sub_epi64(e, fold));
    _mm512_store_si512(b.di[k], di);
    _mm512_store_si512(b.dj[k], dj);
    area2 = _mm512_add_epi64(area2, e);
    z0 = _mm512_add_pd(z0, _mm512_mul_pd(_mm512_cvtepi64_pd(e), z[k]));
    dzi = _mm512_add_pd(dzi, _mm512_mul_pd(_mm512_cvtepi64_pd(di), z[k]));
    dzj = _mm512_add_pd(dzj, _mm512_mul_pd(_mm512_cvtepi64_pd(dj), z[k]));
  }
  // Lanes past `lanes` divide by zero: never read.
  const __m512d inv = _mm512_div_pd(_mm512_set1_pd(1.0), _mm512_cvtepi64_pd(area2));
  _mm512_store_pd(b.z, _mm512_mul_pd(z0, inv));
  _mm512_store_pd(b.dzi, _mm512_mul_pd(dzi, inv));
  _mm512_store_pd(b.dzj, _mm512_mul_pd(dzj, inv));
}

// Boxes of up to kNarrow chunks: their chunks' edge functions and heights are kept in
// registers and stepped from row to row, so that a row costs little more than its writes.
// `p` gives the triangle's fields (a Raster, or a lane of a SetupBatch: no copy to a Raster).
template <bool kFloor, int kNarrow, class Fields>
FW_AVX512 inline void narrow_rows(const Fields& p, int rows, RowRing& ring) {
  constexpr int kind = kFloor ? 0 : 1;
  const size_t w = ring.width;
  const int mask_rows = ring.rows - 1;
  const __m512i iota = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
  __m512i v[kNarrow][3];
  __m512i step[3];
  for (int k = 0; k < 3; ++k) {
    step[k] = _mm512_set1_epi64(p.dj(k));
    v[0][k] = _mm512_add_epi64(_mm512_set1_epi64(p.e(k)),
                               _mm512_mullo_epi64(_mm512_set1_epi64(p.di(k)), iota));
    for (int c = 1; c < kNarrow; ++c) {
      v[c][k] = _mm512_add_epi64(v[c - 1][k], _mm512_set1_epi64(kChunk * p.di(k)));
    }
  }
  __m512d zv[kNarrow];
  zv[0] =
      _mm512_add_pd(_mm512_set1_pd(p.z()),
                    _mm512_mul_pd(_mm512_set1_pd(p.dzi()), _mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7)));
  for (int c = 1; c < kNarrow; ++c) {
    zv[c] = _mm512_add_pd(zv[0], _mm512_set1_pd(p.dzi() * (kChunk * c)));
  }
  const __m512d zstep = _mm512_set1_pd(p.dzj());
  const int i0 = p.i0(), floor = p.floor();
  const __m256i floor_index = _mm256_set1_epi32(floor);
  uint8_t* const count = ring.count[kind].data() + i0;
  double* const zs = ring.z[kind].data() + i0;
  int* const fl = ring.floor.data() + i0;
  int row = p.row();
  for (int q = 0; q < rows; ++q, ++row) {
    const int slot = row & mask_rows;
    const SlotView sv{count + slot * w, zs + slot * kPlanes * w, fl + slot * kPlanes * w};
    for (int c = 0; c < kNarrow; ++c) {
      const __mmask8 m = static_cast<__mmask8>(
          ~_mm512_movepi64_mask(_mm512_or_si512(_mm512_or_si512(v[c][0], v[c][1]), v[c][2])));
      write_chunk<kFloor>(sv, w, kChunk * c, m, zv[c], floor_index, ring.spill[kind][slot], floor,
                          i0);
      for (int k = 0; k < 3; ++k) v[c][k] = _mm512_add_epi64(v[c][k], step[k]);
      zv[c] = _mm512_add_pd(zv[c], zstep);
    }
  }
}

struct RasterFields {
  const Raster& r;
  int64_t e(int k) const { return r.e[k]; }
  int64_t di(int k) const { return r.di[k]; }
  int64_t dj(int k) const { return r.dj[k]; }
  double z() const { return r.z; }
  double dzi() const { return r.dzi; }
  double dzj() const { return r.dzj; }
  int i0() const { return r.i0; }
  int row() const { return r.row; }
  int floor() const { return r.floor; }
};

struct LaneFields {
  const SetupBatch& b;
  int u, first_row, floor_record;
  int64_t e(int k) const { return b.e[k][u]; }
  int64_t di(int k) const { return b.di[k][u]; }
  int64_t dj(int k) const { return b.dj[k][u]; }
  double z() const { return b.z[u]; }
  double dzi() const { return b.dzi[u]; }
  double dzj() const { return b.dzj[u]; }
  int i0() const { return b.i0[u]; }
  int row() const { return first_row; }
  int floor() const { return floor_record; }
};

template <bool kFloor, int kNarrow>
FW_AVX512 void raster_avx512_narrow(Raster& r, int rows, RowRing& ring) {
  narrow_rows<kFloor, kNarrow>(RasterFields{r}, rows, ring);
  for (int k = 0; k < 3; ++k) r.e[k] += r.dj[k] * rows;
  r.z += r.dzj * rows;
  r.row += rows;
}

template <bool kFloor, int kNarrow>
FW_AVX512 void raster_lane_narrow(const SetupBatch& b, int u, int row, int floor, int rows,
                                  RowRing& ring) {
  narrow_rows<kFloor, kNarrow>(LaneFields{b, u, row, floor}, rows, ring);
}

// Rows [row, row + rows) of lane u of a set-up batch, a box of at most two chunks (floor: its
// record, or -1), straight from the batch: the triangles of a row are set up 8 at a time and
// most are rasterized whole at once, so copying each to a Raster first cost more than the
// rare ones going on later need.
FW_AVX512 inline void raster_lane_avx512(const SetupBatch& b, int u, int row, int floor, int rows,
                                         RowRing& ring) {
  const bool one = b.i1[u] - b.i0[u] < kChunk;
  if (floor >= 0) {
    if (one) return raster_lane_narrow<true, 1>(b, u, row, floor, rows, ring);
    return raster_lane_narrow<true, 2>(b, u, row, floor, rows, ring);
  }
  if (one) return raster_lane_narrow<false, 1>(b, u, row, floor, rows, ring);
  raster_lane_narrow<false, 2>(b, u, row, floor, rows, ring);
}

FW_AVX512 inline void raster_avx512(Raster& r, int rows, RowRing& ring) {
  const int chunks = (r.i1 - r.i0) / kChunk + 1;
  if (r.floor >= 0) {
    if (chunks == 1) return raster_avx512_narrow<true, 1>(r, rows, ring);
    if (chunks == 2) return raster_avx512_narrow<true, 2>(r, rows, ring);
    raster_avx512_kind<true>(r, rows, ring);
  } else {
    if (chunks == 1) return raster_avx512_narrow<false, 1>(r, rows, ring);
    if (chunks == 2) return raster_avx512_narrow<false, 2>(r, rows, ring);
    raster_avx512_kind<false>(r, rows, ring);
  }
}

// Sections of one plane of a chunk (lanes in `m`) added to their floors. When they all share
// one floor (wide triangles) the chunk is summed in registers; otherwise each lane's (h, h i,
// h j) is laid out as a 32-byte record and added to its floor's in one load, add and store.
FW_AVX512 inline void add_sections(__mmask8 m, __m512d h, __m256i floor, int col, int j,
                                   FloorMoments* moments, __m512d& sum) {
  sum = _mm512_mask_add_pd(sum, m, sum, h);
  const int leader =
      _mm256_extract_epi32(_mm256_permutexvar_epi32(_mm256_set1_epi32(lowest_bit(m)), floor), 0);
  const __m512d hk = _mm512_maskz_mov_pd(m, h);
  const __m512d hi =
      _mm512_mul_pd(hk, _mm512_add_pd(_mm512_setr_pd(0, 1, 2, 3, 4, 5, 6, 7), _mm512_set1_pd(col)));
  if (_mm256_mask_cmpeq_epi32_mask(m, floor, _mm256_set1_epi32(leader)) == m) {
    // One 32-byte update as below: a scalar store into a record that a later 32-byte load
    // reads could not be forwarded.
    double* f = &moments[leader].m0;
    const double sh = _mm512_reduce_add_pd(hk);
    _mm256_store_pd(f, _mm256_add_pd(_mm256_load_pd(f),
                                     _mm256_setr_pd(sh, _mm512_reduce_add_pd(hi), sh * j, 0.0)));
    return;
  }
  const __m512d hj = _mm512_mul_pd(hk, _mm512_set1_pd(j));
  // (h, h i) of lanes 0-3 and 4-7 interleaved, then each lane's pair followed by h j twice.
  const __m512d lo = _mm512_permutex2var_pd(hk, _mm512_setr_epi64(0, 8, 1, 9, 2, 10, 3, 11), hi);
  const __m512d up = _mm512_permutex2var_pd(hk, _mm512_setr_epi64(4, 12, 5, 13, 6, 14, 7, 15), hi);
  alignas(64) double record[kChunk][4];
  _mm512_store_pd(record[0],
                  _mm512_permutex2var_pd(lo, _mm512_setr_epi64(0, 1, 8, 8, 2, 3, 9, 9), hj));
  _mm512_store_pd(record[2],
                  _mm512_permutex2var_pd(lo, _mm512_setr_epi64(4, 5, 10, 10, 6, 7, 11, 11), hj));
  _mm512_store_pd(record[4],
                  _mm512_permutex2var_pd(up, _mm512_setr_epi64(0, 1, 12, 12, 2, 3, 13, 13), hj));
  _mm512_store_pd(record[6],
                  _mm512_permutex2var_pd(up, _mm512_setr_epi64(4, 5, 14, 14, 6, 7, 15, 15), hj));
  // All eight lanes, those without a section into a record of their own: a loop of fixed
  // length, whose exit is predicted.
  alignas(32) double unused[4];
  alignas(64) double* to[kChunk];
  _mm512_store_si512(to,
                     _mm512_mask_add_epi64(_mm512_set1_epi64(reinterpret_cast<int64_t>(unused)), m,
                                           _mm512_set1_epi64(reinterpret_cast<int64_t>(moments)),
                                           _mm512_slli_epi64(_mm512_cvtepi32_epi64(floor), 5)));
  for (int u = 0; u < kChunk; ++u) {
    double* f = to[u];
    _mm256_store_pd(f, _mm256_add_pd(_mm256_load_pd(f), _mm256_load_pd(record[u])));
  }
}

// A compare-exchange of a sorting network on planes x < y of 8 columns: floor heights a with
// their records o, ceiling heights b.
FW_AVX512 inline void exchange(__m512d* a, __m512d* b, __m256i* o, int x, int y) {
  const __mmask8 k = _mm512_cmp_pd_mask(a[y], a[x], _CMP_LT_OQ);
  const __m512d ax = a[x];
  a[x] = _mm512_mask_blend_pd(k, a[x], a[y]);
  a[y] = _mm512_mask_blend_pd(k, a[y], ax);
  const __m256i ox = o[x];
  o[x] = _mm256_mask_blend_epi32(k, o[x], o[y]);
  o[y] = _mm256_mask_blend_epi32(k, o[y], ox);
  const __m512d bx = b[x];
  b[x] = _mm512_min_pd(b[x], b[y]);
  b[y] = _mm512_max_pd(b[y], bx);
}

FW_AVX512 inline void resolve_avx512(int j, RowRing& ring, FloorMoments* moments, ColumnScratch& s,
                                     RowTotals& totals) {
  // Every chunk of the row: testing the empty ones costs less than keeping the range of
  // columns with hits per row in the raster (two loads and stores a triangle-row).
  const int slot = j & (ring.rows - 1), lo = 0, hi = ring.width - kChunk - 1;
  sort_spill(ring, slot);
  const size_t w = ring.width;
  uint8_t *fc = ring.count[0].data() + slot * w, *cc = ring.count[1].data() + slot * w;
  const double* fz = ring.z[0].data() + slot * kPlanes * w;
  const double* cz = ring.z[1].data() + slot * kPlanes * w;
  const int* fl = ring.floor.data() + slot * kPlanes * w;
  const __m512d inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());
  __m512d sum = _mm512_setzero_pd();
  long long unmatched = 0;
  size_t at[2] = {0, 0};
  for (int col = lo & ~(kChunk - 1); col <= hi; col += kChunk) {
    const __m128i f = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(fc + col));
    const __m128i c = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(cc + col));
    const __m128i both = _mm_or_si128(f, c);
    if (!(_mm_cmpneq_epi8_mask(both, _mm_setzero_si128()) & 0xFFu)) continue;
    const unsigned many = _mm_cmpgt_epu8_mask(both, _mm_set1_epi8(1)) & 0xFFu;
    if (!many) {
      // At most one hit of each kind: one section where there are both.
      const __mmask8 m =
          static_cast<__mmask8>(_mm_cmpeq_epi8_mask(_mm_and_si128(f, c), _mm_set1_epi8(1)));
      const __m512d h = _mm512_sub_pd(_mm512_loadu_pd(cz + col), _mm512_loadu_pd(fz + col));
      add_sections(m, h, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(fl + col)), col, j,
                   moments, sum);
    } else if (!(_mm_cmpgt_epu8_mask(_mm_max_epu8(f, c), _mm_set1_epi8(kPlanes)) & 0xFFu)) {
      // Up to kPlanes of each: planes padded with infinite heights, sorted by a network.
      __m512d a[kPlanes], b[kPlanes];
      __m256i o[kPlanes];
      for (int p = 0; p < kPlanes; ++p) {
        const __mmask8 kf = static_cast<__mmask8>(_mm_cmpgt_epu8_mask(f, _mm_set1_epi8(p)));
        const __mmask8 kc = static_cast<__mmask8>(_mm_cmpgt_epu8_mask(c, _mm_set1_epi8(p)));
        a[p] = _mm512_mask_loadu_pd(inf, kf, fz + p * w + col);
        b[p] = _mm512_mask_loadu_pd(inf, kc, cz + p * w + col);
        o[p] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(fl + p * w + col));
      }
      exchange(a, b, o, 0, 1);
      exchange(a, b, o, 2, 3);
      exchange(a, b, o, 0, 2);
      exchange(a, b, o, 1, 3);
      exchange(a, b, o, 1, 2);
      const __m128i pairs = _mm_min_epu8(f, c);
      for (int p = 0; p < kPlanes; ++p) {
        const __mmask8 m = static_cast<__mmask8>(_mm_cmpgt_epu8_mask(pairs, _mm_set1_epi8(p)));
        if (m) add_sections(m, _mm512_sub_pd(b[p], a[p]), o[p], col, j, moments, sum);
      }
    } else {
      // Spilled hits: column by column.
      RowTotals t;
      for (int i = col; i < col + kChunk; ++i) {
        if (fc[i] | cc[i]) resolve_column(slot, i, j, ring, at, moments, s, t);
      }
      totals.sum_heights += t.sum_heights;
      totals.unmatched += t.unmatched;
      continue;  // resolve_column cleared the counts and counted unmatched columns itself
    }
    unmatched += _mm_popcnt_u32(_mm_cmpneq_epi8_mask(f, c) & 0xFFu);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(fc + col), _mm_setzero_si128());
    _mm_storel_epi64(reinterpret_cast<__m128i*>(cc + col), _mm_setzero_si128());
  }
  totals.sum_heights += _mm512_reduce_add_pd(sum);
  totals.unmatched += unmatched;
  ring.spill[0][slot].clear();
  ring.spill[1][slot].clear();
}
#if !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace fluidweight::detail::rows

#endif
